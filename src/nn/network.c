/* A network: its resolved layers, the one contiguous parameter array and the named tensor
 * views into it, and the deterministic initialisation. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/rng.h"
#include "nn/internal.h"

typedef struct tensor_list {
  nn_tensor *t; /* NULL while counting */
  int n;
  size_t offset;
} tensor_list;

static size_t add_tensor(tensor_list *tl, int layer, const char *part, int rows, int cols) {
  size_t at = tl->offset;
  if (tl->t) {
    nn_tensor *t = &tl->t[tl->n];
    snprintf(t->name, sizeof t->name, "layers.%d.%s", layer, part);
    t->offset = at;
    t->rank = cols > 0 ? 2 : 1;
    t->rows = rows;
    t->cols = cols > 0 ? cols : 1;
    t->count = (size_t)rows * (size_t)t->cols;
  }
  tl->n++;
  tl->offset += (size_t)rows * (size_t)(cols > 0 ? cols : 1);
  return at;
}

void nn_resolve(nn_network *nn) {
  const nn_spec *spec = &nn->spec;
  tensor_list tl = {nn->tensors, 0, 0};
  memset(nn->skip_source, 0, sizeof nn->skip_source);
  nn->widths[0] = spec->n_inputs;
  nn->max_width = spec->n_inputs;
  for (int i = 0; i < spec->n_layers; i++) {
    const nn_layer_spec *s = &spec->layers[i];
    nn_layer *l = &nn->layers[i];
    l->kind = s->kind;
    l->in = nn->widths[i];
    l->out = (s->kind == NBRDF_NN_LINEAR || s->kind == NBRDF_NN_PLAIN) ? s->width : l->in;
    l->hidden = s->kind == NBRDF_NN_RESIDUAL ? (s->hidden > 0 ? s->hidden : l->in / 2) : 0;
    l->w1 = l->b1 = l->g1 = l->be1 = l->w2 = l->b2 = l->g2 = l->be2 = l->wskip = NN_NONE;
    switch (s->kind) {
    case NBRDF_NN_LINEAR:
      l->w1 = add_tensor(&tl, i, "weight", l->out, l->in);
      l->b1 = add_tensor(&tl, i, "bias", l->out, 0);
      break;
    case NBRDF_NN_LAYERNORM:
      l->g1 = add_tensor(&tl, i, "weight", l->out, 0);
      l->be1 = add_tensor(&tl, i, "bias", l->out, 0);
      break;
    case NBRDF_NN_RELU:
      break;
    case NBRDF_NN_PLAIN:
      l->w1 = add_tensor(&tl, i, "fc.weight", l->out, l->in);
      l->b1 = add_tensor(&tl, i, "fc.bias", l->out, 0);
      l->g1 = add_tensor(&tl, i, "norm.weight", l->out, 0);
      l->be1 = add_tensor(&tl, i, "norm.bias", l->out, 0);
      break;
    case NBRDF_NN_RESIDUAL:
      l->w1 = add_tensor(&tl, i, "fc1.weight", l->hidden, l->in);
      l->b1 = add_tensor(&tl, i, "fc1.bias", l->hidden, 0);
      l->g1 = add_tensor(&tl, i, "norm1.weight", l->hidden, 0);
      l->be1 = add_tensor(&tl, i, "norm1.bias", l->hidden, 0);
      l->w2 = add_tensor(&tl, i, "fc2.weight", l->out, l->hidden);
      l->b2 = add_tensor(&tl, i, "fc2.bias", l->out, 0);
      l->g2 = add_tensor(&tl, i, "norm2.weight", l->out, 0);
      l->be2 = add_tensor(&tl, i, "norm2.bias", l->out, 0);
      break;
    }
    l->skip_from = s->has_skip ? s->skip_from : -1;
    l->skip_width = s->has_skip ? nn->widths[s->skip_from] : 0;
    if (s->has_skip) {
      nn->skip_source[s->skip_from] = 1;
      if (l->skip_width != l->out)
        l->wskip = add_tensor(&tl, i, "skip.weight", l->out, l->skip_width);
    }
    nn->widths[i + 1] = l->out;
    if (l->out > nn->max_width) nn->max_width = l->out;
    if (l->hidden > nn->max_width) nn->max_width = l->hidden;
  }
  nn->n_params = tl.offset;
  nn->n_tensors = tl.n;
}

nbrdf_status nn_create(const nn_spec *spec, nn_network **out, nbrdf_error *err) {
  *out = NULL;
  nbrdf_status st = nn_spec_validate(spec, err);
  if (st != NBRDF_OK) return st;
  nn_network *nn = calloc(1, sizeof *nn);
  if (!nn) return core_fail(err, NBRDF_ERR_MEMORY, "network: out of memory");
  nn->spec = *spec;
  nn_resolve(nn); /* counts tensors and parameters */
  nn->tensors = calloc((size_t)nn->n_tensors + 1, sizeof *nn->tensors);
  size_t bytes = (nn->n_params * sizeof(float) + NN_ALIGN - 1) / NN_ALIGN * NN_ALIGN;
  nn->params = aligned_alloc(NN_ALIGN, bytes ? bytes : NN_ALIGN);
  if (!nn->tensors || !nn->params) {
    size_t n = nn->n_params;
    nn_destroy(nn);
    return core_fail(err, NBRDF_ERR_MEMORY, "network: out of memory for %zu parameters", n);
  }
  memset(nn->params, 0, bytes);
  nn_resolve(nn); /* fills the tensor views */
  *out = nn;
  return NBRDF_OK;
}

void nn_destroy(nn_network *nn) {
  if (!nn) return;
  free(nn->params);
  free(nn->tensors);
  free(nn);
}

const nn_spec *nn_get_spec(const nn_network *nn) { return &nn->spec; }
int nn_inputs(const nn_network *nn) { return nn->widths[0]; }
int nn_outputs(const nn_network *nn) { return nn->widths[nn->spec.n_layers]; }
float *nn_params(nn_network *nn) { return nn->params; }
const float *nn_params_const(const nn_network *nn) { return nn->params; }
size_t nn_param_count(const nn_network *nn) { return nn->n_params; }
int nn_tensor_count(const nn_network *nn) { return nn->n_tensors; }

const nn_tensor *nn_tensor_at(const nn_network *nn, int index) {
  return index >= 0 && index < nn->n_tensors ? &nn->tensors[index] : NULL;
}

const nn_tensor *nn_find_tensor(const nn_network *nn, const char *name) {
  for (int i = 0; i < nn->n_tensors; i++)
    if (strcmp(nn->tensors[i].name, name) == 0) return &nn->tensors[i];
  return NULL;
}

/* Does the weight at `offset` feed a ReLU (directly or through a LayerNorm)? */
static int feeds_relu(const nn_network *nn, size_t offset) {
  for (int i = 0; i < nn->spec.n_layers; i++) {
    const nn_layer *l = &nn->layers[i];
    if (offset == l->wskip) return 0;
    if (l->kind == NBRDF_NN_PLAIN || l->kind == NBRDF_NN_RESIDUAL)
      if (offset == l->w1 || offset == l->w2) return 1;
    if (l->kind == NBRDF_NN_LINEAR && offset == l->w1) {
      nn_kind next = i + 1 < nn->spec.n_layers ? nn->layers[i + 1].kind : 0;
      return next == NBRDF_NN_RELU || next == NBRDF_NN_LAYERNORM;
    }
  }
  return 0;
}

static int is_gamma(const nn_network *nn, size_t offset) {
  for (int i = 0; i < nn->spec.n_layers; i++)
    if (offset == nn->layers[i].g1 || offset == nn->layers[i].g2) return 1;
  return 0;
}

void nn_init_params(nn_network *nn, uint64_t seed) {
  for (int k = 0; k < nn->n_tensors; k++) {
    const nn_tensor *t = &nn->tensors[k];
    float *p = nn->params + t->offset;
    if (t->rank == 1) {
      /* LayerNorm gamma = 1, beta = 0; every bias = 0. */
      float v = is_gamma(nn, t->offset) ? 1.0f : 0.0f;
      for (size_t i = 0; i < t->count; i++)
        p[i] = v;
      continue;
    }
    /* He uniform keeps the variance of ReLU activations (He et al. 2015); LeCun uniform keeps
     * unit variance through a linear map. */
    double gain = feeds_relu(nn, t->offset) ? 6.0 : 3.0;
    float bound = (float)sqrt(gain / t->cols);
    core_rng rng;
    core_rng_init(&rng, seed, (uint64_t)k);
    for (size_t i = 0; i < t->count; i++)
      p[i] = bound * (2.0f * core_rng_uniformf(&rng) - 1.0f);
  }
}
