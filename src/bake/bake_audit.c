/* The bake's energy audit (bake_audit.h). */
#include "bake/bake_audit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_compact.h"
#include "core/error.h"
#include "model/albedo_quad.h"
#include "model/bundle.h"
#include "model/model_gpu.h"

const double bake_audit_theta_deg[BAKE_AUDIT_N_THETA] = {0.0, 30.0, 60.0, 80.0, 85.0, 89.0};

#define AUDIT_SEED UINT64_C(0x6175646974)

static nbrdf_status albedo_max(const nbrdf_model *model, struct gpu_network *gpu, size_t n,
                               const float *latents, const float *sigma, double *maxv,
                               int *theta_index, nbrdf_error *err) {
  if (n == 0) return NBRDF_OK;
  double *rho = malloc(n * BAKE_AUDIT_N_THETA * sizeof *rho);
  if (!rho) return core_fail(err, NBRDF_ERR_MEMORY, "energy audit: out of memory");
  model_runner runner;
  nbrdf_status st = gpu ? model_gpu_runner(gpu, 8192, &runner, err)
                        : model_runner_create(model->decoder->nn, 4096, NBRDF_NN_INFER, &runner, err);
  if (!st)
    st = model_albedo_decoded(model->decoder, &runner, n, latents, sigma, BAKE_AUDIT_N_THETA,
                              bake_audit_theta_deg, BAKE_AUDIT_SAMPLES, AUDIT_SEED, rho, NULL, err);
  /* The cheap estimate's maximum over θi is noisy and biased upwards (the
   * largest of six noisy values): latents that come near the limit are
   * measured again with BAKE_AUDIT_REFINE_SAMPLES directions. */
  for (size_t k = 0; k < n && !st; k++) {
    double mx = 0.0;
    for (int t = 0; t < BAKE_AUDIT_N_THETA; t++)
      mx = fmax(mx, rho[k * BAKE_AUDIT_N_THETA + t]);
    if (mx > BAKE_AUDIT_REFINE_ABOVE)
      st = model_albedo_decoded(model->decoder, &runner, 1, latents + k * model->latent_dim,
                                sigma ? sigma + k : NULL, BAKE_AUDIT_N_THETA, bake_audit_theta_deg,
                                BAKE_AUDIT_REFINE_SAMPLES, AUDIT_SEED, rho + k * BAKE_AUDIT_N_THETA,
                                NULL, err);
  }
  model_runner_destroy(&runner);
  for (size_t k = 0; k < n && !st; k++) {
    int best = 0;
    for (int t = 1; t < BAKE_AUDIT_N_THETA; t++)
      if (rho[k * BAKE_AUDIT_N_THETA + t] > rho[k * BAKE_AUDIT_N_THETA + best]) best = t;
    maxv[k] = rho[k * BAKE_AUDIT_N_THETA + best];
    if (theta_index) theta_index[k] = best;
  }
  free(rho);
  return st;
}

nbrdf_status bake_albedo_max(const nbrdf_model *model, size_t n, const float *latents,
                             const float *sigma, double *maxv, int *theta_index, nbrdf_error *err) {
  return albedo_max(model, NULL, n, latents, sigma, maxv, theta_index, err);
}

void bake_audit_init(bake_audit *a, size_t cap) {
  memset(a, 0, sizeof *a);
  a->cap = cap;
  a->worst = -1.0;
}

void bake_audit_free(bake_audit *a) {
  free(a->lat), free(a->sigma), free(a->maxv), free(a->theta);
  size_t cap = a->cap;
  struct gpu_network *gpu = a->gpu_decoder;
  memset(a, 0, sizeof *a);
  a->cap = cap;
  a->gpu_decoder = gpu;
}

nbrdf_status bake_audit_tuples(bake_audit *a, const nbrdf_model *model, const float *out,
                               const size_t *idx, size_t n, size_t *band_worst, nbrdf_error *err) {
  *band_worst = (size_t)-1;
  size_t room = a->cap > a->audited ? a->cap - a->audited : 0;
  if (n > room) a->skipped += n - room, n = room;
  if (n == 0) return NBRDF_OK;
  const size_t D = (size_t)nbrdf_model_latent_dim(model);
  const size_t stored = a->compact ? (size_t)a->compact->work_dim : D;
  if (n > a->scratch_cap) {
    free(a->lat), free(a->sigma), free(a->maxv), free(a->theta);
    a->lat = malloc(n * D * sizeof *a->lat);
    a->sigma = malloc(n * sizeof *a->sigma);
    a->maxv = malloc(n * sizeof *a->maxv);
    a->theta = malloc(n * sizeof *a->theta);
    a->scratch_cap = n;
    if (!a->lat || !a->sigma || !a->maxv || !a->theta) {
      a->scratch_cap = 0;
      return core_fail(err, NBRDF_ERR_MEMORY, "energy audit: out of memory");
    }
  }
  for (size_t k = 0; k < n; k++) {
    const float *o = out + idx[k] * (stored + 2);
    if (a->compact)
      bake_compact_reduce(a->compact, o, a->lat + k * D);
    else
      memcpy(a->lat + k * D, o, D * sizeof *a->lat);
    a->sigma[k] = o[stored];
  }
  nbrdf_status st = albedo_max(model, a->gpu_decoder, n, a->lat, a->sigma, a->maxv, a->theta, err);
  if (st) return st;
  a->audited += n;
  for (size_t k = 0; k < n; k++) {
    a->over += a->maxv[k] > BAKE_AUDIT_LIMIT;
    if (a->maxv[k] > a->worst) {
      a->worst = a->maxv[k], a->worst_theta = a->theta[k];
      *band_worst = idx[k];
    }
  }
  return NBRDF_OK;
}

void bake_audit_found(bake_audit *a, const bake_tuple *t, int x, int y, int c) {
  a->tuple = *t, a->x = x, a->y = y, a->c = c;
}

void bake_audit_message(const bake_audit *a, int rgb, char *buf, size_t cap) {
  buf[0] = '\0';
  size_t len = 0;
  if (a->audited && a->worst > BAKE_AUDIT_LIMIT) {
    const float *p = a->tuple.p;
    char chan[16] = "";
    if (rgb) snprintf(chan, sizeof chan, " channel %c", "RGB"[a->c % 3]);
    int n = snprintf(buf, cap,
                     "energy audit: %zu of %zu distinct latents decode to a directional albedo "
                     "above %.2f (the model creates energy there); the worst, %.3f at theta_i = "
                     "%g deg, at texel (%d, %d)%s: alpha1=%g eta=%g alpha2=%g r0=%g albedo=%g "
                     "sigma_t=%g",
                     a->over, a->audited, BAKE_AUDIT_LIMIT, a->worst,
                     bake_audit_theta_deg[a->worst_theta], a->x, a->y, chan,
                     (double)p[NBRDF_BAKE_ALPHA1], (double)p[NBRDF_BAKE_ETA],
                     (double)p[NBRDF_BAKE_ALPHA2], (double)p[NBRDF_BAKE_R0],
                     (double)p[NBRDF_BAKE_ALBEDO], (double)p[NBRDF_BAKE_SIGMA_T]);
    len = n > 0 && (size_t)n < cap ? (size_t)n : len;
  }
  if (a->skipped && len < cap)
    snprintf(buf + len, cap - len,
             "%senergy audit: %zu distinct latents past the first %zu were "
             "not audited (nbrdf:maxAlbedo covers those audited)",
             len ? "; " : "", a->skipped, a->audited);
}
