#include "model/layering.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

const char *const model_layering_presets[] = {"paper", "medium", "small", NULL};

nbrdf_status model_layering_spec(const char *preset, int latent_dim, nn_spec *spec,
                                 nbrdf_error *err) {
  if (latent_dim < 1 || latent_dim > 4096)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "layering: latent dimension %d, expected 1..4096",
                     latent_dim);
  int width, blocks;
  if (!strcmp(preset, "paper"))
    width = 512, blocks = 4;
  else if (!strcmp(preset, "medium"))
    width = 256, blocks = 3;
  else if (!strcmp(preset, "small"))
    width = 128, blocks = 2;
  else
    return core_fail(err, NBRDF_ERR_ARGUMENT, "unknown layering preset '%s' (paper, medium, small)",
                     preset);
  return nn_spec_resmlp(spec, 2 * latent_dim + 2, width, blocks, 0, latent_dim, err);
}

static nbrdf_status wrap(const char *preset, int latent_dim, nn_network *nn, model_layering **out,
                         nbrdf_error *err) {
  model_layering *net = calloc(1, sizeof *net);
  if (!net) {
    nn_destroy(nn);
    return core_fail(err, NBRDF_ERR_MEMORY, "layering: out of memory");
  }
  snprintf(net->preset, sizeof net->preset, "%s", preset);
  net->latent_dim = latent_dim;
  net->nn = nn;
  *out = net;
  return NBRDF_OK;
}

nbrdf_status model_layering_create(const char *preset, int latent_dim, uint64_t seed,
                                   model_layering **out, nbrdf_error *err) {
  nn_spec spec;
  nn_network *nn = NULL;
  nbrdf_status st = model_layering_spec(preset, latent_dim, &spec, err);
  if (st == NBRDF_OK) st = nn_create(&spec, &nn, err);
  if (st != NBRDF_OK) return st;
  nn_init_params(nn, seed);
  return wrap(preset, latent_dim, nn, out, err);
}

void model_layering_destroy(model_layering *net) {
  if (!net) return;
  nn_destroy(net->nn);
  free(net);
}

float model_layering_sigma_t_input(float sigma_t) { return log1pf(sigma_t); }

void model_layering_fill_inputs(const model_layering *net, size_t n, const float *top,
                                const float *bottom, const float *albedo, const float *sigma_t,
                                float *x) {
  size_t d = (size_t)net->latent_dim, in = 2 * d + 2;
  for (size_t k = 0; k < n; k++) {
    float *row = x + k * in;
    memcpy(row, top + k * d, d * sizeof(float));
    memcpy(row + d, bottom + k * d, d * sizeof(float));
    row[2 * d] = albedo[k];
    row[2 * d + 1] = model_layering_sigma_t_input(sigma_t[k]);
  }
}

nbrdf_status model_layering_eval(const model_layering *net, model_runner *runner, size_t n,
                                 const float *top, const float *bottom, const float *albedo,
                                 const float *sigma_t, float *out, nbrdf_error *err) {
  size_t d = (size_t)net->latent_dim, chunk = (size_t)runner->max_batch;
  for (size_t k0 = 0; k0 < n; k0 += chunk) {
    size_t m = n - k0 < chunk ? n - k0 : chunk;
    model_layering_fill_inputs(net, m, top + k0 * d, bottom + k0 * d, albedo + k0, sigma_t + k0,
                               runner->x);
    nbrdf_status st = model_runner_forward(net->nn, runner, runner->x, (int)m, out + k0 * d, err);
    if (st != NBRDF_OK) return st;
  }
  return NBRDF_OK;
}

nbrdf_status model_layering_save(const model_layering *net, const char *path, uint64_t *checksum,
                                 nbrdf_error *err) {
  nn_st_writer *w = NULL;
  nbrdf_status st = model_net_writer(net->nn, "layering", net->latent_dim, &w, err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.sigma_t_input", "log1p", err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.preset", net->preset, err);
  if (st == NBRDF_OK) st = nn_st_writer_save(w, path, checksum, err);
  nn_st_writer_destroy(w);
  return st;
}

nbrdf_status model_layering_read(const nn_st_reader *reader, model_layering **out,
                                 nbrdf_error *err) {
  const char *label = nn_st_label(reader), *cond = NULL;
  nbrdf_status st = model_net_check_kind(reader, "layering", err);
  if (st == NBRDF_OK) st = nn_st_metadata_require(reader, "nbrdf.sigma_t_input", &cond, err);
  if (st == NBRDF_OK && strcmp(cond, "log1p") != 0)
    st = core_fail(err, NBRDF_ERR_UNSUPPORTED,
                   "%s: sigma_t input \"%s\" is not supported (only \"log1p\")", label, cond);
  nn_network *nn = NULL;
  int dim = 0;
  if (st == NBRDF_OK) st = model_net_read(reader, "layering", &nn, &dim, err);
  if (st != NBRDF_OK) return st;
  if (nn_inputs(nn) != 2 * dim + 2 || nn_outputs(nn) != dim) {
    st = core_fail(err, NBRDF_ERR_MISMATCH,
                   "%s: layering network maps %d inputs to %d outputs; latent dimension %d "
                   "needs %d -> %d",
                   label, nn_inputs(nn), nn_outputs(nn), dim, 2 * dim + 2, dim);
    nn_destroy(nn);
    return st;
  }
  const char *preset = nn_st_metadata_get(reader, "nbrdf.preset");
  return wrap(preset ? preset : "custom", dim, nn, out, err);
}
