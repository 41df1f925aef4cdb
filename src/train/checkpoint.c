#include "train/checkpoint.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

void train_checkpoint_data_key(const train_samples *data, char *out, size_t size) {
  size_t at = 0;
  out[0] = '\0';
  for (int i = 0; i < data->n_files && at + 18 < size; i++)
    at += (size_t)snprintf(out + at, size - at, "%s%016" PRIx64, i ? "," : "", data->checksums[i]);
}

static nbrdf_status add(nbrdf_st_writer *w, const char *name, size_t n, const float *x,
                        nbrdf_error *err) {
  int64_t shape[1] = {(int64_t)n};
  return nbrdf_st_writer_add_borrowed(w, name, 1, shape, x, err);
}

nbrdf_status train_checkpoint_save(const char *path, const model_decoder *dec, model_fit *fit,
                                   const float *latents, size_t n_brdfs, const train_samples *data,
                                   nbrdf_error *err) {
  nbrdf_st_writer *w = NULL;
  char *spec = NULL, step[32], key[1024];
  nbrdf_status st = nbrdf_st_writer_create(&w, err);
  if (!st) st = nbrdf_nn_spec_to_json(&dec->cfg.spec, &spec, err);
  size_t p = nbrdf_nn_param_count(dec->nn), nl = n_brdfs * (size_t)dec->cfg.latent_dim;
  nbrdf_adam *al = model_fit_adam(fit, 0), *aw = model_fit_adam(fit, 1);
  snprintf(step, sizeof step, "%" PRId64, model_fit_steps(fit));
  train_checkpoint_data_key(data, key, sizeof key);
  if (!st) st = nbrdf_st_writer_set_metadata(w, "nbrdf.format", TRAIN_CHECKPOINT_FORMAT, err);
  if (!st) st = nbrdf_st_writer_set_metadata(w, "nbrdf.spec", spec, err);
  if (!st) st = nbrdf_st_writer_set_metadata(w, "nbrdf.step", step, err);
  if (!st) st = nbrdf_st_writer_set_metadata(w, "nbrdf.data", key, err);
  if (!st) st = add(w, "decoder.params", p, nbrdf_nn_params_const(dec->nn), err);
  if (!st) st = add(w, "latents", nl, latents, err);
  if (!st) st = add(w, "adam.latents.m", nl, nbrdf_adam_moment(al, 0), err);
  if (!st) st = add(w, "adam.latents.v", nl, nbrdf_adam_moment(al, 1), err);
  if (!st && aw) st = add(w, "adam.weights.m", p, nbrdf_adam_moment(aw, 0), err);
  if (!st && aw) st = add(w, "adam.weights.v", p, nbrdf_adam_moment(aw, 1), err);
  if (!st) st = nbrdf_st_writer_save(w, path, NULL, err);
  free(spec);
  nbrdf_st_writer_destroy(w);
  return st;
}

static nbrdf_status take(const nbrdf_st_reader *r, const char *name, size_t n, float *dst,
                         nbrdf_error *err) {
  int64_t shape[1] = {(int64_t)n};
  return nbrdf_st_expect_copy(r, name, 1, shape, dst, err);
}

static nbrdf_status require(const nbrdf_st_reader *r, const char *k, const char *want,
                            const char *what, nbrdf_error *err) {
  const char *v = nbrdf_st_metadata_get(r, k);
  if (v && !strcmp(v, want)) return NBRDF_OK;
  return nbrdf_fail(err, NBRDF_ERR_MISMATCH,
                    "%s: the checkpoint was made with another %s than this run's (start a new "
                    "run folder, or give the same settings)",
                    nbrdf_st_label(r), what);
}

nbrdf_status train_checkpoint_load(const char *path, model_decoder *dec, model_fit *fit,
                                   float *latents, size_t n_brdfs, const train_samples *data,
                                   int64_t *step, nbrdf_error *err) {
  nbrdf_st_reader *r = NULL;
  char *spec = NULL, key[1024];
  nbrdf_status st = nbrdf_st_open(path, &r, err);
  if (st) return st;
  size_t p = nbrdf_nn_param_count(dec->nn), nl = n_brdfs * (size_t)dec->cfg.latent_dim;
  nbrdf_adam *al = model_fit_adam(fit, 0), *aw = model_fit_adam(fit, 1);
  train_checkpoint_data_key(data, key, sizeof key);
  st = require(r, "nbrdf.format", TRAIN_CHECKPOINT_FORMAT, "file format", err);
  if (!st) st = nbrdf_nn_spec_to_json(&dec->cfg.spec, &spec, err);
  if (!st) st = require(r, "nbrdf.spec", spec, "decoder architecture", err);
  if (!st) st = require(r, "nbrdf.data", key, "data sets", err);
  const char *s = nbrdf_st_metadata_get(r, "nbrdf.step");
  char *end = NULL;
  long long k = s ? strtoll(s, &end, 10) : -1;
  if (!st && (!s || *end || k < 0))
    st = nbrdf_fail(err, NBRDF_ERR_FORMAT, "%s: no valid nbrdf.step", path);
  if (!st) st = take(r, "decoder.params", p, nbrdf_nn_params(dec->nn), err);
  if (!st) st = take(r, "latents", nl, latents, err);
  if (!st) st = take(r, "adam.latents.m", nl, nbrdf_adam_moment(al, 0), err);
  if (!st) st = take(r, "adam.latents.v", nl, nbrdf_adam_moment(al, 1), err);
  if (!st && aw) st = take(r, "adam.weights.m", p, nbrdf_adam_moment(aw, 0), err);
  if (!st && aw) st = take(r, "adam.weights.v", p, nbrdf_adam_moment(aw, 1), err);
  if (!st) {
    model_fit_set_steps(fit, (int64_t)k);
    *step = (int64_t)k;
  }
  free(spec);
  nbrdf_st_close(r);
  return st;
}
