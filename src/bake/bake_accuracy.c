#include "bake/bake_accuracy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_audit.h"
#include "bake/bake_energy_check.h"
#include "bake/bake_heldout.h"
#include "bake/bake_range.h"
#include "bake/bake_select.h"
#include "core/error.h"

/* ---- the cost model (cost-model seconds; docs/BAKE.md, "Accuracy levels") ----
 * Calibrated in CPU-seconds on the 2-core build machine (2026-11-25, release
 * build, OPENBLAS_NUM_THREADS=1): 39 tuples x 8 incident directions of fit
 * samples took 16.4 CPU-s, 12 held-out tuples' lobe images 3.5 CPU-s, and
 * 130 projection steps of 39 tuples x 128 rows 1.3 CPU-s (2.0 us a row with
 * the default 27 k-MAC decoder). */
#define COST_INCIDENT 0.055 /* s per incident direction of one tuple's fit samples */
#define COST_LOBE 0.45      /* s per held-out tuple's six lobe images (0.3 for the first four) */
#define MAC_RATE 3.4e10     /* decoder multiply-add passes per second in a fit */
#define PROJECT_PASSES 2.5  /* forward + backward to the inputs */
#define JOINT_PASSES 3.5    /* ... and to the weights */
#define MIN_STEPS 100
#define MAX_STEPS 1000 /* projection steps */
#define MAX_JOINT 8000 /* joint steps */
#define TRUTH_SHARE 0.7  /* of the budget after the held-out set: the carry needs tuples */
#define MIN_INCIDENT 8
#define MAX_INCIDENT 32
#define MAX_FIT 1024
#define MAX_HELD 16

/* COMPACT: the share of the budget the student's distillation gets, and
 * its cost per row drawn (a small network is bound by per-row work, not
 * multiply-adds). */
#define DISTIL_SHARE 0.3
#define DISTIL_ROWS 16
#define DISTIL_BATCH 16384
#define DISTIL_ROW_COST 2.0e-7
#define SMALL_MAC_RATE 1.0e10
#define MIN_DISTIL 300
#define MAX_DISTIL 30000 /* 6,000 steps: 11.8 %, 30,000: 6.0 % at lr 2e-3 on a constant */

#define OUTGOING 128
#define SAMPLED 64
#define SPP 2048
#define LOBE_RES 32
#define LOBE_WALKS 512

static int lobe_worse(const bake_fit_result *r) {
  return r->heldout > 0 && r->heldout_error > r->heldout_error_fast + BAKE_FALLBACK_MARGIN;
}

int bake_fit_creates_energy(const bake_fit_result *r) {
  return r->albedo_tuples > 0 && bake_energy_creates(r->albedo_max, r->albedo_max_fast);
}

int bake_fit_worse_than_fast(const bake_fit_result *r) {
  return lobe_worse(r) || bake_fit_creates_energy(r);
}

void bake_fit_worse_message(const bake_fit_result *r, nbrdf_bake_accuracy level, char *buf,
                            size_t cap) {
  buf[0] = '\0';
  const char *name = nbrdf_bake_accuracy_name(level);
  size_t len = 0;
  if (lobe_worse(r))
    len = (size_t)snprintf(buf, cap,
                           "the %s texture's held-out lobe error (%.2f %%) is worse than the "
                           "fast level's (%.2f %%) on the same %zu tuples (θi up to 89°, "
                           "off-plane azimuths)",
                           name, 100.0 * r->heldout_error, 100.0 * r->heldout_error_fast,
                           r->heldout);
  if (len < cap && bake_fit_creates_energy(r)) {
    if (len) len += (size_t)snprintf(buf + len, cap - len, "; ");
    if (len < cap) bake_fit_energy_message(r, level, buf + len, cap - len);
  }
}

void bake_fit_energy_message(const bake_fit_result *r, nbrdf_bake_accuracy level, char *buf,
                             size_t cap) {
  snprintf(buf, cap,
           "the %s decoder creates energy: its largest decoded directional albedo over the %zu "
           "fitted and held-out tuples is %.3f, above the limit %.3f (max of the audit's %.2f "
           "and fast's %.3f + %.2f on the same tuples)",
           nbrdf_bake_accuracy_name(level), r->albedo_tuples, r->albedo_max,
           bake_energy_limit(r->albedo_max_fast), BAKE_AUDIT_LIMIT, r->albedo_max_fast,
           BAKE_ENERGY_MARGIN);
}

static double step_cost(size_t n_fit, int rows, int64_t macs, double passes) {
  return (double)n_fit * rows * (double)macs * passes / MAC_RATE;
}

/* The joint fine-tune's energy term (bake_fit.h): its rows per penalised tuple, the audit's
 * rule at its six angles, forward and backward like the data term's. Charged whether or not
 * it is on (it is by default): a plan does not depend on the option. */
#define ENERGY_ROWS (BAKE_AUDIT_N_THETA * (BAKE_FIT_ENERGY_RINGS * BAKE_AUDIT_POLAR_PHI + 1))

static double joint_cost(size_t n_fit, int rows, int64_t macs) {
  size_t k = n_fit < BAKE_FIT_ENERGY_BRDFS ? n_fit : BAKE_FIT_ENERGY_BRDFS;
  return step_cost(n_fit, rows, macs, JOINT_PASSES) +
         step_cost(k, ENERGY_ROWS, macs, JOINT_PASSES) / BAKE_FIT_ENERGY_EVERY;
}

static int rows_for(size_t n_fit) { return n_fit <= 32 ? 256 : 128; }

/* The fit's plan within `budget`; `share` is the part of the user's budget
 * it is (the messages speak of the user's). */
static nbrdf_status plan_fit(nbrdf_bake_accuracy level, double share, double budget,
                             size_t distinct, int64_t macs, bake_plan *p, nbrdf_error *err) {
  memset(p, 0, sizeof *p);
  const int joint = level >= NBRDF_BAKE_SPECIALISED;
  const double per_step = step_cost(1, 256, macs, PROJECT_PASSES) +
                          (joint ? 3.0 * joint_cost(1, 256, macs) : 0.0);
  const double min_cost = COST_LOBE + MIN_INCIDENT * COST_INCIDENT + MIN_STEPS * per_step;
  if (!(budget >= min_cost)) {
    char also[128] = "";
    double fitted_min = COST_LOBE + MIN_INCIDENT * COST_INCIDENT +
                        MIN_STEPS * step_cost(1, 256, macs, PROJECT_PASSES);
    if (joint && budget >= fitted_min)
      snprintf(also, sizeof also, "; within %g s 'fitted' fits", budget / share);
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                      "a budget of %g s is too small for '%s': its smallest plan (1 tuple "
                      "fitted, 1 held out, %d fit steps) costs %.1f s; give a budget of %.0f s "
                      "or more, or use 'fast'%s",
                      budget / share, nbrdf_bake_accuracy_name(level), MIN_STEPS,
                      min_cost / share, ceil(min_cost / share), also);
  }
  if (distinct == 0) distinct = 1;
  p->n_held = (size_t)(0.12 * budget / COST_LOBE);
  if (p->n_held < 1) p->n_held = 1;
  if (p->n_held > MAX_HELD) p->n_held = MAX_HELD;
  double rest = budget - p->n_held * COST_LOBE;
  /* Most of the rest to the ground truth (measured: the fit converges in a
   * few hundred steps, while the error between fitted tuples falls only with
   * more of them); few tuples get more incident directions (a constant bake
   * fits its one BRDF from 32), many get 8. */
  double truth = TRUTH_SHARE * rest;
  double k = truth / ((double)distinct * COST_INCIDENT);
  p->incident = k >= MAX_INCIDENT ? MAX_INCIDENT : k <= MIN_INCIDENT ? MIN_INCIDENT : (int)k;
  size_t n_fit = (size_t)(truth / (p->incident * COST_INCIDENT));
  if (n_fit > distinct) n_fit = distinct;
  if (n_fit > MAX_FIT) n_fit = MAX_FIT;
  if (n_fit < 1) n_fit = 1;
  for (;; n_fit = n_fit * 3 / 4 > 0 ? n_fit * 3 / 4 : 1) {
    int rows = rows_for(n_fit);
    double left = rest - n_fit * p->incident * COST_INCIDENT;
    double one = step_cost(n_fit, rows, macs, PROJECT_PASSES) +
                 (joint ? 3.0 * joint_cost(n_fit, rows, macs) : 0.0);
    double steps = left / one; /* projection steps; joint: three times as many joint steps */
    if (steps >= MIN_STEPS || n_fit == 1) {
      if (steps > MAX_STEPS) steps = MAX_STEPS;
      if (steps < MIN_STEPS) steps = MIN_STEPS;
      p->n_fit = n_fit;
      p->rows_per_brdf = rows;
      p->project_steps = (int)steps;
      if (joint) {
        /* What the projection leaves goes to the joint fit, up to MAX_JOINT
         * steps (a scene of few tuples affords many: the fit keeps improving). */
        double js = (left - steps * step_cost(n_fit, rows, macs, PROJECT_PASSES)) /
                    joint_cost(n_fit, rows, macs);
        p->joint_steps = js > MAX_JOINT ? MAX_JOINT : js < 3 * MIN_STEPS ? 3 * MIN_STEPS : (int)js;
      }
      p->cost = p->n_held * COST_LOBE + n_fit * p->incident * COST_INCIDENT +
                p->project_steps * step_cost(n_fit, rows, macs, PROJECT_PASSES) +
                p->joint_steps * joint_cost(n_fit, rows, macs);
      return NBRDF_OK;
    }
  }
}

nbrdf_status bake_plan_make(nbrdf_bake_accuracy level, double budget, size_t distinct,
                            int64_t macs, int64_t student_macs, bake_plan *p, nbrdf_error *err) {
  if (level != NBRDF_BAKE_COMPACT) return plan_fit(level, 1.0, budget, distinct, macs, p, err);
  nbrdf_status st =
      plan_fit(level, 1.0 - DISTIL_SHARE, budget * (1.0 - DISTIL_SHARE), distinct, macs, p, err);
  if (st != NBRDF_OK) return st;
  /* The student sees the fitted tuples and up to BAKE_COMPACT_TEACHER more. */
  size_t n = p->n_fit + (distinct < BAKE_COMPACT_TEACHER ? distinct : BAKE_COMPACT_TEACHER);
  /* Small scenes draw more rows of each BRDF per step (one constant: 1,024). */
  size_t rows = DISTIL_BATCH / n;
  p->distil_rows = rows < DISTIL_ROWS ? DISTIL_ROWS : rows > 1024 ? 1024 : (int)rows;
  double per = (double)n * p->distil_rows *
               (DISTIL_ROW_COST + (double)student_macs * JOINT_PASSES / SMALL_MAC_RATE);
  double steps = budget * DISTIL_SHARE / per;
  p->distil_steps = steps > MAX_DISTIL ? MAX_DISTIL : steps < MIN_DISTIL ? MIN_DISTIL : (int)steps;
  p->cost += p->distil_steps * per;
  return NBRDF_OK;
}

void bake_fit_result_free(bake_fit_result *r) {
  bake_correction_free(&r->correction);
  bake_compact_free(&r->compact);
  memset(r, 0, sizeof *r);
}

void bake_fit_result_report(const bake_fit_result *r, nbrdf_bake_report *rep) {
  rep->budget = r->budget;
  rep->distinct = r->distinct;
  rep->fitted_tuples = r->fitted;
  rep->heldout_tuples = r->heldout;
  rep->heldout_error = r->heldout_error;
  rep->heldout_error_fast = r->heldout_error_fast;
  rep->fit_albedo_tuples = r->albedo_tuples;
  rep->fit_max_albedo = r->albedo_max;
  rep->fit_max_albedo_fast = r->albedo_max_fast;
  rep->creates_energy = bake_fit_creates_energy(r);
}

float bake_fit_energy_weight(const nbrdf_bake_options *o) {
  return o->fit_energy < 0.0 ? 0.0f
         : o->fit_energy > 0.0 ? (float)o->fit_energy
                               : (float)NBRDF_BAKE_FIT_ENERGY_DEFAULT;
}

double bake_accuracy_budget(const nbrdf_bake_options *o) {
  return o->budget > 0.0                         ? o->budget
         : o->accuracy == NBRDF_BAKE_COMPACT     ? NBRDF_BAKE_BUDGET_COMPACT
         : o->accuracy == NBRDF_BAKE_SPECIALISED ? NBRDF_BAKE_BUDGET_SPECIALISED
                                                 : NBRDF_BAKE_BUDGET_FITTED;
}

/* COMPACT: the small decoder's multiply-adds per query (0 for the other levels). */
static nbrdf_status student_macs_of(const nbrdf_bake_options *o, int64_t *macs,
                                    nbrdf_error *err) {
  *macs = 0;
  if (o->accuracy != NBRDF_BAKE_COMPACT) return NBRDF_OK;
  const int K = o->compact_dim > 0 ? o->compact_dim : BAKE_COMPACT_DEFAULT_DIM;
  const int width = o->compact_width > 0 ? o->compact_width : BAKE_COMPACT_DEFAULT_WIDTH;
  model_decoder_config cfg;
  nbrdf_status st = model_decoder_compact_config(K, width, &cfg, err);
  if (st == NBRDF_OK) *macs = nn_spec_macs(&cfg.spec);
  return st;
}

nbrdf_status bake_accuracy_check(const nbrdf_model *model, const nbrdf_bake_options *o,
                                 nbrdf_error *err) {
  int64_t student_macs;
  nbrdf_status st = student_macs_of(o, &student_macs, err);
  bake_plan plan;
  /* One tuple: the smallest plan, whose cost alone decides whether the budget suffices. */
  if (st == NBRDF_OK)
    st = bake_plan_make(o->accuracy, bake_accuracy_budget(o), 1, nbrdf_model_decoder_macs(model),
                        student_macs, &plan, err);
  return st;
}

/* The distinct tuples of the scenes as the fit sees them (bake_gather_tuples; lo, hi: the
 * trained ranges). alpha1 and alpha2 below the trained range are fitted as given
 * (bake_range.h): their ground truth is that of the user's values, the networks see the
 * trained minimum. */
static nbrdf_status gather(const nbrdf_model *model, const bake_scene *scenes, size_t n_scenes,
                           const nbrdf_bake_options *o, const float *lo, const float *hi,
                           bake_tuple **cand, size_t *n_cand, size_t *distinct, nbrdf_error *err) {
  float take[NBRDF_BAKE_PARAM_COUNT], take_hi[NBRDF_BAKE_PARAM_COUNT];
  bake_taken_ranges(model, o->accuracy, take, take_hi);
  bake_gather_settings gs = {lo, hi, take, o->roughness, o->range, o->quantise_bits, o->cancel};
  return bake_gather_tuples(scenes, n_scenes, &gs, cand, n_cand, distinct, err);
}

nbrdf_status bake_accuracy_fit(const nbrdf_model *model, const bake_scene *scenes, size_t n_scenes,
                               const nbrdf_bake_options *o, core_ticker *ticker, bake_fit_result *r,
                               nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  float lo[NBRDF_BAKE_PARAM_COUNT], hi[NBRDF_BAKE_PARAM_COUNT];
  model_material_ranges(model, lo, hi);
  r->budget = bake_accuracy_budget(o);
  const int compact = o->accuracy == NBRDF_BAKE_COMPACT;
  const int K = o->compact_dim > 0 ? o->compact_dim : BAKE_COMPACT_DEFAULT_DIM;
  const int width = o->compact_width > 0 ? o->compact_width : BAKE_COMPACT_DEFAULT_WIDTH;
  int64_t student_macs;
  nbrdf_status sm = student_macs_of(o, &student_macs, err);
  if (sm != NBRDF_OK) return sm;
  bake_tuple *cand = NULL;
  size_t n_cand = 0;
  nbrdf_status st = gather(model, scenes, n_scenes, o, lo, hi, &cand, &n_cand, &r->distinct, err);
  bake_plan plan;
  if (st == NBRDF_OK)
    st = bake_plan_make(o->accuracy, r->budget, r->distinct, nbrdf_model_decoder_macs(model),
                        student_macs, &plan, err);
  bake_selection sel = {0}, teach = {0};
  if (st == NBRDF_OK)
    st = bake_select(cand, n_cand, lo, hi, plan.n_fit, plan.n_held, o->seed, &sel, err);
  /* COMPACT: the tuples the teacher speaks for, spread over the scene the same way. */
  if (st == NBRDF_OK && compact)
    st = bake_select(cand, n_cand, lo, hi, BAKE_COMPACT_TEACHER, 0, o->seed + 7, &teach, err);
  free(cand);
  train_samples samples = {0};
  double *images = NULL;
  bake_truth_settings ts = {plan.incident, OUTGOING,  SAMPLED, SPP, LOBE_RES, LOBE_WALKS,
                            o->seed,       ticker,    0.0,     0.0, o->cancel};
  if (st == NBRDF_OK) {
    ts.total = (double)(sel.n_fit + sel.n_held);
    if (ticker && core_ticker_tick(ticker, "ground truth", 0, ts.total, 1))
      st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled before the ground truth");
  }
  if (st == NBRDF_OK) st = bake_truth_samples(sel.fit, sel.n_fit, &ts, &samples, err);
  if (st == NBRDF_OK) {
    images = malloc(sizeof(double) * sel.n_held * BAKE_LOBE_N_THETA * LOBE_RES * LOBE_RES + 1);
    if (!images) st = core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for lobe images");
    ts.done0 = (double)sel.n_fit;
  }
  if (st == NBRDF_OK) st = bake_truth_lobes(sel.held, sel.n_held, &ts, images, err);
  if (st == NBRDF_OK && ticker &&
      core_ticker_tick(ticker, "ground truth", ts.total, ts.total, 1))
    st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled after the ground truth");
  bake_fit_settings fs = {plan.project_steps, plan.joint_steps, plan.rows_per_brdf, o->seed,
                          ticker, o->cancel, bake_fit_energy_weight(o)};
  if (st == NBRDF_OK)
    st = bake_fit_run(model, sel.fit, sel.n_fit, &samples, &fs, &r->correction, err);
  bake_compact_settings cs = {width, plan.distil_steps, plan.distil_rows, o->seed + 3, ticker,
                              o->cancel};
  if (st == NBRDF_OK && compact)
    st = bake_compact_build(model, &r->correction, sel.fit, sel.n_fit, &samples, teach.fit,
                            teach.n_fit, K, &cs, &r->compact, err);
  if (st == NBRDF_OK)
    st = bake_heldout_error(model, &r->correction, compact ? &r->compact : NULL, sel.held,
                            sel.n_held, images, LOBE_RES, o->seed, &r->heldout_error,
                            &r->heldout_error_fast, NULL, err);
  /* The energy guard on every tuple whose truth the fit or the check used. */
  bake_tuple *both = NULL;
  size_t n_both = sel.n_fit + (sel.held_are_fitted ? 0 : sel.n_held);
  if (st == NBRDF_OK) {
    both = malloc(sizeof *both * (n_both ? n_both : 1));
    if (!both) st = core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for the energy check");
  }
  if (st == NBRDF_OK) {
    memcpy(both, sel.fit, sizeof *both * sel.n_fit);
    if (!sel.held_are_fitted) memcpy(both + sel.n_fit, sel.held, sizeof *both * sel.n_held);
    st = bake_energy_measure(model, &r->correction, compact ? &r->compact : NULL, both, n_both,
                             &r->albedo_max, &r->albedo_max_fast, NULL, err);
    r->albedo_tuples = st == NBRDF_OK ? n_both : 0;
  }
  free(both);
  if (st == NBRDF_OK) {
    r->fitted = sel.n_fit;
    r->heldout = sel.n_held;
    r->level = o->accuracy;
    snprintf(r->attribute, sizeof r->attribute,
             "level=%s; budget=%g; cost=%.1f; distinct=%zu; fitted=%zu; heldout=%zu%s; "
             "heldoutError=%.4f; fastError=%.4f; maxAlbedoFit=%.4f; fastMaxAlbedoFit=%.4f; "
             "seed=%llu",
             nbrdf_bake_accuracy_name(o->accuracy), r->budget, plan.cost, r->distinct, r->fitted,
             r->heldout, sel.held_are_fitted ? " (fitted tuples, independent truth)" : "",
             r->heldout_error, r->heldout_error_fast, r->albedo_max, r->albedo_max_fast,
             (unsigned long long)o->seed);
    if (compact) {
      size_t len = strlen(r->attribute);
      snprintf(r->attribute + len, sizeof r->attribute - len,
               "; compact=%d; compactWidth=%d; decoderMacs=%lld; varianceKept=%.4f; "
               "distilSteps=%d; distilLossTruth=%.4f; distilLossTeacher=%.4f",
               K, width, (long long)student_macs, r->compact.kept, plan.distil_steps,
               r->compact.loss_truth, r->compact.loss_teacher);
    }
  }
  free(images);
  train_samples_free(&samples);
  bake_selection_free(&sel);
  bake_selection_free(&teach);
  if (st != NBRDF_OK) bake_fit_result_free(r);
  return st;
}

nbrdf_status bake_accuracy_fast_error(const nbrdf_model *model, const bake_scene *scenes,
                                      size_t n_scenes, const nbrdf_bake_options *o,
                                      core_ticker *ticker, double *fast, size_t *heldout,
                                      size_t *distinct, nbrdf_error *err) {
  *fast = 0.0, *heldout = 0, *distinct = 0;
  float lo[NBRDF_BAKE_PARAM_COUNT], hi[NBRDF_BAKE_PARAM_COUNT];
  model_material_ranges(model, lo, hi);
  bake_tuple *cand = NULL;
  size_t n_cand = 0;
  nbrdf_status st = gather(model, scenes, n_scenes, o, lo, hi, &cand, &n_cand, distinct, err);
  /* FITTED's plan at this budget and its selection: the held-out tuples are then those the
   * fitted level is measured on, with the same truth (same seed and streams). */
  bake_plan plan;
  if (st == NBRDF_OK)
    st = bake_plan_make(NBRDF_BAKE_FITTED, bake_accuracy_budget(o), *distinct,
                        nbrdf_model_decoder_macs(model), 0, &plan, err);
  bake_selection sel = {0};
  if (st == NBRDF_OK)
    st = bake_select(cand, n_cand, lo, hi, plan.n_fit, plan.n_held, o->seed, &sel, err);
  free(cand);
  double *images = NULL;
  bake_truth_settings ts = {plan.incident, OUTGOING, SAMPLED, SPP, LOBE_RES, LOBE_WALKS,
                            o->seed, ticker, 0.0, (double)sel.n_held, o->cancel};
  if (st == NBRDF_OK) {
    images = malloc(sizeof(double) * sel.n_held * BAKE_LOBE_N_THETA * LOBE_RES * LOBE_RES + 1);
    if (!images) st = core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for lobe images");
  }
  if (st == NBRDF_OK && ticker && core_ticker_tick(ticker, "ground truth", 0, ts.total, 1))
    st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled before the ground truth");
  if (st == NBRDF_OK) st = bake_truth_lobes(sel.held, sel.n_held, &ts, images, err);
  if (st == NBRDF_OK)
    st = bake_heldout_error(model, NULL, NULL, sel.held, sel.n_held, images, LOBE_RES, o->seed,
                            NULL, fast, NULL, err);
  if (st == NBRDF_OK) *heldout = sel.n_held;
  free(images);
  bake_selection_free(&sel);
  return st;
}

double bake_accuracy_budget_for(const nbrdf_model *model, nbrdf_bake_accuracy level,
                                double budget, size_t distinct, double error, double target) {
  if (!(error > target) || !(target > 0.0)) return budget;
  /* A guess, not a promise: the held-out error measured on the ladder falls roughly as
   * 1/sqrt(budget) while more tuples and steps fit (docs/BAKE.md, "auto"). */
  double want = budget * (error / target) * (error / target);
  if (want > 1e7) want = 1e7;
  want = 10.0 * ceil(want / 10.0);
  bake_plan now, then;
  nbrdf_error e;
  int64_t macs = nbrdf_model_decoder_macs(model);
  if (bake_plan_make(level, budget, distinct, macs, 0, &now, &e) != NBRDF_OK ||
      bake_plan_make(level, want, distinct, macs, 0, &then, &e) != NBRDF_OK)
    return want;
  /* The plan no longer grows (every distinct tuple fitted, the most directions and steps):
   * more budget buys nothing. */
  if (then.n_fit == now.n_fit && then.incident == now.incident &&
      then.project_steps == now.project_steps && then.joint_steps == now.joint_steps)
    return 0.0;
  return want;
}
