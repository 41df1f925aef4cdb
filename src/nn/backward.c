/* Backward pass. For a linear map y = x W^T + b with upstream gradient G = dL/dy:
 *   dL/dx = G W              cblas_sgemm(NoTrans, NoTrans)
 *   dL/dW += G^T x           cblas_sgemm(Trans, NoTrans), beta = 1 accumulates into grad
 *   dL/db += column sums of G (in double)
 * The gradient flowing back along the chain lives in two ping-pong buffers; the gradient of an
 * activation that a later skip reads is accumulated in its own buffer and joins the chain
 * when the backward pass reaches that activation. */
#include <cblas.h>
#include <string.h>

#include "core/error.h"
#include "nn/internal.h"

typedef struct bw {
  const nn_network *nn;
  nn_workspace *ws;
  int rows;
  float *grad; /* NULL: no parameter gradients (frozen network) */
  int want_input_grad;
} bw;

/* Gradients of a linear map's weight (and bias, if b_off is set) given dL/d(output) in g. */
static void linear_params(const bw *b, size_t w_off, size_t b_off, int out, int in, const float *g,
                          const float *x) {
  if (!b->grad) return;
  nn_gemm_gtx(b->rows, out, in, g, x, b->grad + w_off);
  if (b_off != NN_NONE) {
    nn_colsum(b->rows, out, g, b->ws->acc);
    nn_flush(out, b->ws->acc, b->grad + b_off);
  }
}

static void skip_backward(const bw *b, const nn_layer *l, const float *g) {
  int j = l->skip_from;
  if (j < 0 || (j == 0 && !b->want_input_grad && l->wskip == NN_NONE)) return;
  nn_workspace *ws = b->ws;
  if (l->wskip == NN_NONE) {
    float *acc = ws->grad_skip[j];
    size_t n = (size_t)b->rows * l->out;
    for (size_t k = 0; k < n; k++)
      acc[k] += g[k];
    return;
  }
  if (b->grad) nn_gemm_gtx(b->rows, l->out, l->skip_width, g, ws->act[j], b->grad + l->wskip);
  if (j > 0 || b->want_input_grad)
    nn_gemm_gw(b->rows, l->out, l->skip_width, g, b->nn->params + l->wskip, 1.0f, ws->grad_skip[j]);
}

/* LayerNorm backward with its gamma/beta/bias gradients flushed into grad. */
static void ln_backward(const bw *b, int w, float *g, const float *y_relu, const float *xhat,
                        const float *rstd, size_t g_off, size_t be_off, size_t bias_off) {
  double *acc = b->ws->acc;
  double *dgamma = acc, *dbeta = acc + w, *dbias = acc + 2 * (size_t)w;
  int with = b->grad != NULL;
  nn_ln_backward(b->rows, w, g, y_relu, xhat, rstd, b->nn->params + g_off, with ? dgamma : NULL,
                 with ? dbeta : NULL, with && bias_off != NN_NONE ? dbias : NULL);
  if (!with) return;
  nn_flush(w, dgamma, b->grad + g_off);
  nn_flush(w, dbeta, b->grad + be_off);
  if (bias_off != NN_NONE) nn_flush(w, dbias, b->grad + bias_off);
}

/* Layer i: g = dL/d(output) on entry (may be modified); writes dL/d(input) into dx unless
 * dx == NULL. Returns the buffer holding dL/d(input) (dx, or g for in-place layers). */
static float *layer_backward(const bw *b, int i, float *g, float *dx) {
  const nn_network *nn = b->nn;
  const nn_layer *l = &nn->layers[i];
  nn_workspace *ws = b->ws;
  const nn_layer_buffers *lb = &ws->layer[i];
  const float *p = nn->params, *x = ws->act[i], *y = ws->act[i + 1];
  switch (l->kind) {
  case NBRDF_NN_RELU:
    nn_relu_backward((size_t)b->rows * l->out, g, y);
    return g;
  case NBRDF_NN_LAYERNORM:
    ln_backward(b, l->out, g, NULL, lb->z1, lb->r1, l->g1, l->be1, NN_NONE);
    return g;
  case NBRDF_NN_LINEAR:
  case NBRDF_NN_PLAIN:
    if (l->kind == NBRDF_NN_PLAIN)
      ln_backward(b, l->out, g, y, lb->z1, lb->r1, l->g1, l->be1, l->b1);
    linear_params(b, l->w1, l->kind == NBRDF_NN_LINEAR ? l->b1 : NN_NONE, l->out, l->in, g, x);
    skip_backward(b, l, g);
    if (dx) nn_gemm_gw(b->rows, l->out, l->in, g, p + l->w1, 0.0f, dx);
    return dx;
  case NBRDF_NN_RESIDUAL: {
    ln_backward(b, l->out, g, y, lb->z2, lb->r2, l->g2, l->be2, l->b2);
    linear_params(b, l->w2, NN_NONE, l->out, l->hidden, g, lb->h);
    skip_backward(b, l, g);
    float *gh = ws->grad_hidden;
    nn_gemm_gw(b->rows, l->out, l->hidden, g, p + l->w2, 0.0f, gh);
    ln_backward(b, l->hidden, gh, lb->h, lb->z1, lb->r1, l->g1, l->be1, l->b1);
    linear_params(b, l->w1, NN_NONE, l->hidden, l->in, gh, x);
    if (!dx) return NULL;
    /* The identity path of the block, then the bottleneck's share on top. */
    memcpy(dx, g, sizeof(float) * (size_t)b->rows * l->in);
    nn_gemm_gw(b->rows, l->hidden, l->in, gh, p + l->w1, 1.0f, dx);
    return dx;
  }
  }
  return NULL;
}

nbrdf_status nn_backward(const nn_network *nn, nn_workspace *ws, const float *dy, float *dx,
                         float *grad, nbrdf_error *err) {
  if (!nn || !ws || !dy)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "network backward: NULL %s",
                     !nn   ? "network"
                     : !ws ? "workspace"
                           : "output gradient");
  if (ws->mode != NBRDF_NN_TRAIN)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "network backward: the workspace was made for inference only");
  if (!nn_same_spec(&nn->spec, &ws->spec))
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "network backward: the workspace was made for another architecture");
  if (!ws->has_fresh)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "network backward: no forward pass to differentiate (call forward first; "
                     "each forward allows one backward)");
  ws->has_fresh = 0;
  const int L = nn->spec.n_layers, rows = ws->batch;
  bw b = {nn, ws, rows, grad, dx != NULL};
  for (int j = 0; j < L; j++)
    if (ws->grad_skip[j] && (j > 0 || b.want_input_grad))
      memset(ws->grad_skip[j], 0, sizeof(float) * (size_t)rows * nn->widths[j]);
  memset(ws->acc, 0, sizeof(double) * 4 * (size_t)nn->max_width);
  float *g = ws->grad_chain[0];
  memcpy(g, dy, sizeof(float) * (size_t)rows * nn->widths[L]);
  for (int i = L - 1; i >= 0; i--) {
    float *target;
    if (i > 0)
      target = g == ws->grad_chain[0] ? ws->grad_chain[1] : ws->grad_chain[0];
    else
      target = dx; /* NULL: the input's gradient is not wanted */
    /* RELU and LAYERNORM work in place: their result must still end up in dx. */
    float *got = layer_backward(&b, i, g, target);
    if (i == 0 && dx && got != dx) memcpy(dx, got, sizeof(float) * (size_t)rows * nn->widths[0]);
    if (i > 0) g = got;
    if (ws->grad_skip[i] && (i > 0 || dx)) {
      float *dst = i > 0 ? g : dx;
      const float *acc = ws->grad_skip[i];
      size_t n = (size_t)rows * nn->widths[i];
      for (size_t k = 0; k < n; k++)
        dst[k] += acc[k];
    }
  }
  return NBRDF_OK;
}
