/* The energy penalty's ceilings and its call in the training loops
 * (energy_reference.h). */
#include "train/energy_reference.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/rng.h"
#include "nbrdf/brdf.h"

#define ENERGY_TAG UINT64_C(0x656e7267)

struct train_energy {
  model_energy *pen;
  const train_samples *data;
  model_energy_options o;
  int per_step;
  int D;
  float *ceiling;           /* [n_brdfs × n_theta], NaN until computed */
  float *floors;            /* [n_brdfs × n_theta] beside it; NULL when o.floor_margin < 0 */
  float *lat, *grad, *ceil; /* [per_step × D], [per_step × D], [per_step × n_theta] */
  float *flo;               /* [per_step × n_theta]; NULL without floors */
  size_t *pick;             /* [per_step] */
};

void train_energy_destroy(train_energy *e) {
  if (!e) return;
  model_energy_destroy(e->pen);
  free(e->ceiling), free(e->floors), free(e->lat), free(e->grad), free(e->ceil), free(e->flo);
  free(e->pick);
  free(e);
}

nbrdf_status train_energy_create(const model_decoder *dec, const train_samples *data,
                                 const model_energy_options *o, int brdfs_per_step,
                                 train_energy **out, nbrdf_error *err) {
  *out = NULL;
  if (o->lambda == 0.0f) return NBRDF_OK;
  if (brdfs_per_step < 1 || brdfs_per_step > 4096)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "energy penalty: %d BRDFs per step, expected 1..4096",
                     brdfs_per_step);
  train_energy *e = calloc(1, sizeof *e);
  if (!e) return core_fail(err, NBRDF_ERR_MEMORY, "energy penalty: out of memory");
  e->data = data, e->o = *o, e->per_step = brdfs_per_step, e->D = dec->cfg.latent_dim;
  nbrdf_status st = model_energy_create(dec, o, &e->pen, err);
  size_t T = (size_t)o->n_theta, K = (size_t)brdfs_per_step;
  if (!st) {
    e->ceiling = malloc((data->n_brdfs ? data->n_brdfs : 1) * T * sizeof *e->ceiling);
    e->lat = malloc(K * (size_t)e->D * sizeof *e->lat);
    e->grad = malloc(K * (size_t)e->D * sizeof *e->grad);
    e->ceil = malloc(K * T * sizeof *e->ceil);
    e->pick = malloc(K * sizeof *e->pick);
    int want_floors = o->floor_margin >= 0.0f;
    if (want_floors) {
      e->floors = malloc((data->n_brdfs ? data->n_brdfs : 1) * T * sizeof *e->floors);
      e->flo = malloc(K * T * sizeof *e->flo);
    }
    if (!e->ceiling || !e->lat || !e->grad || !e->ceil || !e->pick ||
        (want_floors && (!e->floors || !e->flo)))
      st = core_fail(err, NBRDF_ERR_MEMORY, "energy penalty: out of memory");
  }
  if (st) {
    train_energy_destroy(e);
    return st;
  }
  for (size_t k = 0; k < data->n_brdfs * T; k++)
    e->ceiling[k] = NAN;
  *out = e;
  return NBRDF_OK;
}

/* The ceilings (and floors) of BRDF b (a pure function of b and the options). */
static void compute(train_energy *e, size_t b) {
  float *c = e->ceiling + b * (size_t)e->o.n_theta;
  float *lo = e->floors ? e->floors + b * (size_t)e->o.n_theta : NULL;
  nbrdf_brdf *brdf = NULL;
  if (!e->data->params || train_params_create(&e->data->params[b], &brdf, NULL) != NBRDF_OK) {
    for (int t = 0; t < e->o.n_theta; t++) {
      c[t] = 1.0f; /* no reference: energy conservation */
      if (lo) lo[t] = 0.0f;
    }
    return;
  }
  for (int t = 0; t < e->o.n_theta; t++) {
    double rho = 1.0, se = 0.0;
    if (nbrdf_brdf_albedo(brdf, e->o.theta_deg[t] * (M_PI / 180.0), TRAIN_ENERGY_REF_SAMPLES,
                          core_hash64(core_hash64(e->o.seed, ENERGY_TAG), b * 64 + (size_t)t), &rho,
                          &se, NULL) != NBRDF_OK)
      rho = 1.0, se = 0.0;
    c[t] = (float)fmin(1.0, rho + 2.0 * se + 0.01);
    if (lo) lo[t] = (float)fmax(0.0, rho - 2.0 * se - (double)e->o.floor_margin);
  }
  nbrdf_brdf_destroy(brdf);
}

/* Ceilings of n BRDFs into out and, where on and lo is not NULL, their floors into lo. */
static nbrdf_status bounds(train_energy *e, size_t n, const size_t *brdfs, float *out, float *lo,
                           nbrdf_error *err) {
  size_t T = (size_t)e->o.n_theta;
  for (size_t i = 0; i < n; i++) {
    size_t b = brdfs[i];
    if (b >= e->data->n_brdfs)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "energy penalty: BRDF %zu of %zu", b,
                       e->data->n_brdfs);
    if (isnan(e->ceiling[b * T])) compute(e, b);
    memcpy(out + i * T, e->ceiling + b * T, T * sizeof *out);
    if (e->floors && lo) memcpy(lo + i * T, e->floors + b * T, T * sizeof *lo);
  }
  return NBRDF_OK;
}

nbrdf_status train_energy_ceilings(train_energy *e, size_t n, const size_t *brdfs, float *out,
                                   nbrdf_error *err) {
  return bounds(e, n, brdfs, out, NULL, err);
}

nbrdf_status train_energy_add_fit(train_energy *e, model_fit *fit, const float *latents,
                                  int64_t step, double *penalty, nbrdf_error *err) {
  *penalty = 0.0;
  if (!e) return NBRDF_OK;
  double pen = 0.0;
  /* K distinct BRDFs of the step's stream (partial Fisher-Yates by rejection:
   * K is far below the BRDF count in practice). */
  size_t n = e->data->n_brdfs, K = (size_t)e->per_step < n ? (size_t)e->per_step : n;
  size_t D = (size_t)e->D;
  core_rng rng;
  core_rng_init(&rng, core_hash64(e->o.seed, ENERGY_TAG + 1), (uint64_t)step);
  for (size_t k = 0; k < K; k++) {
    size_t b;
    int again;
    do {
      b = (size_t)(core_rng_uniform(&rng) * (double)n);
      again = 0;
      for (size_t j = 0; j < k; j++)
        again |= e->pick[j] == b;
    } while (again);
    e->pick[k] = b;
    memcpy(e->lat + k * D, latents + b * D, D * sizeof *e->lat);
  }
  nbrdf_status st = bounds(e, K, e->pick, e->ceil, e->flo, err);
  memset(e->grad, 0, K * D * sizeof *e->grad);
  if (!st)
    st = model_energy_add(e->pen, K, e->lat, e->ceil, e->flo, step, e->grad,
                          model_fit_grad_weights(fit), &pen, NULL, err);
  if (st) return st;
  float *g = model_fit_grad_latent(fit);
  for (size_t k = 0; k < K; k++)
    for (size_t j = 0; j < D; j++)
      g[e->pick[k] * D + j] += e->grad[k * D + j];
  *penalty = pen;
  return NBRDF_OK;
}

nbrdf_status train_energy_pairs(train_energy *e, size_t m, const size_t *idx, const size_t *brdf_of,
                                const float *z, int64_t step, float *dz, double *penalty,
                                nbrdf_error *err) {
  if (penalty) *penalty = 0.0;
  if (!e || m == 0) return NBRDF_OK;
  size_t K = (size_t)e->per_step < m ? (size_t)e->per_step : m;
  for (size_t k = 0; k < K; k++)
    e->pick[k] = brdf_of[idx[k]];
  nbrdf_status st = bounds(e, K, e->pick, e->ceil, e->flo, err);
  /* z rows 0..K-1 are those pairs' latents, contiguous: no copy needed. */
  if (!st) st = model_energy_add(e->pen, K, z, e->ceil, e->flo, step, dz, NULL, penalty, NULL, err);
  return st;
}
