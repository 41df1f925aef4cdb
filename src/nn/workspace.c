/* Workspaces: every buffer forward and backward use, carved out of one allocation sized once
 * for a maximum batch, so that the hot loop allocates nothing. */
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "nn/internal.h"

/* Beyond this, rows x width x 4 bytes could overflow int arithmetic in BLAS calls. */
#define MAX_BATCH (1 << 24)

int nn_infer_block(const nn_network *nn) {
  int rows = (1 << 19) / nn->max_width / 16 * 16;
  return rows < 64 ? 64 : rows;
}

typedef struct carver {
  char *base; /* NULL while measuring */
  size_t used;
} carver;

static void *carve(carver *c, size_t bytes) {
  void *p = c->base ? c->base + c->used : NULL;
  c->used += (bytes + NN_ALIGN - 1) / NN_ALIGN * NN_ALIGN;
  return p;
}

static float *carve_f(carver *c, int rows, int w) {
  return carve(c, sizeof(float) * (size_t)rows * (size_t)w);
}

/* Lays the workspace out (ws->block == NULL: only measures) and returns its size. */
static size_t plan(nn_workspace *ws, const nn_network *nn) {
  carver c = {ws->block, 0};
  const int W = nn->max_width, L = nn->spec.n_layers;
  const int block = nn_infer_block(nn);
  ws->rows = ws->mode == NBRDF_NN_INFER && ws->max_batch > block ? block : ws->max_batch;
  const int B = ws->rows;
  memset(ws->act, 0, sizeof ws->act);
  memset(ws->layer, 0, sizeof ws->layer);
  memset(ws->grad_skip, 0, sizeof ws->grad_skip);
  if (ws->mode == NBRDF_NN_INFER) {
    /* Activations are only kept while a later skip still reads them; the rest ping-pong. */
    for (int j = 1; j < L; j++)
      if (nn->skip_source[j]) ws->act[j] = carve_f(&c, B, nn->widths[j]);
    ws->pingpong[0] = carve_f(&c, B, W);
    ws->pingpong[1] = carve_f(&c, B, W);
    ws->scratch_z = carve_f(&c, B, W);
    ws->scratch_h = carve_f(&c, B, W);
    ws->scratch_r = carve_f(&c, B, 1);
    return c.used;
  }
  ws->act[0] = carve_f(&c, B, nn->widths[0]);
  for (int i = 0; i < L; i++) {
    const nn_layer *l = &nn->layers[i];
    nn_layer_buffers *b = &ws->layer[i];
    ws->act[i + 1] = carve_f(&c, B, l->out);
    switch (l->kind) {
    case NBRDF_NN_PLAIN:
    case NBRDF_NN_LAYERNORM:
      b->z1 = carve_f(&c, B, l->out);
      b->r1 = carve_f(&c, B, 1);
      break;
    case NBRDF_NN_RESIDUAL:
      b->z1 = carve_f(&c, B, l->hidden);
      b->r1 = carve_f(&c, B, 1);
      b->h = carve_f(&c, B, l->hidden);
      b->z2 = carve_f(&c, B, l->out);
      b->r2 = carve_f(&c, B, 1);
      break;
    case NBRDF_NN_LINEAR:
    case NBRDF_NN_RELU:
      break;
    }
  }
  ws->grad_chain[0] = carve_f(&c, B, W);
  ws->grad_chain[1] = carve_f(&c, B, W);
  ws->grad_hidden = carve_f(&c, B, W);
  for (int j = 0; j < L; j++)
    if (nn->skip_source[j]) ws->grad_skip[j] = carve_f(&c, B, nn->widths[j]);
  ws->acc = carve(&c, sizeof(double) * 4 * (size_t)W);
  return c.used;
}

size_t nn_workspace_bytes(const nn_spec *spec, int max_batch, nn_mode mode) {
  if (nn_spec_validate(spec, NULL) != NBRDF_OK || max_batch < 1) return 0;
  nn_network *nn = calloc(1, sizeof *nn);
  nn_workspace *ws = calloc(1, sizeof *ws);
  size_t bytes = 0;
  if (nn && ws) {
    nn->spec = *spec;
    nn_resolve(nn);
    ws->mode = mode;
    ws->max_batch = max_batch;
    bytes = plan(ws, nn) + sizeof *ws;
  }
  free(nn);
  free(ws);
  return bytes;
}

nbrdf_status nn_workspace_create(const nn_network *nn, int max_batch, nn_mode mode,
                                 nn_workspace **out, nbrdf_error *err) {
  *out = NULL;
  if (max_batch < 1 || max_batch > MAX_BATCH)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "network workspace: max_batch = %d, expected 1..%d",
                     max_batch, MAX_BATCH);
  if (mode != NBRDF_NN_TRAIN && mode != NBRDF_NN_INFER)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "network workspace: unknown mode %d", (int)mode);
  nn_workspace *ws = calloc(1, sizeof *ws);
  if (!ws) return core_fail(err, NBRDF_ERR_MEMORY, "network workspace: out of memory");
  ws->spec = nn->spec;
  ws->mode = mode;
  ws->max_batch = max_batch;
  ws->bytes = plan(ws, nn);
  ws->block = aligned_alloc(NN_ALIGN, ws->bytes);
  if (!ws->block) {
    size_t bytes = ws->bytes;
    free(ws);
    return core_fail(err, NBRDF_ERR_MEMORY,
                     "network workspace: out of memory for %zu bytes (batch %d)", bytes, max_batch);
  }
  plan(ws, nn);
  *out = ws;
  return NBRDF_OK;
}

void nn_workspace_destroy(nn_workspace *ws) {
  if (!ws) return;
  free(ws->block);
  free(ws);
}

int nn_same_spec(const nn_spec *a, const nn_spec *b) {
  if (a->n_inputs != b->n_inputs || a->n_layers != b->n_layers) return 0;
  for (int i = 0; i < a->n_layers; i++) {
    const nn_layer_spec *x = &a->layers[i], *y = &b->layers[i];
    if (x->kind != y->kind || x->width != y->width || x->hidden != y->hidden ||
        x->has_skip != y->has_skip || x->skip_from != y->skip_from)
      return 0;
  }
  return 1;
}

int nn_workspace_max_batch(const nn_workspace *ws) { return ws->max_batch; }
