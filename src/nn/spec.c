/* Architecture description of a dense network: building, validating and costing a spec. */
#include <string.h>

#include "core/error.h"
#include "nn/nn.h"

const char *nn_kind_name(nn_kind kind) {
  switch (kind) {
  case NBRDF_NN_LINEAR:
    return "linear";
  case NBRDF_NN_LAYERNORM:
    return "layernorm";
  case NBRDF_NN_RELU:
    return "relu";
  case NBRDF_NN_PLAIN:
    return "plain";
  case NBRDF_NN_RESIDUAL:
    return "residual";
  }
  return NULL;
}

void nn_spec_init(nn_spec *spec, int n_inputs) {
  memset(spec, 0, sizeof *spec);
  spec->n_inputs = n_inputs;
}

int nn_spec_add(nn_spec *spec, nn_kind kind, int width) {
  if (spec->n_layers < 0 || spec->n_layers >= NBRDF_NN_MAX_LAYERS) {
    /* Remembered as an overflow so that validate reports it instead of silently dropping. */
    spec->n_layers = NBRDF_NN_MAX_LAYERS + 1;
    return -1;
  }
  nn_layer_spec *l = &spec->layers[spec->n_layers];
  memset(l, 0, sizeof *l);
  l->kind = kind;
  l->width = width;
  return spec->n_layers++;
}

void nn_spec_skip(nn_spec *spec, int layer, int from) {
  if (layer < 0 || layer >= NBRDF_NN_MAX_LAYERS) return;
  spec->layers[layer].has_skip = 1;
  spec->layers[layer].skip_from = from;
}

nbrdf_status nn_spec_resmlp(nn_spec *spec, int n_inputs, int width, int n_blocks,
                            int interleave_plain, int n_outputs, nbrdf_error *err) {
  int needed = 2 + n_blocks * (interleave_plain ? 2 : 1);
  if (n_blocks < 0 || needed > NBRDF_NN_MAX_LAYERS)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "resmlp: %d blocks need %d layers, at most %d are supported", n_blocks, needed,
                     NBRDF_NN_MAX_LAYERS);
  nn_spec s;
  nn_spec_init(&s, n_inputs);
  nn_spec_add(&s, NBRDF_NN_PLAIN, width);
  for (int b = 0; b < n_blocks; b++) {
    nn_spec_add(&s, NBRDF_NN_RESIDUAL, 0);
    if (interleave_plain) nn_spec_add(&s, NBRDF_NN_PLAIN, width);
  }
  nn_spec_add(&s, NBRDF_NN_LINEAR, n_outputs);
  nbrdf_status st = nn_spec_validate(&s, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "resmlp: ");
    return st;
  }
  *spec = s;
  return NBRDF_OK;
}

/* Width of each layer's output; valid only after validation succeeded. */
static int layer_out_width(const nn_layer_spec *l, int in) {
  return (l->kind == NBRDF_NN_LINEAR || l->kind == NBRDF_NN_PLAIN) ? l->width : in;
}

static int layer_hidden(const nn_layer_spec *l, int in) {
  return l->hidden > 0 ? l->hidden : in / 2;
}

nbrdf_status nn_spec_validate(const nn_spec *spec, nbrdf_error *err) {
  if (!spec) return core_fail(err, NBRDF_ERR_ARGUMENT, "network spec is NULL");
  if (spec->n_inputs < 1 || spec->n_inputs > NBRDF_NN_MAX_WIDTH)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "network inputs = %d, expected 1..%d", spec->n_inputs,
                     NBRDF_NN_MAX_WIDTH);
  if (spec->n_layers > NBRDF_NN_MAX_LAYERS)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "network has more than %d layers",
                     NBRDF_NN_MAX_LAYERS);
  if (spec->n_layers < 1) return core_fail(err, NBRDF_ERR_ARGUMENT, "network has no layers");
  int widths[NBRDF_NN_MAX_LAYERS + 1];
  widths[0] = spec->n_inputs;
  for (int i = 0; i < spec->n_layers; i++) {
    const nn_layer_spec *l = &spec->layers[i];
    const char *kind = nn_kind_name(l->kind);
    if (!kind)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "layer %d: unknown kind %d", i, (int)l->kind);
    int in = widths[i];
    switch (l->kind) {
    case NBRDF_NN_LINEAR:
    case NBRDF_NN_PLAIN:
      if (l->width < 1 || l->width > NBRDF_NN_MAX_WIDTH)
        return core_fail(err, NBRDF_ERR_ARGUMENT, "layer %d (%s): width = %d, expected 1..%d", i,
                         kind, l->width, NBRDF_NN_MAX_WIDTH);
      if (l->kind == NBRDF_NN_PLAIN && l->width < 2)
        return core_fail(err, NBRDF_ERR_ARGUMENT,
                         "layer %d (plain): width %d is too small for LayerNorm (>= 2)", i,
                         l->width);
      break;
    case NBRDF_NN_LAYERNORM:
    case NBRDF_NN_RELU:
    case NBRDF_NN_RESIDUAL:
      if (l->width != 0 && l->width != in)
        return core_fail(err, NBRDF_ERR_ARGUMENT,
                         "layer %d (%s): width %d differs from its input width %d", i, kind,
                         l->width, in);
      if (l->kind != NBRDF_NN_RELU && in < 2)
        return core_fail(err, NBRDF_ERR_ARGUMENT,
                         "layer %d (%s): input width %d is too small for LayerNorm (>= 2)", i, kind,
                         in);
      break;
    }
    if (l->kind == NBRDF_NN_RESIDUAL) {
      int h = layer_hidden(l, in);
      if (l->hidden < 0 || h < 2 || h > NBRDF_NN_MAX_WIDTH)
        return core_fail(err, NBRDF_ERR_ARGUMENT,
                         "layer %d (residual): hidden width %d, expected 2..%d", i,
                         l->hidden < 0 ? l->hidden : h, NBRDF_NN_MAX_WIDTH);
    } else if (l->hidden != 0) {
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "layer %d (%s): a hidden width is only meaningful for residual blocks", i,
                       kind);
    }
    if (l->has_skip) {
      if (l->kind == NBRDF_NN_LAYERNORM || l->kind == NBRDF_NN_RELU)
        return core_fail(err, NBRDF_ERR_ARGUMENT, "layer %d (%s) cannot take a skip connection", i,
                         kind);
      if (l->skip_from < 0 || l->skip_from > i)
        return core_fail(err, NBRDF_ERR_ARGUMENT,
                         "layer %d (%s): skip from activation %d, expected 0 (network input) "
                         "..%d (its own input)",
                         i, kind, l->skip_from, i);
    } else if (l->skip_from != 0) {
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "layer %d (%s): skip_from = %d set without has_skip", i, kind, l->skip_from);
    }
    widths[i + 1] = layer_out_width(l, in);
  }
  return NBRDF_OK;
}

int nn_spec_width(const nn_spec *spec, int activation) {
  int w = spec->n_inputs;
  for (int i = 0; i < activation && i < spec->n_layers; i++)
    w = layer_out_width(&spec->layers[i], w);
  return w;
}

int nn_spec_outputs(const nn_spec *spec) { return nn_spec_width(spec, spec->n_layers); }

/* Per-layer multiply-adds (GEMMs only) and parameter count, shared by the two queries. */
static void layer_cost(const nn_spec *spec, int i, int in, int64_t *macs, size_t *params) {
  const nn_layer_spec *l = &spec->layers[i];
  int out = layer_out_width(l, in);
  int64_t m = 0;
  size_t p = 0;
  switch (l->kind) {
  case NBRDF_NN_LINEAR:
    m = (int64_t)in * out;
    p = (size_t)in * out + out;
    break;
  case NBRDF_NN_PLAIN:
    m = (int64_t)in * out;
    p = (size_t)in * out + 3 * (size_t)out;
    break;
  case NBRDF_NN_LAYERNORM:
    p = 2 * (size_t)in;
    break;
  case NBRDF_NN_RELU:
    break;
  case NBRDF_NN_RESIDUAL: {
    int h = layer_hidden(l, in);
    m = 2 * (int64_t)in * h;
    p = 2 * (size_t)in * h + 3 * (size_t)h + 3 * (size_t)in;
    break;
  }
  }
  if (l->has_skip) {
    int sw = nn_spec_width(spec, l->skip_from);
    if (sw != out) {
      m += (int64_t)sw * out;
      p += (size_t)sw * out;
    }
  }
  *macs = m;
  *params = p;
}

int64_t nn_spec_macs(const nn_spec *spec) {
  int64_t total = 0;
  int in = spec->n_inputs;
  for (int i = 0; i < spec->n_layers; i++) {
    int64_t m;
    size_t p;
    layer_cost(spec, i, in, &m, &p);
    total += m;
    in = layer_out_width(&spec->layers[i], in);
  }
  return total;
}

size_t nn_spec_param_count(const nn_spec *spec) {
  size_t total = 0;
  int in = spec->n_inputs;
  for (int i = 0; i < spec->n_layers; i++) {
    int64_t m;
    size_t p;
    layer_cost(spec, i, in, &m, &p);
    total += p;
    in = layer_out_width(&spec->layers[i], in);
  }
  return total;
}
