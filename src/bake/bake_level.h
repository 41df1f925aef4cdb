/* Each accuracy level's stages of a bake (docs/BAKE.md, "Accuracy levels").
 * nbrdf_bake runs the same sequence for every level:
 *
 *   sources -> plan/fit -> per-band evaluate -> write -> audit
 *
 * and a level supplies what differs: its plan/fit stage (nothing for FAST;
 * bake_accuracy_fit otherwise), which produces the fit result
 * (bake_fit_result); the evaluate stage's setup from that result (the model
 * the latents are computed with, the correction added to them, the layout
 * the texture stores and how band texels and mip rows become it); and what
 * the audit stage adds to the warnings and the report. The evaluate stage
 * reads the fit result only, so a fit is made once and baked from later
 * (nbrdf/fit.h: nbrdf_bake then takes it from options.fit and skips the
 * plan/fit stage). */
#ifndef NBRDF_BAKE_BAKE_LEVEL_H
#define NBRDF_BAKE_BAKE_LEVEL_H

#include <stddef.h>

#include "bake/bake_accuracy.h"
#include "core/progress.h"
#include "nbrdf/bake.h"
#include "texture/latent_layout.h"

/* The evaluate stage as a level sets it up from its fit result. */
typedef struct bake_evaluate {
  /* Computes every tuple's latent and proxy: the bundle's, or the one whose
   * decoder is the fine-tuned copy (SPECIALISED, COMPACT: the texture's
   * proxies then come from that decoder's latents). */
  const nbrdf_model *model;
  /* The decoder the texture carries and the energy audit decodes with
   * (COMPACT: the student); else `model`. */
  const nbrdf_model *stored_model;
  const bake_correction *correct; /* added to every latent; NULL: FAST */
  const bake_compact *compact;    /* COMPACT: the audit decodes its coordinates */
  texture_latent_layout work;     /* the band's texels (the bundle's latents) */
  texture_latent_layout stored;   /* the texture's */
  /* n band texels (work layout) to stored texels; in == out where the level
   * stores the work texels (then a no-op). */
  void (*store)(const struct bake_evaluate *e, const float *in, float *out, size_t n);
  /* The proxy of a mip row of averaged stored texels (texture_latent_exr_options.mip_row,
   * user: this struct). */
  nbrdf_status (*mip_row)(void *user, int level, int y, float *row, int width, nbrdf_error *err);
  int stores_work; /* band texels are the stored texels (no second buffer) */
  float *work_row; /* mip_row's scratch: a row of work texels (COMPACT) */
  nbrdf_model *owned[2];
} bake_evaluate;

typedef struct bake_level {
  nbrdf_bake_accuracy accuracy;
  /* The plan/fit stage: everything before the texels and before any file exists. */
  nbrdf_status (*fit)(const nbrdf_model *model, const bake_scene *scenes, size_t n_scenes,
                      const nbrdf_bake_options *o, core_ticker *ticker, bake_fit_result *r,
                      nbrdf_error *err);
  /* The evaluate stage of `model` and the fit result `r` for textures `width`
   * texels wide whose band texels have layout `work`. */
  nbrdf_status (*evaluate_open)(const nbrdf_model *model, const bake_fit_result *r,
                                const texture_latent_layout *work, int width, bake_evaluate *e,
                                nbrdf_error *err);
  /* The audit stage's part of the level after the texture is written: its
   * warnings (o->warning) and its fields of the report (may be NULL). */
  void (*audit)(const nbrdf_bake_options *o, const bake_fit_result *r, const bake_evaluate *e,
                nbrdf_bake_report *rep);
} bake_level;

/* The stages of level `a` (checked by nbrdf_bake_options_check). */
const bake_level *bake_level_of(nbrdf_bake_accuracy a);

void bake_evaluate_close(bake_evaluate *e);

#endif
