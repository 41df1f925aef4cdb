/* The neural side of `nbrdf evaluate`: latents per held-out BRDF (projection,
 * or tables + layering network), decoded lobe images, and the metrics. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/error.h"
#include "core/sort.h"
#include "eval/evaluate.h"
#include "eval/median_interval.h"
#include "lobe/lobe.h"
#include "model/bundle.h"
#include "train/params_latent.h"
#include "train/table_fit.h"

#define IMG ((size_t)NBRDF_LOBE_RES * NBRDF_LOBE_RES)
#define PER_BRDF (NBRDF_LOBE_N_THETA * IMG)

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

nbrdf_status eval_decoder_lobe_fn(void *user, size_t n, const nbrdf_query *q, double *f,
                                  nbrdf_error *err) {
  const eval_decoder_lobe *d = user;
  int D = d->dec->cfg.latent_dim;
  float *lat = calloc(n * (size_t)D, sizeof *lat), *wi = calloc(6 * n, sizeof *wi);
  float *wo = wi ? wi + 3 * n : NULL, *out = calloc(n, sizeof *out);
  nbrdf_status st = lat && wi && out ? NBRDF_OK : core_fail(err, NBRDF_ERR_MEMORY, "out of memory");
  for (size_t k = 0; k < n && !st; k++) {
    memcpy(lat + k * (size_t)D, d->latent, (size_t)D * sizeof *lat);
    for (int j = 0; j < 3; j++)
      wi[3 * k + j] = (float)q[k].wi[j], wo[3 * k + j] = (float)q[k].wo[j];
  }
  if (!st) st = model_decoder_eval(d->dec, d->runner, n, 1, lat, wi, wo, out, err);
  for (size_t k = 0; k < n && !st; k++)
    f[k] = out[k];
  free(lat), free(wi), free(out);
  return st;
}

static void summarise(eval_result *r) {
  double *e = malloc((size_t)r->n * sizeof *e), *a = malloc((size_t)r->n * sizeof *a);
  if (!e || !a) {
    free(e), free(a);
    return;
  }
  r->worst = -1, r->max_albedo = 0;
  for (int i = 0; i < r->n; i++) {
    e[i] = r->cases[i].lobe_error, a[i] = r->cases[i].albedo_error;
    if (e[i] > r->worst) r->worst = e[i], r->worst_index = i;
    if (r->cases[i].max_albedo > r->max_albedo)
      r->max_albedo = r->cases[i].max_albedo, r->max_albedo_index = i;
  }
  core_sort_doubles(e, (size_t)r->n);
  core_sort_doubles(a, (size_t)r->n);
  r->median = e[r->n / 2];
  int k90 = (int)ceil(0.9 * r->n) - 1;
  r->p90 = e[k90 < 0 ? 0 : k90];
  r->median_albedo_error = a[r->n / 2];
  for (int i = 0; i < r->n; i++)
    if (r->cases[i].lobe_error == r->median) r->median_index = i;
  /* seeded by the set alone: the same cases give the same interval */
  eval_median_interval(e, r->n, (uint64_t)r->set, &r->median_lo, &r->median_hi);
  /* tails: the same figures per region (case i is in region i % 3) */
  for (int g = 0; g < TRAIN_TAILS_REGIONS && eval_set_has_regions(r->set); g++) {
    int m = 0;
    for (int i = g; i < r->n; i += TRAIN_TAILS_REGIONS)
      e[m++] = r->cases[i].lobe_error;
    r->region_n[g] = m;
    if (!m) continue;
    core_sort_doubles(e, (size_t)m);
    int q90 = (int)ceil(0.9 * m) - 1;
    r->region_median[g] = e[m / 2], r->region_p90[g] = e[q90 < 0 ? 0 : q90];
    eval_median_interval(e, m, (uint64_t)r->set * 16 + (uint64_t)g + 1, &r->region_median_lo[g],
                         &r->region_median_hi[g]);
  }
  free(e), free(a);
}

nbrdf_status eval_score_latents(model_decoder *dec, size_t n, const float *lat, const double *ref,
                                double *approx, eval_case *cases, nbrdf_error *err) {
  size_t D = (size_t)dec->cfg.latent_dim;
  double *own = approx ? NULL : malloc(PER_BRDF * sizeof *own);
  if (!approx && !own) return core_fail(err, NBRDF_ERR_MEMORY, "evaluate: out of memory");
  model_runner runner = {0};
  eval_decoder_lobe dl = {dec, &runner, NULL};
  nbrdf_status st = model_runner_create(dec->nn, 4096, NBRDF_NN_INFER, &runner, err);
  for (size_t i = 0; i < n && !st; i++) {
    dl.latent = lat + i * D;
    const double *r = ref + i * PER_BRDF;
    double *img = approx ? approx + i * PER_BRDF : own;
    st = lobe_images(eval_decoder_lobe_fn, &dl, NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA, lobe_theta_deg,
                     img, err);
    if (st) break;
    eval_case *c = &cases[i];
    c->lobe_error = lobe_l1_error(PER_BRDF, r, img);
    c->albedo_error = lobe_albedo_error(NBRDF_LOBE_RES, NBRDF_LOBE_N_THETA, r, img, NULL);
    c->max_albedo = 0;
    for (int t = 0; t < NBRDF_LOBE_N_THETA; t++) {
      double a = lobe_albedo(NBRDF_LOBE_RES, img + t * IMG);
      if (a > c->max_albedo) c->max_albedo = a;
    }
  }
  model_runner_destroy(&runner);
  free(own);
  return st;
}

nbrdf_status eval_run(const nbrdf_model *model, model_decoder *dec, eval_set set,
                      const eval_settings *s, eval_result *r, nbrdf_error *err) {
  memset(r, 0, sizeof *r);
  r->set = set, r->n = s->count;
  if (eval_set_size_max(set) && s->count > eval_set_size_max(set))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "evaluate: the %s set has %d BRDFs, not %d",
                     eval_set_name(set), eval_set_size_max(set), s->count);
  if (model) dec = model->decoder;
  int projected = set == EVAL_REP || set == EVAL_SINGLE || set == EVAL_TAILS_REP;
  if (!projected && !model)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "evaluate: the %s set needs a bundle (tables and layering network)",
                     eval_set_name(set));
  size_t n = (size_t)s->count, D = (size_t)dec->cfg.latent_dim;
  r->cases = calloc(n, sizeof *r->cases);
  r->ref = malloc(n * PER_BRDF * sizeof *r->ref);
  r->approx = malloc(n * PER_BRDF * sizeof *r->approx);
  float *lat = malloc(n * D * sizeof *lat);
  train_params *params = malloc(n * sizeof *params);
  if (!r->cases || !r->ref || !r->approx || !lat || !params) {
    free(lat), free(params);
    eval_result_free(r);
    return core_fail(err, NBRDF_ERR_MEMORY, "evaluate: out of memory");
  }
  uint64_t family = train_heldout_seed(eval_set_heldout(set));
  for (size_t i = 0; i < n; i++) {
    eval_set_draw(set, i, &params[i]);
    r->cases[i].params = params[i];
  }
  double t0 = now_s();
  eval_extra_ref extra = {0};
  nbrdf_status st = eval_reference(set, s, r->ref, &r->ref_noise, err);
  if (!st) st = eval_reference_extra(set, s, &extra, err);
  double t1 = now_s();
  if (!st && projected)
    st = train_project_params(dec, n, params, family, s->project_steps, 1, lat, NULL, err);
  for (size_t i = 0; i < n && !st && !projected; i++)
    st = train_params_bundle_latent(model, &params[i], lat + i * D, err);
  if (!st) st = eval_score_latents(dec, n, lat, r->ref, r->approx, r->cases, err);
  if (!st) st = eval_score_extra(model, dec, n, lat, r->ref, &extra, r->cases, err);
  eval_extra_ref_free(&extra);
  r->seconds_reference = t1 - t0;
  r->seconds_model = now_s() - t1;
  free(lat), free(params);
  if (st) {
    eval_result_free(r);
    return st;
  }
  summarise(r);
  eval_summarise_extra(r);
  return NBRDF_OK;
}

void eval_result_free(eval_result *r) {
  free(r->cases), free(r->ref), free(r->approx);
  r->cases = NULL, r->ref = r->approx = NULL;
}
