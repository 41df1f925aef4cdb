#include "model/netio.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/gpu.h"

nbrdf_status model_runner_create(const nn_network *nn, int max_batch, nn_mode mode,
                                 model_runner *runner, nbrdf_error *err) {
  memset(runner, 0, sizeof *runner);
  nbrdf_status st = nn_workspace_create(nn, max_batch, mode, &runner->ws, err);
  if (st != NBRDF_OK) return st;
  runner->max_batch = max_batch;
  runner->x = malloc(sizeof(float) * (size_t)max_batch * (size_t)nn_inputs(nn));
  runner->y = malloc(sizeof(float) * (size_t)max_batch * (size_t)nn_outputs(nn));
  if (!runner->x || !runner->y) {
    model_runner_destroy(runner);
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory for a batch of %d rows", max_batch);
  }
  return NBRDF_OK;
}

void model_runner_destroy(model_runner *runner) {
  nn_workspace_destroy(runner->ws);
  free(runner->x);
  free(runner->y);
  memset(runner, 0, sizeof *runner);
}

nbrdf_status model_runner_forward(const nn_network *nn, model_runner *runner, const float *x,
                                  int rows, float *y, nbrdf_error *err) {
  if (runner->gpu) return gpu_network_forward(runner->gpu, x, (size_t)rows, y, err);
  return nn_forward(nn, runner->ws, x, rows, y, err);
}

nbrdf_status model_net_writer(const nn_network *nn, const char *network, int latent_dim,
                              nn_st_writer **out, nbrdf_error *err) {
  nn_st_writer *w = NULL;
  char *spec_json = NULL;
  nbrdf_status st = nn_st_writer_create(&w, err);
  if (st == NBRDF_OK) st = nn_spec_to_json(nn_get_spec(nn), &spec_json, err);
  const float *params = nn_params_const(nn);
  for (int i = 0; st == NBRDF_OK && i < nn_tensor_count(nn); i++) {
    const nn_tensor *t = nn_tensor_at(nn, i);
    int64_t shape[2] = {t->rows, t->cols};
    st = nn_st_writer_add_borrowed(w, t->name, t->rank, shape, params + t->offset, err);
  }
  char dim[32];
  snprintf(dim, sizeof dim, "%d", latent_dim);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.format", MODEL_NET_FORMAT, err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.version", MODEL_NET_VERSION, err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.network", network, err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.spec", spec_json, err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.latent_dim", dim, err);
  free(spec_json);
  if (st != NBRDF_OK) {
    nn_st_writer_destroy(w);
    return st;
  }
  *out = w;
  return NBRDF_OK;
}

static nbrdf_status require_value(const nn_st_reader *r, const char *key, const char *want,
                                  nbrdf_error *err) {
  const char *v;
  nbrdf_status st = nn_st_metadata_require(r, key, &v, err);
  if (st != NBRDF_OK) return st;
  if (strcmp(v, want) != 0)
    return core_fail(err, NBRDF_ERR_MISMATCH, "%s: metadata %s is \"%s\", expected \"%s\"",
                     nn_st_label(r), key, v, want);
  return NBRDF_OK;
}

nbrdf_status model_meta_int(const nn_st_reader *reader, const char *key, long lo, long hi,
                            long *value, nbrdf_error *err) {
  const char *v;
  nbrdf_status st = nn_st_metadata_require(reader, key, &v, err);
  if (st != NBRDF_OK) return st;
  char *end;
  errno = 0;
  long x = strtol(v, &end, 10);
  if (!*v || *end || errno || x < lo || x > hi)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: metadata %s = \"%s\" is not an integer in [%ld, %ld]",
                     nn_st_label(reader), key, v, lo, hi);
  *value = x;
  return NBRDF_OK;
}

nbrdf_status model_meta_double(const nn_st_reader *reader, const char *key, double lo, double hi,
                               double *value, nbrdf_error *err) {
  const char *v;
  nbrdf_status st = nn_st_metadata_require(reader, key, &v, err);
  if (st != NBRDF_OK) return st;
  char *end;
  errno = 0;
  double x = strtod(v, &end);
  if (!*v || *end || errno || !isfinite(x) || x < lo || x > hi)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: metadata %s = \"%s\" is not a number in [%g, %g]",
                     nn_st_label(reader), key, v, lo, hi);
  *value = x;
  return NBRDF_OK;
}

nbrdf_status model_net_check_kind(const nn_st_reader *reader, const char *network,
                                  nbrdf_error *err) {
  nbrdf_status st = require_value(reader, "nbrdf.format", MODEL_NET_FORMAT, err);
  if (st == NBRDF_OK) st = require_value(reader, "nbrdf.network", network, err);
  return st;
}

nbrdf_status model_net_read(const nn_st_reader *reader, const char *network, nn_network **out,
                            int *latent_dim, nbrdf_error *err) {
  const char *label = nn_st_label(reader);
  nbrdf_status st = model_net_check_kind(reader, network, err);
  if (st == NBRDF_OK) st = require_value(reader, "nbrdf.version", MODEL_NET_VERSION, err);
  long dim = 0;
  if (st == NBRDF_OK) st = model_meta_int(reader, "nbrdf.latent_dim", 1, 4096, &dim, err);
  const char *spec_json = NULL;
  if (st == NBRDF_OK) st = nn_st_metadata_require(reader, "nbrdf.spec", &spec_json, err);
  nn_spec spec;
  if (st == NBRDF_OK) {
    st = nn_spec_from_json(spec_json, &spec, err);
    if (st != NBRDF_OK) core_error_prefix(err, "%s: metadata nbrdf.spec: ", label);
  }
  if (st != NBRDF_OK) return st;

  nn_network *nn = NULL;
  st = nn_create(&spec, &nn, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", label);
    return st;
  }
  float *params = nn_params(nn);
  for (int i = 0; st == NBRDF_OK && i < nn_tensor_count(nn); i++) {
    const nn_tensor *t = nn_tensor_at(nn, i);
    int64_t shape[2] = {t->rows, t->cols};
    st = nn_st_expect_copy(reader, t->name, t->rank, shape, params + t->offset, err);
  }
  if (st == NBRDF_OK && nn_st_tensor_count(reader) != (size_t)nn_tensor_count(nn)) {
    /* Name the first tensor the architecture does not use. */
    const char *extra = "?";
    for (size_t k = 0; k < nn_st_tensor_count(reader); k++) {
      const char *name = nn_st_tensor_at(reader, k)->name;
      if (!nn_find_tensor(nn, name)) {
        extra = name;
        break;
      }
    }
    st = core_fail(
        err, NBRDF_ERR_MISMATCH,
        "%s: %zu tensors, the architecture in nbrdf.spec has %d (e.g. '%s' is not part of it)",
        label, nn_st_tensor_count(reader), nn_tensor_count(nn), extra);
  }
  if (st != NBRDF_OK) {
    nn_destroy(nn);
    return st;
  }
  *latent_dim = (int)dim;
  *out = nn;
  return NBRDF_OK;
}
