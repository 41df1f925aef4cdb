#include "bake/bake_energy_check.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_audit.h"
#include "core/error.h"
#include "model/bundle.h"

double bake_energy_limit(double fast_max) {
  return fmax(BAKE_AUDIT_LIMIT, fast_max + BAKE_ENERGY_MARGIN);
}

int bake_energy_creates(double level_max, double fast_max) {
  return !(level_max <= bake_energy_limit(fast_max));
}

nbrdf_status bake_energy_measure(const nbrdf_model *model, const bake_correction *c,
                                 const bake_compact *compact, const bake_tuple *t, size_t n,
                                 double *level_max, double *fast_max, size_t *worst,
                                 nbrdf_error *err) {
  *level_max = *fast_max = 0.0;
  if (worst) *worst = 0;
  if (n == 0) return NBRDF_OK;
  const int D = nbrdf_model_latent_dim(model);
  const model_decoder *spec = compact ? compact->student : bake_correction_decoder(c, model);
  const int K = compact ? spec->cfg.latent_dim : D;
  float *net = malloc(sizeof(float) * n * (D + 2));
  float *zf = malloc(sizeof(float) * n * D), *zl = malloc(sizeof(float) * n * K);
  double *vf = malloc(sizeof(double) * n), *vl = malloc(sizeof(double) * n);
  nbrdf_status st = NBRDF_OK;
  if (!net || !zf || !zl || !vf || !vl)
    st = core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for the energy check");
  if (st == NBRDF_OK) st = bake_tuples_evaluate(model, t, NULL, n, net, err);
  if (st == NBRDF_OK) {
    for (size_t k = 0; k < n; k++)
      memcpy(zf + k * D, net + k * (D + 2), sizeof(float) * D);
    /* The level's latents: the network's plus the carried correction (a fitted tuple's own
     * fitted latent), as the texture stores them. */
    bake_correct_latents(c, t, NULL, n, net, (size_t)(D + 2));
    for (size_t k = 0; k < n; k++) {
      if (compact)
        bake_compact_reduce(compact, net + k * (D + 2), zl + k * K);
      else
        memcpy(zl + k * K, net + k * (D + 2), sizeof(float) * D);
    }
    st = bake_albedo_precise_with(model->decoder, n, zf, vf, NULL, err);
  }
  if (st == NBRDF_OK) st = bake_albedo_precise_with(spec, n, zl, vl, NULL, err);
  if (st == NBRDF_OK) {
    size_t w = 0;
    double f = vf[0];
    for (size_t k = 1; k < n; k++) {
      if (!isnan(vl[w]) && !(vl[k] <= vl[w])) w = k; /* NaN wins: reported, never hidden */
      f = fmax(f, vf[k]);
    }
    *level_max = vl[w], *fast_max = f;
    if (worst) *worst = w;
  }
  free(net), free(zf), free(zl), free(vf), free(vl);
  return st;
}
