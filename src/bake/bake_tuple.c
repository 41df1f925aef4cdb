#include "bake/bake_tuple.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "model/bundle.h"
#include "model/layering.h"
#include "model/model_gpu.h"
#include "model/sampler.h"

/* Layering then sampling network on the GPU: the values are prepared (finite, in range),
 * so nbrdf_model_layer's and nbrdf_model_proxy_params's checks have nothing to find. */
static nbrdf_status networks_gpu(const nbrdf_model *m, const model_gpu *gpu, size_t n,
                                 const float *top, const float *bottom, const float *albedo,
                                 const float *sigma_t, float *layered, float *sigma, float *w,
                                 nbrdf_error *err) {
  model_runner r;
  nbrdf_status st = model_gpu_runner(gpu->layering, (int)n, &r, err);
  if (st == NBRDF_OK)
    st = model_layering_eval(m->layering, &r, n, top, bottom, albedo, sigma_t, layered, err);
  model_runner_destroy(&r);
  if (st == NBRDF_OK) st = model_gpu_runner(gpu->sampler, (int)n, &r, err);
  if (st == NBRDF_OK) st = model_sampler_eval(m->sampler, &r, n, layered, sigma, w, err);
  model_runner_destroy(&r);
  return st;
}

nbrdf_status bake_tuples_evaluate(const nbrdf_model *model, const bake_tuple *t, const size_t *idx,
                                  size_t n, float *out, nbrdf_error *err) {
  return bake_tuples_evaluate_on(model, NULL, t, idx, n, out, err);
}

nbrdf_status bake_tuples_evaluate_on(const nbrdf_model *model, const model_gpu *gpu,
                                     const bake_tuple *t, const size_t *idx, size_t n, float *out,
                                     nbrdf_error *err) {
  const size_t D = (size_t)nbrdf_model_latent_dim(model);
  float *p0 = malloc(sizeof(float) * n * 4);
  float *lat = malloc(sizeof(float) * n * (D * 3 + 4));
  if (!p0 || !lat) {
    free(p0);
    free(lat);
    return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for %zu tuples", n);
  }
  float *p1 = p0 + n, *q0 = p0 + 2 * n, *q1 = p0 + 3 * n;
  float *top = lat, *bottom = top + n * D, *layered = bottom + n * D;
  float *albedo = layered + n * D, *sigma_t = albedo + n, *sigma = sigma_t + n, *w = sigma + n;
  for (size_t k = 0; k < n; k++) {
    const float *p = t[idx ? idx[k] : k].p;
    p0[k] = p[NBRDF_BAKE_ALPHA1], p1[k] = p[NBRDF_BAKE_ETA];
    q0[k] = p[NBRDF_BAKE_ALPHA2], q1[k] = p[NBRDF_BAKE_R0];
    albedo[k] = p[NBRDF_BAKE_ALBEDO], sigma_t[k] = p[NBRDF_BAKE_SIGMA_T];
  }
  /* Values are already inside the grids (model_material_prepare), so CLAMP never moves them. */
  nbrdf_status st = nbrdf_model_base_latents(model, NBRDF_BASE_DIELECTRIC, n, p0, p1,
                                             NBRDF_RANGE_CLAMP, top, NULL, err);
  if (st == NBRDF_OK)
    st = nbrdf_model_base_latents(model, NBRDF_BASE_CONDUCTOR, n, q0, q1, NBRDF_RANGE_CLAMP, bottom,
                                  NULL, err);
  if (st == NBRDF_OK && gpu)
    st = networks_gpu(model, gpu, n, top, bottom, albedo, sigma_t, layered, sigma, w, err);
  else if (st == NBRDF_OK) {
    st = nbrdf_model_layer(model, n, top, bottom, albedo, sigma_t, layered, err);
    if (st == NBRDF_OK) st = nbrdf_model_proxy_params(model, n, layered, sigma, w, err);
  }
  if (st == NBRDF_OK) {
    for (size_t k = 0; k < n; k++) {
      float *o = out + (idx ? idx[k] : k) * (D + 2);
      memcpy(o, layered + k * D, sizeof(float) * D);
      o[D] = sigma[k];
      o[D + 1] = w[k];
    }
  }
  free(p0);
  free(lat);
  return st;
}
