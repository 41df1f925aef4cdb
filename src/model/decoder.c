#include "model/decoder.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

const char *const model_decoder_presets[] = {"paper", "large", "medium", "small", NULL};

const char *model_output_name(model_output output) {
  return output == MODEL_OUTPUT_LOG1P ? "log1p" : "f";
}

nbrdf_status model_decoder_config_make(int latent_dim, model_encoding encoding, model_output output,
                                       int width, int blocks, int interleave_plain,
                                       model_decoder_config *cfg, nbrdf_error *err) {
  if (latent_dim < 1 || latent_dim > 4096)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "decoder: latent dimension %d, expected 1..4096",
                     latent_dim);
  if (!model_encoding_kind_name(encoding.kind) || encoding.octaves < 0 ||
      encoding.octaves > MODEL_ENCODING_MAX_OCTAVES)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "decoder: invalid encoding (kind %d, %d octaves; at most %d)",
                     (int)encoding.kind, encoding.octaves, MODEL_ENCODING_MAX_OCTAVES);
  if (output != MODEL_OUTPUT_F && output != MODEL_OUTPUT_LOG1P)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "decoder: invalid output transform %d", (int)output);
  model_decoder_config c;
  memset(&c, 0, sizeof c);
  snprintf(c.preset, sizeof c.preset, "custom");
  c.latent_dim = latent_dim;
  c.encoding = encoding;
  c.output = output;
  int inputs = latent_dim + model_encoding_width(&encoding);
  nbrdf_status st = nn_spec_resmlp(&c.spec, inputs, width, blocks, interleave_plain, 1, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "decoder: ");
    return st;
  }
  *cfg = c;
  return NBRDF_OK;
}

nbrdf_status model_decoder_preset(const char *name, int latent_dim, model_decoder_config *cfg,
                                  nbrdf_error *err) {
  model_encoding cart = {MODEL_ENCODING_CARTESIAN, 0}, hd = {MODEL_ENCODING_HALFDIFF, 0};
  nbrdf_status st;
  if (!strcmp(name, "paper"))
    st = model_decoder_config_make(latent_dim, cart, MODEL_OUTPUT_F, 256, 8, 1, cfg, err);
  else if (!strcmp(name, "large"))
    st = model_decoder_config_make(latent_dim, hd, MODEL_OUTPUT_LOG1P, 128, 3, 1, cfg, err);
  else if (!strcmp(name, "medium"))
    st = model_decoder_config_make(latent_dim, hd, MODEL_OUTPUT_LOG1P, 64, 3, 1, cfg, err);
  else if (!strcmp(name, "small"))
    st = model_decoder_config_make(latent_dim, hd, MODEL_OUTPUT_LOG1P, 32, 2, 1, cfg, err);
  else
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "unknown decoder preset '%s' (paper, large, medium, small)", name);
  if (st == NBRDF_OK) snprintf(cfg->preset, sizeof cfg->preset, "%s", name);
  return st;
}

static nbrdf_status check_config(const model_decoder_config *cfg, const char *where,
                                 nbrdf_error *err) {
  int want = cfg->latent_dim + model_encoding_width(&cfg->encoding);
  if (cfg->spec.n_inputs != want)
    return core_fail(
        err, NBRDF_ERR_MISMATCH, "%s: decoder has %d inputs, latent %d + %s encoding %d needs %d",
        where, cfg->spec.n_inputs, cfg->latent_dim, model_encoding_kind_name(cfg->encoding.kind),
        model_encoding_width(&cfg->encoding), want);
  if (nn_spec_outputs(&cfg->spec) != 1)
    return core_fail(err, NBRDF_ERR_MISMATCH, "%s: decoder has %d outputs, expected 1", where,
                     nn_spec_outputs(&cfg->spec));
  return NBRDF_OK;
}

static nbrdf_status wrap(const model_decoder_config *cfg, nn_network *nn, model_decoder **out,
                         nbrdf_error *err) {
  model_decoder *dec = calloc(1, sizeof *dec);
  if (!dec) {
    nn_destroy(nn);
    return core_fail(err, NBRDF_ERR_MEMORY, "decoder: out of memory");
  }
  dec->cfg = *cfg;
  dec->nn = nn;
  *out = dec;
  return NBRDF_OK;
}

nbrdf_status model_decoder_create(const model_decoder_config *cfg, uint64_t seed,
                                  model_decoder **out, nbrdf_error *err) {
  nbrdf_status st = check_config(cfg, "decoder", err);
  nn_network *nn = NULL;
  if (st == NBRDF_OK) st = nn_create(&cfg->spec, &nn, err);
  if (st != NBRDF_OK) return st;
  nn_init_params(nn, seed);
  return wrap(cfg, nn, out, err);
}

void model_decoder_destroy(model_decoder *dec) {
  if (!dec) return;
  nn_destroy(dec->nn);
  free(dec);
}

int model_decoder_inputs(const model_decoder *dec) { return dec->cfg.spec.n_inputs; }

int64_t model_decoder_macs(const model_decoder *dec) { return nn_spec_macs(&dec->cfg.spec); }

void model_decoder_fill_inputs(const model_decoder *dec, size_t n, int channels,
                               const float *latents, const float *wi, const float *wo, float *x) {
  size_t dim = (size_t)dec->cfg.latent_dim, in = (size_t)model_decoder_inputs(dec);
  for (size_t k = 0; k < n; k++) {
    float *first = x + k * channels * in;
    model_encode(&dec->cfg.encoding, 1, wi + 3 * k, wo + 3 * k, first + dim, in);
    for (int c = 0; c < channels; c++) {
      float *row = first + (size_t)c * in;
      memcpy(row, latents + (k * channels + c) * dim, dim * sizeof(float));
      if (c > 0) memcpy(row + dim, first + dim, (in - dim) * sizeof(float));
    }
  }
}

float model_output_to_f(model_output output, float o) {
  if (output == MODEL_OUTPUT_LOG1P) return expm1f(fminf(fmaxf(o, 0.0f), 80.0f));
  return fmaxf(o, 0.0f);
}

nbrdf_status model_decoder_eval(const model_decoder *dec, model_runner *runner, size_t n,
                                int channels, const float *latents, const float *wi,
                                const float *wo, float *f, nbrdf_error *err) {
  if (channels < 1 || channels > runner->max_batch)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "decoder: %d channels for a batch of %d rows",
                     channels, runner->max_batch);
  size_t per_chunk = (size_t)(runner->max_batch / channels);
  size_t dim = (size_t)dec->cfg.latent_dim;
  for (size_t k0 = 0; k0 < n; k0 += per_chunk) {
    size_t m = n - k0 < per_chunk ? n - k0 : per_chunk;
    model_decoder_fill_inputs(dec, m, channels, latents + k0 * channels * dim, wi + 3 * k0,
                              wo + 3 * k0, runner->x);
    int rows = (int)(m * channels);
    nbrdf_status st = model_runner_forward(dec->nn, runner, runner->x, rows, runner->y, err);
    if (st != NBRDF_OK) return st;
    for (int r = 0; r < rows; r++)
      f[k0 * channels + r] = model_output_to_f(dec->cfg.output, runner->y[r]);
  }
  return NBRDF_OK;
}

/* The writer of a decoder file: its tensors and metadata (borrowed from dec). */
static nbrdf_status decoder_writer(const model_decoder *dec, nn_st_writer **out, nbrdf_error *err) {
  nn_st_writer *w = NULL;
  nbrdf_status st = model_net_writer(dec->nn, "decoder", dec->cfg.latent_dim, &w, err);
  char oct[16];
  snprintf(oct, sizeof oct, "%d", dec->cfg.encoding.octaves);
  if (st == NBRDF_OK)
    st = nn_st_writer_set_metadata(w, "nbrdf.encoding",
                                   model_encoding_kind_name(dec->cfg.encoding.kind), err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.octaves", oct, err);
  if (st == NBRDF_OK)
    st = nn_st_writer_set_metadata(w, "nbrdf.output", model_output_name(dec->cfg.output), err);
  if (st == NBRDF_OK) st = nn_st_writer_set_metadata(w, "nbrdf.preset", dec->cfg.preset, err);
  if (st != NBRDF_OK) {
    nn_st_writer_destroy(w);
    return st;
  }
  *out = w;
  return NBRDF_OK;
}

nbrdf_status model_decoder_save(const model_decoder *dec, const char *path, uint64_t *checksum,
                                nbrdf_error *err) {
  nn_st_writer *w = NULL;
  nbrdf_status st = decoder_writer(dec, &w, err);
  if (st == NBRDF_OK) st = nn_st_writer_save(w, path, checksum, err);
  nn_st_writer_destroy(w);
  return st;
}

nbrdf_status model_decoder_serialize(const model_decoder *dec, void **bytes, size_t *size,
                                     nbrdf_error *err) {
  nn_st_writer *w = NULL;
  nbrdf_status st = decoder_writer(dec, &w, err);
  if (st == NBRDF_OK) st = nn_st_writer_serialize(w, bytes, size, err);
  nn_st_writer_destroy(w);
  return st;
}

nbrdf_status model_decoder_read(const nn_st_reader *reader, model_decoder **out, nbrdf_error *err) {
  const char *label = nn_st_label(reader);
  model_decoder_config cfg;
  memset(&cfg, 0, sizeof cfg);
  const char *enc = NULL, *output = NULL, *preset = NULL;
  long octaves = 0;
  nbrdf_status st = model_net_check_kind(reader, "decoder", err);
  if (st == NBRDF_OK) st = nn_st_metadata_require(reader, "nbrdf.encoding", &enc, err);
  if (st == NBRDF_OK && !model_encoding_kind_parse(enc, &cfg.encoding.kind))
    st = core_fail(err, NBRDF_ERR_FORMAT, "%s: unknown encoding \"%s\"", label, enc);
  if (st == NBRDF_OK)
    st = model_meta_int(reader, "nbrdf.octaves", 0, MODEL_ENCODING_MAX_OCTAVES, &octaves, err);
  if (st == NBRDF_OK) st = nn_st_metadata_require(reader, "nbrdf.output", &output, err);
  if (st == NBRDF_OK) {
    if (!strcmp(output, "f"))
      cfg.output = MODEL_OUTPUT_F;
    else if (!strcmp(output, "log1p"))
      cfg.output = MODEL_OUTPUT_LOG1P;
    else
      st = core_fail(err, NBRDF_ERR_FORMAT, "%s: unknown output transform \"%s\"", label, output);
  }
  if (st != NBRDF_OK) return st;
  cfg.encoding.octaves = (int)octaves;
  preset = nn_st_metadata_get(reader, "nbrdf.preset");
  snprintf(cfg.preset, sizeof cfg.preset, "%s", preset ? preset : "custom");

  nn_network *nn = NULL;
  st = model_net_read(reader, "decoder", &nn, &cfg.latent_dim, err);
  if (st != NBRDF_OK) return st;
  cfg.spec = *nn_get_spec(nn);
  st = check_config(&cfg, label, err);
  if (st != NBRDF_OK) {
    nn_destroy(nn);
    return st;
  }
  return wrap(&cfg, nn, out, err);
}

nbrdf_status model_decoder_load(const char *path, model_decoder **out, nbrdf_error *err) {
  nn_st_reader *r = NULL;
  nbrdf_status st = nn_st_open(path, &r, err);
  if (st == NBRDF_OK) st = model_decoder_read(r, out, err);
  nn_st_close(r);
  return st;
}

nbrdf_status model_decoder_compact_config(int dim, int width, model_decoder_config *cfg, nbrdf_error *err) {
  if (dim < 1 || dim > MODEL_COMPACT_MAX_DIM)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "compact: %d latent channels; 1 to %d", dim,
                     MODEL_COMPACT_MAX_DIM);
  if (width < 4 || width > 256)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "compact: decoder width %d; 4 to 256", width);
  model_encoding hd = {MODEL_ENCODING_HALFDIFF, 1};
  nbrdf_status st = model_decoder_config_make(dim, hd, MODEL_OUTPUT_LOG1P, width, 1, 0, cfg, err);
  if (st == NBRDF_OK) snprintf(cfg->preset, sizeof cfg->preset, "compact");
  return st;
}
