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
#include "model/param_conventions.h"

void bake_ranges_init(const nbrdf_model *model, float lo[NBRDF_BAKE_PARAM_COUNT],
                      float hi[NBRDF_BAKE_PARAM_COUNT]) {
  int n0, n1;
  const float *a0, *a1;
  nbrdf_model_base_grid(model, NBRDF_BASE_DIELECTRIC, &n0, &a0, &n1, &a1);
  lo[NBRDF_BAKE_ALPHA1] = a0[0], hi[NBRDF_BAKE_ALPHA1] = a0[n0 - 1];
  lo[NBRDF_BAKE_ETA] = a1[0], hi[NBRDF_BAKE_ETA] = a1[n1 - 1];
  nbrdf_model_base_grid(model, NBRDF_BASE_CONDUCTOR, &n0, &a0, &n1, &a1);
  lo[NBRDF_BAKE_ALPHA2] = a0[0], hi[NBRDF_BAKE_ALPHA2] = a0[n0 - 1];
  lo[NBRDF_BAKE_R0] = a1[0], hi[NBRDF_BAKE_R0] = a1[n1 - 1];
  lo[NBRDF_BAKE_ALBEDO] = 0.0f, hi[NBRDF_BAKE_ALBEDO] = 1.0f;
  lo[NBRDF_BAKE_SIGMA_T] = 0.0f, hi[NBRDF_BAKE_SIGMA_T] = NBRDF_BAKE_SIGMA_T_MAX;
}

bake_verdict bake_value_prepare(const float *lo, const float *hi, int id, nbrdf_roughness roughness,
                                nbrdf_range_policy range, float *v) {
  return bake_value_prepare_read(lo, hi, id, roughness, range, v, NULL);
}

bake_verdict bake_value_prepare_read(const float *lo, const float *hi, int id,
                                     nbrdf_roughness roughness, nbrdf_range_policy range, float *v,
                                     float *read) {
  float x = *v + 0.0f; /* -0 -> +0, so equal tuples have equal bytes */
  if (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2)
    x = (float)model_roughness_alpha(roughness, x);
  *v = x;
  if (read) *read = x;
  if (!isfinite(x) || x < 0.0f) return BAKE_VALUE_INVALID;
  if (x >= lo[id] && x <= hi[id]) return BAKE_VALUE_OK;
  if ((id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO) && x > 1.0f) return BAKE_VALUE_UNPHYSICAL;
  if (range == NBRDF_RANGE_REFUSE) return BAKE_VALUE_OUTSIDE;
  *v = x < lo[id] ? lo[id] : hi[id];
  return BAKE_VALUE_CLAMPED;
}

nbrdf_status bake_value_fail(bake_verdict verdict, const float *lo, const float *hi, int id,
                             nbrdf_roughness roughness, const char *at, float typed,
                             nbrdf_error *err) {
  if (roughness == NBRDF_ROUGHNESS_PERCEPTUAL &&
      (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2)) {
    double a = model_roughness_alpha(roughness, typed);
    if (verdict == BAKE_VALUE_INVALID)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "%s = %g (perceptual roughness r; alpha = r^2 = %g) is not a finite "
                       "value >= 0",
                       at, (double)typed, a);
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s = %g (perceptual roughness r; alpha = r^2 = %g) is outside the "
                     "model's trained range: r in [%g, %g] (alpha in [%g, %g])",
                     at, (double)typed, a, sqrt((double)lo[id]), sqrt((double)hi[id]),
                     (double)lo[id], (double)hi[id]);
  }
  if (verdict == BAKE_VALUE_INVALID)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = %g is not a finite value >= 0", at,
                     (double)typed);
  if (verdict == BAKE_VALUE_UNPHYSICAL)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = %g is above 1 (not physical)", at,
                     (double)typed);
  return core_fail(err, NBRDF_ERR_ARGUMENT, "%s = %g is outside the model's trained range [%g, %g]",
                   at, (double)typed, (double)lo[id], (double)hi[id]);
}

/* Quantisation levels are spaced evenly where the parameter's effect is
 * about even: alpha in sqrt (perceptual roughness; linear steps would be
 * 40 % of alpha = 0.01 at 8 bits), sigma_t in log(1 + sigma_t) (as the
 * layering network sees it), the rest linearly. The ends of the range are
 * levels, so quantised values stay inside it. */
static float warp(int id, float v) {
  if (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2) return sqrtf(v);
  if (id == NBRDF_BAKE_SIGMA_T) return model_layering_sigma_t_input(v);
  return v;
}

static float unwarp(int id, float u) {
  if (id == NBRDF_BAKE_ALPHA1 || id == NBRDF_BAKE_ALPHA2) return u * u;
  if (id == NBRDF_BAKE_SIGMA_T) return expm1f(u);
  return u;
}

float bake_value_normalise(const float *lo_, const float *hi_, int id, float v) {
  float lo = warp(id, lo_[id]), hi = warp(id, hi_[id]);
  return hi > lo ? (warp(id, v) - lo) / (hi - lo) : 0.0f;
}

float bake_value_quantise(const float *lo_, const float *hi_, int id, int bits, float v) {
  float lo = warp(id, lo_[id]), hi = warp(id, hi_[id]);
  if (!(hi > lo)) return v;
  float steps = (float)((1u << bits) - 1);
  float q = roundf((warp(id, v) - lo) / (hi - lo) * steps);
  float r = unwarp(id, lo + (hi - lo) * q / steps);
  /* keep the ends exact (sqrt/square and log1p/expm1 round) */
  return q <= 0 ? lo_[id] : q >= steps ? hi_[id] : r;
}

void bake_clamp_warning(char *buf, size_t cap, const char *name, const float *lo, const float *hi,
                        int id, const char *what, int plural) {
  snprintf(buf, cap, "%s: %s outside the model's trained range [%g, %g] %s clamped", name, what,
           (double)lo[id], (double)hi[id], plural ? "were" : "was");
}

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
  /* Values are already inside the grids (bake_value_prepare), so CLAMP never moves them. */
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
