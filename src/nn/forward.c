/* Forward pass: one GEMM per linear map (cblas_sgemm, y = x W^T), then one fused pass per row
 * for bias + residual + skip, LayerNorm and ReLU. */
#include <string.h>

#include "core/error.h"
#include "nn/internal.h"

/* Layer i on `rows` rows: x -> y; `skip` is the skip source's activation (or NULL). */
static void layer_forward(const nn_network *nn, int i, int rows, const float *x, const float *skip,
                          float *y, const nn_layer_buffers *b) {
  const nn_layer *l = &nn->layers[i];
  const float *p = nn->params;
  int has_skip = l->skip_from >= 0;
  /* An identity skip is added in the row pass; a projected one by a GEMM into the same sum. */
  const float *skip_add = has_skip && l->wskip == NN_NONE ? skip : NULL;
  int projected = has_skip && l->wskip != NN_NONE;
  switch (l->kind) {
  case NBRDF_NN_LINEAR:
    if (projected) nn_gemm_xwt(rows, l->skip_width, l->out, skip, p + l->wskip, 0.0f, y);
    nn_gemm_xwt(rows, l->in, l->out, x, p + l->w1, projected ? 1.0f : 0.0f, y);
    nn_add_rows(rows, l->out, y, p + l->b1, skip_add);
    break;
  case NBRDF_NN_PLAIN:
    if (projected) nn_gemm_xwt(rows, l->skip_width, l->out, skip, p + l->wskip, 0.0f, b->z1);
    nn_gemm_xwt(rows, l->in, l->out, x, p + l->w1, projected ? 1.0f : 0.0f, b->z1);
    nn_ln_forward(rows, l->out, b->z1, p + l->b1, skip_add, NULL, p + l->g1, p + l->be1, b->r1, y,
                  1);
    break;
  case NBRDF_NN_RESIDUAL:
    nn_gemm_xwt(rows, l->in, l->hidden, x, p + l->w1, 0.0f, b->z1);
    nn_ln_forward(rows, l->hidden, b->z1, p + l->b1, NULL, NULL, p + l->g1, p + l->be1, b->r1, b->h,
                  1);
    if (projected) nn_gemm_xwt(rows, l->skip_width, l->out, skip, p + l->wskip, 0.0f, b->z2);
    nn_gemm_xwt(rows, l->hidden, l->out, b->h, p + l->w2, projected ? 1.0f : 0.0f, b->z2);
    /* The block's input is added before normalisation and activation (paper Fig. 3). */
    nn_ln_forward(rows, l->out, b->z2, p + l->b2, x, skip_add, p + l->g2, p + l->be2, b->r2, y, 1);
    break;
  case NBRDF_NN_LAYERNORM:
    memcpy(b->z1, x, sizeof(float) * (size_t)rows * l->out);
    nn_ln_forward(rows, l->out, b->z1, NULL, NULL, NULL, p + l->g1, p + l->be1, b->r1, y, 0);
    break;
  case NBRDF_NN_RELU:
    nn_relu_forward((size_t)rows * l->out, x, y);
    break;
  }
}

static void forward_train(const nn_network *nn, nn_workspace *ws, const float *x, int rows,
                          float *y) {
  const int L = nn->spec.n_layers;
  memcpy(ws->act[0], x, sizeof(float) * (size_t)rows * nn->widths[0]);
  for (int i = 0; i < L; i++) {
    int j = nn->layers[i].skip_from;
    layer_forward(nn, i, rows, ws->act[i], j >= 0 ? ws->act[j] : NULL, ws->act[i + 1],
                  &ws->layer[i]);
  }
  memcpy(y, ws->act[L], sizeof(float) * (size_t)rows * nn->widths[L]);
  ws->batch = rows;
  ws->has_fresh = 1;
}

/* Inference: x and y are used in place, intermediate activations ping-pong between two
 * buffers unless a later skip needs them. */
static void forward_infer(const nn_network *nn, nn_workspace *ws, const float *x, int rows,
                          float *y) {
  const int L = nn->spec.n_layers;
  nn_layer_buffers b = {ws->scratch_z, ws->scratch_r, ws->scratch_h, ws->scratch_z, ws->scratch_r};
  const float *act[NBRDF_NN_MAX_LAYERS + 1];
  act[0] = x;
  for (int i = 0; i < L; i++) {
    float *out;
    if (i == L - 1)
      out = y;
    else if (nn->skip_source[i + 1])
      out = ws->act[i + 1];
    else
      out = ws->pingpong[(i + 1) & 1];
    int j = nn->layers[i].skip_from;
    layer_forward(nn, i, rows, act[i], j >= 0 ? act[j] : NULL, out, &b);
    act[i + 1] = out;
  }
}

nbrdf_status nn_forward(const nn_network *nn, nn_workspace *ws, const float *x, int batch, float *y,
                        nbrdf_error *err) {
  if (!nn || !ws || !x || !y)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "network forward: NULL %s",
                     !nn   ? "network"
                     : !ws ? "workspace"
                     : !x  ? "input"
                           : "output");
  if (!nn_same_spec(&nn->spec, &ws->spec))
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "network forward: the workspace was made for another architecture");
  if (batch < 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "network forward: batch = %d, expected >= 1", batch);
  if (ws->mode == NBRDF_NN_TRAIN) {
    if (batch > ws->max_batch)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "network forward: batch %d exceeds the training workspace's %d", batch,
                       ws->max_batch);
    forward_train(nn, ws, x, batch, y);
    return NBRDF_OK;
  }
  const int in = nn->widths[0], out = nn->widths[nn->spec.n_layers];
  for (int done = 0; done < batch; done += ws->rows) {
    int rows = batch - done < ws->rows ? batch - done : ws->rows;
    forward_infer(nn, ws, x + (size_t)done * in, rows, y + (size_t)done * out);
  }
  return NBRDF_OK;
}
