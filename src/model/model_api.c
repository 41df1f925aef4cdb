/* The public calls of include/nbrdf/model.h on a loaded bundle: argument
 * checks, scratch buffers per call (a model is shared between threads), and
 * the internal networks. */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "model/autodecoder.h"
#include "model/bundle.h"
#include "model/proxy.h"

#define API_BATCH 4096

/* A model decoding a compact texture (issue 19) reads fewer latents than the
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

static nbrdf_status check_directions(size_t n, const float *wi, const float *wo, nbrdf_error *err) {
  for (size_t k = 0; k < n; k++) {
    nbrdf_status st = check_direction(wi + 3 * k, "wi", k, err);
    if (st == NBRDF_OK) st = check_direction(wo + 3 * k, "wo", k, err);
    if (st != NBRDF_OK) return st;
  }
  return NBRDF_OK;
}

static nbrdf_status check_finite(const float *x, size_t count, const char *what, nbrdf_error *err) {
  for (size_t k = 0; k < count; k++)
    if (!isfinite(x[k]))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: value %zu is not finite", what, k);
  return NBRDF_OK;
}

static int batch_for(size_t rows, int multiple) {
  size_t b = rows < API_BATCH ? rows : API_BATCH;
  if (b < (size_t)multiple) b = (size_t)multiple;
  return (int)b;
}

nbrdf_status nbrdf_model_decode(const nbrdf_model *m, size_t n, int channels, const float *latents,
                                const float *wi, const float *wo, float *f, nbrdf_error *err) {
  if (channels < 1 || channels > 64)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "decode: %d channels, expected 1..64", channels);
  if (n == 0) return NBRDF_OK;
  nbrdf_status st = check_directions(n, wi, wo, err);
  if (st == NBRDF_OK)
    st = check_finite(latents, n * (size_t)channels * (size_t)m->latent_dim, "decode latents", err);
  if (st != NBRDF_OK) return st;
  model_runner runner;
  st = model_runner_create(m->decoder->nn, batch_for(n * (size_t)channels, channels),
                           NBRDF_NN_INFER, &runner, err);
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
  nbrdf_status st = check_finite(top, count, "layer: top latents", err);
  if (st == NBRDF_OK) st = check_finite(bottom, count, "layer: bottom latents", err);
  if (st != NBRDF_OK) return st;
  model_runner runner;
  st = model_runner_create(m->layering->nn, batch_for(n, 1), NBRDF_NN_INFER, &runner, err);
  if (st == NBRDF_OK)
    st = model_layering_eval(m->layering, &runner, n, top, bottom, albedo, sigma_t, out, err);
  model_runner_destroy(&runner);
  return st;
}

nbrdf_status nbrdf_model_proxy_params(const nbrdf_model *m, size_t n, const float *latents,
                                      float *sigma, float *w, nbrdf_error *err) {
  nbrdf_status st = check_full_latents(m, "proxy", err);
  if (st != NBRDF_OK || n == 0) return st;
  st = check_finite(latents, n * (size_t)m->latent_dim, "proxy: latents", err);
  if (st != NBRDF_OK) return st;
  model_runner runner;
  st = model_runner_create(m->sampler->nn, batch_for(n, 1), NBRDF_NN_INFER, &runner, err);
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

static nbrdf_status check_projection(size_t n_brdfs, const size_t *offsets, const float *wi,
                                     const float *wo, const float *f,
                                     const nbrdf_project_options *o, nbrdf_error *err) {
  if (n_brdfs < 1) return core_fail(err, NBRDF_ERR_ARGUMENT, "project: no BRDF given");
  if (offsets[0] != 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "project: offsets[0] = %zu, expected 0", offsets[0]);
  for (size_t b = 0; b < n_brdfs; b++)
    if (offsets[b + 1] <= offsets[b])
      return core_fail(err, NBRDF_ERR_ARGUMENT, "project: BRDF %zu has no samples", b);
  size_t rows = offsets[n_brdfs];
  nbrdf_status st = check_directions(rows, wi, wo, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "project: ");
    return st;
  }
  for (size_t r = 0; r < rows; r++)
    if (!(f[r] >= 0.0f) || !isfinite(f[r]))
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "project: f of sample %zu = %g is not finite and >= 0", r, f[r]);
  if (o->steps < 0 || o->rows_per_brdf < 1 || !(o->learning_rate > 0.0f) ||
      !isfinite(o->learning_rate) || (o->loss != NBRDF_LOSS_L1 && o->loss != NBRDF_LOSS_L1_LOG1P))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "project: options need steps >= 0, rows_per_brdf >= 1, a learning rate > 0 "
                     "and a known loss");
  return NBRDF_OK;
}

nbrdf_status nbrdf_model_project(const nbrdf_model *m, size_t n_brdfs, const size_t *offsets,
                                 const float *wi, const float *wo, const float *f,
                                 const nbrdf_project_options *options, float *out,
                                 double *final_loss, nbrdf_error *err) {
  nbrdf_project_options defaults = NBRDF_PROJECT_OPTIONS_DEFAULT;
  const nbrdf_project_options *o = options ? options : &defaults;
  nbrdf_status st = check_projection(n_brdfs, offsets, wi, wo, f, o, err);
  if (st != NBRDF_OK) return st;
  size_t count = n_brdfs * (size_t)m->latent_dim;
  if (o->init_from_out) {
    st = check_finite(out, count, "project: initial latents", err);
    if (st != NBRDF_OK) return st;
  } else {
    for (size_t k = 0; k < count; k++)
      out[k] = 0.0f;
  }
  model_fit_options fo = MODEL_FIT_OPTIONS_DEFAULT;
  fo.loss = o->loss == NBRDF_LOSS_L1 ? MODEL_LOSS_L1 : MODEL_LOSS_L1_LOG1P;
  fo.rows_per_brdf = o->rows_per_brdf;
  fo.lr_latent = o->learning_rate;
  fo.lr_weights = 0.0f; /* frozen: the fit never writes the decoder, so sharing it is safe */
  fo.seed = o->seed;
  fo.max_batch = batch_for(n_brdfs * (size_t)o->rows_per_brdf, 1);
  model_samples samples = {n_brdfs, offsets, wi, wo, f, NULL};
  model_fit *fit = NULL;
  nn_adam *adam = NULL;
  /* The smallest loop over the gradient engine: in memory, no schedule, no
   * checkpoint (src/train/trainer.h is the loop with all of them; the model
   * layer cannot call up into train/). */
  nn_adam_options ao = NBRDF_ADAM_OPTIONS_DEFAULT;
  ao.lr = o->learning_rate;
  st = model_fit_create(m->decoder, n_brdfs, out, &fo, &fit, err);
  if (st == NBRDF_OK) st = nn_adam_create(count, &ao, &adam, err);
  for (int s = 0; st == NBRDF_OK && s < o->steps; s++) {
    st = model_fit_gradient(fit, &samples, s, NULL, err);
    if (st == NBRDF_OK) st = nn_adam_step(adam, out, model_fit_grad_latent(fit), err);
  }
  if (st == NBRDF_OK && final_loss) st = model_fit_eval_loss(fit, &samples, final_loss, NULL, err);
  nn_adam_destroy(adam);
  model_fit_destroy(fit);
  if (st != NBRDF_OK) core_error_prefix(err, "project: ");
  return st;
}
