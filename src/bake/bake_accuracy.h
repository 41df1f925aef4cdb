/* The accuracy levels of a bake (nbrdf_bake_options.accuracy) before the
 * texels are computed: the plan that fits the budget (a deterministic cost
 * model), the scene's representative tuples (bake_select.h), their ground
 * truth (bake_truth.h), the fit (bake_fit.h) and its error on held-out
 * tuples. The bake then applies the correction to every tuple (bake_band.c's
 * `correct` hook).
 *
 * The budget is in seconds of the cost model, calibrated on one core of the
 * 2-core build machine unloaded (docs/BAKE.md, "Accuracy levels"): the same
 * inputs, options and seed give the same texture on any machine and at any
 * load; the wall time is about the budget over the cores free. */
#ifndef NBRDF_BAKE_BAKE_ACCURACY_H
#define NBRDF_BAKE_BAKE_ACCURACY_H

#include "bake/bake_compact.h"
#include "bake/bake_fit.h"
#include "bake/bake_select.h"
#include "bake/bake_truth.h"
#include "nbrdf/bake.h"
#include "texture/param_source.h"

typedef struct bake_plan {
  size_t n_fit, n_held;
  int incident;      /* fit samples' incident directions per tuple */
  int project_steps, joint_steps, rows_per_brdf;
  int distil_steps, distil_rows; /* COMPACT: the student's steps, rows per BRDF per step */
  double cost;       /* cost-model seconds of the plan */
} bake_plan;

/* The plan of `level` within `budget` seconds for `distinct` candidate
 * tuples; NBRDF_ERR_ARGUMENT saying what fits when the budget is too small.
 * COMPACT: student_macs is the small decoder's (else ignored). */
nbrdf_status bake_plan_make(nbrdf_bake_accuracy level, double budget, size_t distinct,
                            int64_t decoder_macs, int64_t student_macs, bake_plan *plan,
                            nbrdf_error *err);

/* The budget of o->accuracy (not FAST) with this model's decoder: o->budget or
 * the level's default; NBRDF_ERR_ARGUMENT when even the smallest plan does not
 * fit it. Needs no input: the smallest plan's cost does not depend on them. */
nbrdf_status bake_accuracy_check(const nbrdf_model *model, const nbrdf_bake_options *o,
                                 nbrdf_error *err);

/* The fit result: everything the plan/fit stage produces and the evaluate
 * stage consumes (bake_level.h), and nothing else: no state of the band loop,
 * so a fit is made once and baked from later (nbrdf/fit.h, bake_fit_file.h). */
typedef struct bake_fit_result {
  bake_correction correction; /* the latent correction carried to every tuple; SPECIALISED
                               * and COMPACT: with the fine-tuned decoder */
  bake_compact compact;       /* COMPACT: the basis and the student (else zero) */
  size_t distinct, fitted, heldout;
  double heldout_error, heldout_error_fast;
  /* The energy guard (bake_energy_check.h) over the fitted and held-out tuples: the largest
   * decoded directional albedo with the level's decoder and with fast's, and how many tuples
   * (0: not measured, a fit file from before the guard; no energy verdict then). */
  double albedo_max, albedo_max_fast;
  size_t albedo_tuples;
  nbrdf_bake_accuracy level; /* the level fitted (FAST: nothing fitted) */
  double budget;
  char attribute[512]; /* NBRDF_ATTR_ACCURACY */
} bake_fit_result;

/* The plan/fit stage of level o->accuracy (not FAST) over n_scenes scenes
 * (the tiles of a set, whose distinct tuples are gathered together; one
 * scene: a texture's own fit): everything before the texels (plan,
 * selection, ground truth, fit, COMPACT's distillation, held-out error);
 * progress stages "ground truth" and "fit" through `ticker`. */
nbrdf_status bake_accuracy_fit(const nbrdf_model *model, const bake_scene *scenes, size_t n_scenes,
                               const nbrdf_bake_options *o, core_ticker *ticker, bake_fit_result *r,
                               nbrdf_error *err);
void bake_fit_result_free(bake_fit_result *r);

/* The fit's figures in the bake report: budget, distinct, fitted and held-out tuples, the
 * held-out medians of the level and of fast. */
void bake_fit_result_report(const bake_fit_result *r, nbrdf_bake_report *rep);

/* How far a level's held-out median may exceed fast's on the same tuples before the level
 * counts as worse than fast (a fraction: 0.25 percentage points). Both are medians against
 * the same ground truth, so its noise largely cancels; what is left is the decoders'. */
#define BAKE_FALLBACK_MARGIN 0.0025

/* Non-zero when the fit's held-out error is worse than the fast level's beyond the margin,
 * or when its decoder creates energy on the tuples it was checked on (bake_fit_creates_energy):
 * the bake then falls back to fast and auto never chooses it (docs/BAKE.md, "Held-out
 * check"). */
int bake_fit_worse_than_fast(const bake_fit_result *r);
/* Non-zero when the energy guard measured the fit and its largest decoded albedo exceeds
 * bake_energy_limit of fast's (bake_energy_check.h). */
int bake_fit_creates_energy(const bake_fit_result *r);
/* Why a fit is worse than fast, for a warning: "the LEVEL texture's held-out lobe error
 * (...) is worse than..." and/or "its decoder creates energy: ...", naming the figures. */
void bake_fit_worse_message(const bake_fit_result *r, nbrdf_bake_accuracy level, char *buf,
                            size_t cap);
/* The energy part of it alone: "the LEVEL decoder creates energy: ... 805.000, above ...". */
void bake_fit_energy_message(const bake_fit_result *r, nbrdf_bake_accuracy level, char *buf,
                             size_t cap);

/* The fine-tune's energy weight of o->fit_energy: 0 gives the default, < 0 off (0). */
float bake_fit_energy_weight(const nbrdf_bake_options *o);

/* o->budget, or the default of o->accuracy. */
double bake_accuracy_budget(const nbrdf_bake_options *o);

/* The fast level's held-out median (*fast) on the tuples the fitted level at this budget
 * would hold out (the same truth), their number and the scenes' distinct tuples: what AUTO
 * measures first. */
nbrdf_status bake_accuracy_fast_error(const nbrdf_model *model, const bake_scene *scenes,
                                      size_t n_scenes, const nbrdf_bake_options *o,
                                      core_ticker *ticker, double *fast, size_t *heldout,
                                      size_t *distinct, nbrdf_error *err);

/* The budget that would likely bring `level`'s held-out error from `error` (measured at
 * `budget`) to `target`: a guess from the cost model's plan (0 when the plan no longer
 * grows with the budget, so more of it is unlikely to help). */
double bake_accuracy_budget_for(const nbrdf_model *model, nbrdf_bake_accuracy level,
                                double budget, size_t distinct, double error, double target);

#endif
