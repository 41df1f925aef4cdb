/* The storage-buffer layouts of the GLSL shaders (include/nbrdf/gpu_pack.h). The layer
 * records are derived from the spec and the tensors' names, so the shader walks exactly
 * the architecture the C forward pass runs. */
#include "model/gpu_pack.h"

#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "model/bundle.h"

static uint32_t bits(float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof u);
  return u;
}

/* Offset of tensor layers.<i>.<part>, or NONE when the layer has no such tensor. */
static uint32_t tensor_offset(const nn_network *nn, int i, const char *part) {
  char name[64];
  snprintf(name, sizeof name, "layers.%d.%s", i, part);
  const nn_tensor *t = nn_find_tensor(nn, name);
  return t ? (uint32_t)t->offset : NBRDF_GPU_NONE;
}

static void layer_record(const nn_network *nn, int i, uint32_t r[NBRDF_GPU_LAYER_WORDS]) {
  const nn_spec *spec = nn_get_spec(nn);
  const nn_layer_spec *s = &spec->layers[i];
  int in = nn_spec_width(spec, i), out = nn_spec_width(spec, i + 1);
  int residual = s->kind == NBRDF_NN_RESIDUAL;
  int plain = s->kind == NBRDF_NN_PLAIN;
  memset(r, 0, sizeof(uint32_t) * NBRDF_GPU_LAYER_WORDS);
  r[0] = (uint32_t)s->kind;
  r[1] = (uint32_t)in;
  r[2] = (uint32_t)out;
  r[3] = residual ? (uint32_t)(s->hidden > 0 ? s->hidden : in / 2) : 0u;
  r[4] = s->has_skip ? (uint32_t)s->skip_from : NBRDF_GPU_NONE;
  r[5] = s->has_skip ? (uint32_t)nn_spec_width(spec, s->skip_from) : 0u;
  const char *w1 = residual ? "fc1.weight" : plain ? "fc.weight" : "weight";
  const char *b1 = residual ? "fc1.bias" : plain ? "fc.bias" : "bias";
  const char *g1 = residual ? "norm1.weight" : "norm.weight";
  const char *be1 = residual ? "norm1.bias" : "norm.bias";
  if (s->kind == NBRDF_NN_LINEAR) {
    r[6] = tensor_offset(nn, i, w1);
    r[7] = tensor_offset(nn, i, b1);
    r[8] = r[9] = NBRDF_GPU_NONE;
  } else if (s->kind == NBRDF_NN_LAYERNORM) {
    r[6] = r[7] = NBRDF_GPU_NONE;
    r[8] = tensor_offset(nn, i, "weight");
    r[9] = tensor_offset(nn, i, "bias");
  } else if (s->kind == NBRDF_NN_RELU) {
    r[6] = r[7] = r[8] = r[9] = NBRDF_GPU_NONE;
  } else {
    r[6] = tensor_offset(nn, i, w1);
    r[7] = tensor_offset(nn, i, b1);
    r[8] = tensor_offset(nn, i, g1);
    r[9] = tensor_offset(nn, i, be1);
  }
  r[10] = residual ? tensor_offset(nn, i, "fc2.weight") : NBRDF_GPU_NONE;
  r[11] = residual ? tensor_offset(nn, i, "fc2.bias") : NBRDF_GPU_NONE;
  r[12] = residual ? tensor_offset(nn, i, "norm2.weight") : NBRDF_GPU_NONE;
  r[13] = residual ? tensor_offset(nn, i, "norm2.bias") : NBRDF_GPU_NONE;
  r[14] = tensor_offset(nn, i, "skip.weight");
}

nbrdf_status model_gpu_pack_decoder(const model_decoder *dec, uint32_t *words, size_t capacity,
                                    size_t *n_words, nbrdf_error *err) {
  const nn_network *nn = dec->nn;
  const nn_spec *spec = nn_get_spec(nn);
  int max_width = spec->n_inputs;
  for (int i = 0; i < spec->n_layers; i++) {
    const nn_layer_spec *s = &spec->layers[i];
    /* The shader keeps the network input for the whole pass, but no other activation. */
    if (s->has_skip && s->skip_from != 0)
      return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                       "gpu pack: layer %d (%s) has a skip from activation %d; the shader "
                       "supports skips from the network input only",
                       i, nn_kind_name(s->kind), s->skip_from);
    int w = nn_spec_width(spec, i + 1);
    if (w > max_width) max_width = w;
    if (s->kind == NBRDF_NN_RESIDUAL) {
      int in = nn_spec_width(spec, i);
      int h = s->hidden > 0 ? s->hidden : in / 2;
      if (h > max_width) max_width = h;
    }
  }
  /* Rounded up to a multiple of 32, at least 64: measured on lavapipe (Mesa 22.3, LLVM 15),
   * pipelines with activation arrays of 32..48 floats took 6-13 s to compile (small arrays
   * are lowered differently), 64..256 took 1-2 s. A larger array costs nothing on a GPU
   * that indexes it in local memory. */
  max_width = (max_width + 31) / 32 * 32;
  if (max_width < 64) max_width = 64;
  size_t n_params = nn_param_count(nn);
  size_t params_at = NBRDF_GPU_HEADER_WORDS + (size_t)NBRDF_GPU_LAYER_WORDS * spec->n_layers;
  size_t total = params_at + n_params;
  if (n_words) *n_words = total;
  if (!words) return NBRDF_OK;
  if (capacity < total)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "gpu pack: the decoder needs %zu words, got %zu",
                     total, capacity);
  int64_t macs = nn_spec_macs(spec);
  memset(words, 0, sizeof(uint32_t) * params_at);
  words[NBRDF_GPU_W_MAGIC] = NBRDF_GPU_DECODER_MAGIC;
  words[NBRDF_GPU_W_VERSION] = NBRDF_GPU_VERSION;
  words[NBRDF_GPU_W_INPUTS] = (uint32_t)spec->n_inputs;
  words[NBRDF_GPU_W_LAYERS] = (uint32_t)spec->n_layers;
  words[NBRDF_GPU_W_LATENT_DIM] = (uint32_t)dec->cfg.latent_dim;
  words[NBRDF_GPU_W_ENCODING] = (uint32_t)dec->cfg.encoding.kind;
  words[NBRDF_GPU_W_OCTAVES] = (uint32_t)dec->cfg.encoding.octaves;
  words[NBRDF_GPU_W_OUTPUT] = dec->cfg.output == MODEL_OUTPUT_LOG1P ? 1u : 0u;
  words[NBRDF_GPU_W_OUTPUTS] = (uint32_t)nn_spec_outputs(spec);
  words[NBRDF_GPU_W_MAX_WIDTH] = (uint32_t)max_width;
  words[NBRDF_GPU_W_PARAMS] = (uint32_t)params_at;
  words[NBRDF_GPU_W_PARAM_COUNT] = (uint32_t)n_params;
  words[NBRDF_GPU_W_MACS] = macs > (int64_t)UINT32_MAX ? UINT32_MAX : (uint32_t)macs;
  for (int i = 0; i < spec->n_layers; i++)
    layer_record(nn, i, words + NBRDF_GPU_HEADER_WORDS + (size_t)NBRDF_GPU_LAYER_WORDS * i);
  const float *p = nn_params_const(nn);
  for (size_t k = 0; k < n_params; k++)
    words[params_at + k] = bits(p[k]);
  return NBRDF_OK;
}

nbrdf_status nbrdf_gpu_pack_decoder(const nbrdf_model *model, uint32_t *words, size_t capacity,
                                    size_t *n_words, nbrdf_error *err) {
  if (!model) return core_fail(err, NBRDF_ERR_ARGUMENT, "gpu pack: NULL model");
  return model_gpu_pack_decoder(model->decoder, words, capacity, n_words, err);
}

nbrdf_status nbrdf_gpu_pack_latents(int levels, const int *width, const int *height, int channels,
                                    int latent_dim, int colours, int proxy,
                                    const float *const *data, uint32_t *words, size_t capacity,
                                    size_t *n_words, nbrdf_error *err) {
  if (levels < 1 || levels > NBRDF_GPU_L_MAX_LEVELS)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "gpu pack: %d levels, expected 1..%d", levels,
                     NBRDF_GPU_L_MAX_LEVELS);
  if ((colours != 1 && colours != 3) || latent_dim < 1 ||
      channels != colours * (latent_dim + (proxy ? 2 : 0)))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "gpu pack: %d channels per texel do not match %d colour(s) of %d latents%s",
                     channels, colours, latent_dim, proxy ? " + sigma, w" : "");
  size_t total = NBRDF_GPU_L_DATA;
  for (int l = 0; l < levels; l++) {
    int w = width[0] >> l, h = height[0] >> l;
    w = w > 1 ? w : 1;
    h = h > 1 ? h : 1;
    if (width[0] < 1 || height[0] < 1 || width[l] != w || height[l] != h)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "gpu pack: level %d is %d x %d, the round-down chain of %d x %d needs "
                       "%d x %d",
                       l, width[l], height[l], width[0], height[0], w, h);
    total += (size_t)w * h * channels;
  }
  if (total > UINT32_MAX)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                     "gpu pack: %zu words exceed the 32-bit word offsets", total);
  if (n_words) *n_words = total;
  if (!words) return NBRDF_OK;
  if (capacity < total)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "gpu pack: the texture needs %zu words, got %zu",
                     total, capacity);
  memset(words, 0, sizeof(uint32_t) * NBRDF_GPU_L_DATA);
  words[NBRDF_GPU_L_MAGIC] = NBRDF_GPU_LATENT_MAGIC;
  words[NBRDF_GPU_L_VERSION] = NBRDF_GPU_VERSION;
  words[NBRDF_GPU_L_CHANNELS] = (uint32_t)channels;
  words[NBRDF_GPU_L_LEVELS] = (uint32_t)levels;
  words[NBRDF_GPU_L_LATENT_DIM] = (uint32_t)latent_dim;
  words[NBRDF_GPU_L_COLOURS] = (uint32_t)colours;
  words[NBRDF_GPU_L_PROXY] = proxy ? 1u : 0u;
  size_t at = NBRDF_GPU_L_DATA;
  for (int l = 0; l < levels; l++) {
    uint32_t *rec = words + NBRDF_GPU_L_HEADER_WORDS + 4 * l;
    rec[0] = (uint32_t)width[l];
    rec[1] = (uint32_t)height[l];
    rec[2] = (uint32_t)at;
    size_t n = (size_t)width[l] * height[l] * channels;
    memcpy(words + at, data[l], n * sizeof(float));
    at += n;
  }
  return NBRDF_OK;
}
