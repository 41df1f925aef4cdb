/* gpu_plan.h: the steps of a forward pass. */
#include "gpu/gpu_plan.h"

#include <string.h>

#include "core/error.h"
#include "nn/internal.h"

static int add_buffer(gpu_plan *p, int width) {
  p->buffer_width[p->n_buffers] = width;
  p->floats_per_row += width;
  if (width > p->max_width) p->max_width = width;
  return p->n_buffers++;
}

static gpu_step *add_step(gpu_plan *p, gpu_step_kind kind, int x, int y) {
  gpu_step *s = &p->steps[p->n_steps++];
  memset(s, 0, sizeof *s);
  s->kind = kind;
  s->x = x, s->y = y, s->a1 = -1, s->a2 = -1;
  return s;
}

static void gemm(gpu_plan *p, int x, int y, int K, int N, size_t w, size_t b, uint32_t flags,
                 int a1, int a2) {
  gpu_step *s = add_step(p, GPU_STEP_GEMM, x, y);
  s->a1 = a1, s->a2 = a2;
  s->push.K = (uint32_t)K, s->push.N = (uint32_t)N;
  s->push.w_off = (uint32_t)w;
  s->push.b_off = b == NN_NONE ? 0u : (uint32_t)b;
  s->push.flags = flags | (b == NN_NONE ? 0u : GPU_BIAS) | (a1 >= 0 ? GPU_ADD1 : 0u) |
                  (a2 >= 0 ? GPU_ADD2 : 0u);
}

static void rownorm(gpu_plan *p, int y, int N, size_t g, size_t be, uint32_t flags) {
  gpu_step *s = add_step(p, GPU_STEP_ROWNORM, -1, y);
  s->push.N = (uint32_t)N;
  s->push.flags = flags;
  s->push.g_off = g == NN_NONE ? 0u : (uint32_t)g;
  s->push.be_off = be == NN_NONE ? 0u : (uint32_t)be;
}

nbrdf_status gpu_plan_make(const nn_network *nn, gpu_plan *p, nbrdf_error *err) {
  memset(p, 0, sizeof *p);
  const int L = nn->spec.n_layers;
  if (nn->n_params >= UINT32_MAX)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "GPU: %zu parameters (at most 2^32)",
                     nn->n_params);
  int act[NBRDF_NN_MAX_LAYERS + 1];
  act[0] = p->input = add_buffer(p, nn->widths[0]);
  int pingpong[2] = {-1, -1}, hidden = -1, hidden_width = 0;
  for (int i = 0; i < L; i++)
    if (nn->layers[i].kind == NBRDF_NN_RESIDUAL && nn->layers[i].hidden > hidden_width)
      hidden_width = nn->layers[i].hidden;
  if (hidden_width) hidden = add_buffer(p, hidden_width);
  for (int i = 0; i < L; i++) {
    const nn_layer *l = &nn->layers[i];
    int y;
    if (i == L - 1)
      y = p->output = add_buffer(p, nn->widths[L]);
    else if (nn->skip_source[i + 1])
      y = add_buffer(p, nn->widths[i + 1]);
    else {
      int k = (i + 1) & 1;
      if (pingpong[k] < 0) pingpong[k] = add_buffer(p, nn->max_width);
      y = pingpong[k];
    }
    act[i + 1] = y;
    const int x = act[i];
    const int skip = l->skip_from >= 0 ? act[l->skip_from] : -1;
    const int projected = skip >= 0 && l->wskip != NN_NONE;
    const int identity = skip >= 0 && !projected ? skip : -1;
    const uint32_t acc = projected ? GPU_ACCUMULATE : 0u;
    switch (l->kind) {
    case NBRDF_NN_LINEAR:
    case NBRDF_NN_PLAIN:
      if (projected) gemm(p, skip, y, l->skip_width, l->out, l->wskip, NN_NONE, 0u, -1, -1);
      gemm(p, x, y, l->in, l->out, l->w1, l->b1, acc, -1, identity);
      if (l->kind == NBRDF_NN_PLAIN) rownorm(p, y, l->out, l->g1, l->be1, GPU_NORM | GPU_RELU);
      break;
    case NBRDF_NN_RESIDUAL:
      gemm(p, x, hidden, l->in, l->hidden, l->w1, l->b1, 0u, -1, -1);
      rownorm(p, hidden, l->hidden, l->g1, l->be1, GPU_NORM | GPU_RELU);
      if (projected) gemm(p, skip, y, l->skip_width, l->out, l->wskip, NN_NONE, 0u, -1, -1);
      gemm(p, hidden, y, l->hidden, l->out, l->w2, l->b2, acc, x, identity);
      rownorm(p, y, l->out, l->g2, l->be2, GPU_NORM | GPU_RELU);
      break;
    case NBRDF_NN_LAYERNORM:
    case NBRDF_NN_RELU: {
      gpu_step *s = add_step(p, GPU_STEP_COPY, x, y);
      s->push.N = (uint32_t)l->out;
      if (l->kind == NBRDF_NN_LAYERNORM)
        rownorm(p, y, l->out, l->g1, l->be1, GPU_NORM);
      else
        rownorm(p, y, l->out, NN_NONE, NN_NONE, GPU_RELU);
      break;
    }
    }
  }
  return NBRDF_OK;
}
