/* The public calls of include/nbrdf/model.h on a loaded bundle: argument
 * checks, scratch buffers per call (a model is shared between threads), and
 * the internal networks. Projection fits latents, so it runs in the trainer:
 * nbrdf_model_project is in src/train/project_api.c, with these checks
 * (model/api_checks.h). */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "model/api_checks.h"
#include "model/bundle.h"
#include "model/model_gpu.h"
#include "model/proxy.h"

/* A model decoding a compact texture (docs/BAKE.md) reads fewer latents than the
 * bundle's tables, layering and sampling networks write. */
static nbrdf_status check_full_latents(const nbrdf_model *m, const char *what, nbrdf_error *err) {
  if (!m->parent || m->latent_dim == m->parent->latent_dim) return NBRDF_OK;
  return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                   "%s: this model decodes a compact texture's %d latent channels; %s works on "
                   "the bundle's %d-float latents (use the bundle itself)",
                   what, m->latent_dim, what, m->parent->latent_dim);
}

static nbrdf_status check_direction(const float *w, const char *name, size_t k, nbrdf_error *err) {
  double x = w[0], y = w[1], z = w[2];
  if (!isfinite(x) || !isfinite(y) || !isfinite(z))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s of query %zu is not finite", name, k);
  if (fabs(sqrt(x * x + y * y + z * z) - 1.0) > 1e-3)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s of query %zu is not a unit vector", name, k);
  if (!(z > 0.0))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s of query %zu is at or below the horizon (z = %g)",
                     name, k, z);
  return NBRDF_OK;
}

nbrdf_status model_check_directions(size_t n, const float *wi, const float *wo, nbrdf_error *err) {
  for (size_t k = 0; k < n; k++) {
    nbrdf_status st = check_direction(wi + 3 * k, "wi", k, err);
    if (st == NBRDF_OK) st = check_direction(wo + 3 * k, "wo", k, err);
    if (st != NBRDF_OK) return st;
  }
  return NBRDF_OK;
}

nbrdf_status model_check_finite(const float *x, size_t count, const char *what, nbrdf_error *err) {
  for (size_t k = 0; k < count; k++)
    if (!isfinite(x[k]))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: value %zu is not finite", what, k);
  return NBRDF_OK;
}

int model_batch_for(size_t rows, int multiple) {
  size_t b = rows < MODEL_API_BATCH ? rows : MODEL_API_BATCH;
  if (b < (size_t)multiple) b = (size_t)multiple;
  return (int)b;
}

nbrdf_status nbrdf_model_decode(const nbrdf_model *m, size_t n, int channels, const float *latents,
                                const float *wi, const float *wo, float *f, nbrdf_error *err) {
  return model_decode_on(m, NULL, n, channels, latents, wi, wo, f, err);
}

nbrdf_status model_decode_on(const nbrdf_model *m, struct gpu_network *gpu, size_t n, int channels,
                             const float *latents, const float *wi, const float *wo, float *f,
                             nbrdf_error *err) {
  if (channels < 1 || channels > 64)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "decode: %d channels, expected 1..64", channels);
  if (n == 0) return NBRDF_OK;
  nbrdf_status st = model_check_directions(n, wi, wo, err);
  if (st == NBRDF_OK)
    st = model_check_finite(latents, n * (size_t)channels * (size_t)m->latent_dim, "decode latents",
                            err);
  if (st != NBRDF_OK) return st;
  model_runner runner;
  /* A GPU takes the whole call in one batch (it streams its own chunks). */
  size_t rows = n * (size_t)channels;
  st = gpu ? model_gpu_runner(gpu, rows < (1u << 20) ? (int)rows : (1 << 20), &runner, err)
           : model_runner_create(m->decoder->nn, model_batch_for(rows, channels), NBRDF_NN_INFER,
                                 &runner, err);
  if (st == NBRDF_OK)
    st = model_decoder_eval(m->decoder, &runner, n, channels, latents, wi, wo, f, err);
  model_runner_destroy(&runner);
  return st;
}

nbrdf_status nbrdf_model_base_latents(const nbrdf_model *m, nbrdf_base_kind kind, size_t n,
                                      const float *p0, const float *p1, nbrdf_range_policy policy,
                                      float *out, unsigned char *clamped, nbrdf_error *err) {
  if (kind != NBRDF_BASE_DIELECTRIC && kind != NBRDF_BASE_CONDUCTOR)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "base latents: unknown base kind %d", (int)kind);
  nbrdf_status full = check_full_latents(m, "base latents", err);
  if (full != NBRDF_OK) return full;
  /* Parameters are floats everywhere in the public API (as nbrdf_model_layer's); the table
   * look-up interpolates in double, as training's does. In chunks: no allocation. */
  enum { CHUNK = 256 };
  double q0[CHUNK], q1[CHUNK];
  const size_t D = (size_t)m->latent_dim;
  for (size_t k0 = 0; k0 < n; k0 += CHUNK) {
    size_t c = n - k0 < CHUNK ? n - k0 : CHUNK;
    for (size_t k = 0; k < c; k++)
      q0[k] = p0[k0 + k], q1[k] = p1[k0 + k];
    nbrdf_status st =
        model_base_table_lookup(&m->tables[kind], c, q0, q1, policy == NBRDF_RANGE_REFUSE,
                                out + k0 * D, clamped ? clamped + k0 : NULL, err);
    if (st != NBRDF_OK) return st;
  }
  return NBRDF_OK;
}

nbrdf_status nbrdf_model_layer(const nbrdf_model *m, size_t n, const float *top,
                               const float *bottom, const float *albedo, const float *sigma_t,
                               float *out, nbrdf_error *err) {
  nbrdf_status full = check_full_latents(m, "layer", err);
  if (full != NBRDF_OK) return full;
  if (n == 0) return NBRDF_OK;
  for (size_t k = 0; k < n; k++) {
    if (!(albedo[k] >= 0.0f && albedo[k] <= 1.0f))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "layer: albedo = %g (query %zu) is outside [0, 1]",
                       albedo[k], k);
    if (!(sigma_t[k] >= 0.0f) || !isfinite(sigma_t[k]))
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "layer: sigma_t = %g (query %zu) is not finite and >= 0", sigma_t[k], k);
  }
  size_t count = n * (size_t)m->latent_dim;
  nbrdf_status st = model_check_finite(top, count, "layer: top latents", err);
  if (st == NBRDF_OK) st = model_check_finite(bottom, count, "layer: bottom latents", err);
  if (st != NBRDF_OK) return st;
  model_runner runner;
  st = model_runner_create(m->layering->nn, model_batch_for(n, 1), NBRDF_NN_INFER, &runner, err);
  if (st == NBRDF_OK)
    st = model_layering_eval(m->layering, &runner, n, top, bottom, albedo, sigma_t, out, err);
  model_runner_destroy(&runner);
  return st;
}

nbrdf_status nbrdf_model_proxy_params(const nbrdf_model *m, size_t n, const float *latents,
                                      float *sigma, float *w, nbrdf_error *err) {
  nbrdf_status st = check_full_latents(m, "proxy", err);
  if (st != NBRDF_OK || n == 0) return st;
  st = model_check_finite(latents, n * (size_t)m->latent_dim, "proxy: latents", err);
  if (st != NBRDF_OK) return st;
  model_runner runner;
  st = model_runner_create(m->sampler->nn, model_batch_for(n, 1), NBRDF_NN_INFER, &runner, err);
  if (st == NBRDF_OK) st = model_sampler_eval(m->sampler, &runner, n, latents, sigma, w, err);
  model_runner_destroy(&runner);
  return st;
}

double nbrdf_proxy_pdf(double sigma, double w, const double wi[3], const double wo[3]) {
  return model_proxy_pdf(sigma, w, v3(wi[0], wi[1], wi[2]), v3(wo[0], wo[1], wo[2]));
}

int nbrdf_proxy_sample(double sigma, double w, const double wi[3], const double u[3], double wo[3],
                       double *pdf) {
  vec3 d;
  int ok = model_proxy_sample(sigma, w, v3(wi[0], wi[1], wi[2]), u[0], u[1], u[2], &d, pdf);
  wo[0] = d.x, wo[1] = d.y, wo[2] = d.z;
  return ok;
}
