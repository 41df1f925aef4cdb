#include "model/sampler.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "model/proxy.h"

const char *const model_sampler_presets[] = {"default", NULL};

nbrdf_status model_sampler_spec(const char *preset, int latent_dim, nn_spec *spec,
                                nbrdf_error *err) {
  if (latent_dim < 1 || latent_dim > 4096)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "sampler: latent dimension %d, expected 1..4096",
                     latent_dim);
  if (strcmp(preset, "default") != 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "unknown sampler preset '%s' (default)", preset);
  return nn_spec_resmlp(spec, latent_dim, 64, 2, 0, 2, err);
}

static nbrdf_status wrap(const char *preset, int latent_dim, nn_network *nn, model_sampler **out,
                         nbrdf_error *err) {
  model_sampler *net = calloc(1, sizeof *net);
  if (!net) {
    nn_destroy(nn);
    return core_fail(err, NBRDF_ERR_MEMORY, "sampler: out of memory");
  }
  snprintf(net->preset, sizeof net->preset, "%s", preset);
  net->latent_dim = latent_dim;
  net->nn = nn;
  *out = net;
  return NBRDF_OK;
}

nbrdf_status model_sampler_create(const char *preset, int latent_dim, uint64_t seed,
                                  model_sampler **out, nbrdf_error *err) {
  nn_spec spec;
  nn_network *nn = NULL;
  nbrdf_status st = model_sampler_spec(preset, latent_dim, &spec, err);
  if (st == NBRDF_OK) st = nn_create(&spec, &nn, err);
  if (st != NBRDF_OK) return st;
  nn_init_params(nn, seed);
  return wrap(preset, latent_dim, nn, out, err);
}

void model_sampler_destroy(model_sampler *net) {
  if (!net) return;
  nn_destroy(net->nn);
  free(net);
}

void model_sampler_transform(const float o[2], float *sigma, float *w, float *dsigma_do0,
                             float *dw_do1) {
  double a = o[0], b = o[1];
  /* softplus(a) = log(1 + e^a), evaluated without overflow; its derivative is sigmoid(a). */
  double softplus = a > 30.0 ? a : log1p(exp(a));
  double sig_a = 1.0 / (1.0 + exp(-a));
  double sig_b = 1.0 / (1.0 + exp(-b));
  *sigma = (float)(MODEL_PROXY_SIGMA_MIN + softplus);
  *w = (float)sig_b;
  if (dsigma_do0) *dsigma_do0 = (float)sig_a;
  if (dw_do1) *dw_do1 = (float)(sig_b * (1.0 - sig_b));
}

nbrdf_status model_sampler_eval(const model_sampler *net, model_runner *runner, size_t n,
                                const float *latents, float *sigma, float *w, nbrdf_error *err) {
  size_t d = (size_t)net->latent_dim, chunk = (size_t)runner->max_batch;
  for (size_t k0 = 0; k0 < n; k0 += chunk) {
    size_t m = n - k0 < chunk ? n - k0 : chunk;
    nbrdf_status st = model_runner_forward(net->nn, runner, latents + k0 * d, (int)m, runner->y, err);
    if (st != NBRDF_OK) return st;
    for (size_t k = 0; k < m; k++)
      model_sampler_transform(runner->y + 2 * k, sigma + k0 + k, w + k0 + k, NULL, NULL);
  }
  return NBRDF_OK;
}

nbrdf_status model_sampler_save(const model_sampler *net, const char *path, uint64_t *checksum,
                                nbrdf_error *err) {
  nn_st_writer *w = NULL;
  char sigma_min[32];
  snprintf(sigma_min, sizeof sigma_min, "%.17g", MODEL_PROXY_SIGMA_MIN);
  nbrdf_status st = model_net_writer(net->nn, "sampler", net->latent_dim, &w, err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.sigma_min", sigma_min, err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.preset", net->preset, err);
  if (st == NBRDF_OK) st = nn_st_writer_save(w, path, checksum, err);
  nn_st_writer_destroy(w);
  return st;
}

nbrdf_status model_sampler_read(const nn_st_reader *reader, model_sampler **out, nbrdf_error *err) {
  const char *label = nn_st_label(reader);
  double sigma_min = 0.0;
  nbrdf_status st = model_net_check_kind(reader, "sampler", err);
  if (st == NBRDF_OK) st = model_meta_double(reader, "nbrdf.sigma_min", 0.0, 1.0, &sigma_min, err);
  if (st == NBRDF_OK && sigma_min != MODEL_PROXY_SIGMA_MIN)
    st = core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: sigma_min %g differs from this build's %g",
                   label, sigma_min, MODEL_PROXY_SIGMA_MIN);
  nn_network *nn = NULL;
  int dim = 0;
  if (st == NBRDF_OK) st = model_net_read(reader, "sampler", &nn, &dim, err);
  if (st != NBRDF_OK) return st;
  if (nn_inputs(nn) != dim || nn_outputs(nn) != 2) {
    st = core_fail(err, NBRDF_ERR_MISMATCH,
                   "%s: sampling network maps %d inputs to %d outputs; expected %d -> 2", label,
                   nn_inputs(nn), nn_outputs(nn), dim);
    nn_destroy(nn);
    return st;
  }
  const char *preset = nn_st_metadata_get(reader, "nbrdf.preset");
  return wrap(preset ? preset : "custom", dim, nn, out, err);
}
