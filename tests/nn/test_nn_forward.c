/* Forward pass against a naive double-precision reference written from the block definitions
 * in src/nn/nn.h; training vs inference workspaces, chunking, batch 1; misuse is refused. */
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "nn/nn.h"
#include "testing.h"

#define MAXW 64

/* ---- reference: one row at a time, in double, straight from the definitions ---- */

static void ref_linear(const float *w, const float *b, int in, int out, const double *x,
                       double *y) {
  for (int o = 0; o < out; o++) {
    double s = b ? b[o] : 0.0;
    for (int i = 0; i < in; i++)
      s += (double)w[(size_t)o * in + i] * x[i];
    y[o] = s;
  }
}

static void ref_ln(const float *gamma, const float *beta, int w, double *u, int relu) {
  double mean = 0, var = 0;
  for (int c = 0; c < w; c++)
    mean += u[c];
  mean /= w;
  for (int c = 0; c < w; c++)
    var += (u[c] - mean) * (u[c] - mean);
  var /= w;
  for (int c = 0; c < w; c++) {
    double v = (u[c] - mean) / sqrt(var + 1e-5) * gamma[c] + beta[c];
    u[c] = relu && v < 0 ? 0 : v;
  }
}

static const float *P(const nn_network *nn, int layer, const char *part) {
  char name[64];
  snprintf(name, sizeof name, "layers.%d.%s", layer, part);
  const nn_tensor *t = nn_find_tensor(nn, name);
  return t ? nn_params_const(nn) + t->offset : NULL;
}

static void ref_forward(const nn_network *nn, const float *x, double *y) {
  const nn_spec *s = nn_get_spec(nn);
  static double act[NBRDF_NN_MAX_LAYERS + 1][MAXW];
  int w[NBRDF_NN_MAX_LAYERS + 1];
  w[0] = s->n_inputs;
  for (int c = 0; c < w[0]; c++)
    act[0][c] = x[c];
  for (int i = 0; i < s->n_layers; i++) {
    const nn_layer_spec *l = &s->layers[i];
    const double *in = act[i];
    double *out = act[i + 1], skip[MAXW] = {0}, h[MAXW];
    int win = w[i];
    int wout = l->kind == NBRDF_NN_LINEAR || l->kind == NBRDF_NN_PLAIN ? l->width : win;
    w[i + 1] = wout;
    if (l->has_skip) {
      const float *ps = P(nn, i, "skip.weight");
      if (ps)
        ref_linear(ps, NULL, w[l->skip_from], wout, act[l->skip_from], skip);
      else
        for (int c = 0; c < wout; c++)
          skip[c] = act[l->skip_from][c];
    }
    switch (l->kind) {
    case NBRDF_NN_LINEAR:
      ref_linear(P(nn, i, "weight"), P(nn, i, "bias"), win, wout, in, out);
      for (int c = 0; c < wout; c++)
        out[c] += skip[c];
      break;
    case NBRDF_NN_PLAIN:
      ref_linear(P(nn, i, "fc.weight"), P(nn, i, "fc.bias"), win, wout, in, out);
      for (int c = 0; c < wout; c++)
        out[c] += skip[c];
      ref_ln(P(nn, i, "norm.weight"), P(nn, i, "norm.bias"), wout, out, 1);
      break;
    case NBRDF_NN_RESIDUAL: {
      int hid = l->hidden ? l->hidden : win / 2;
      ref_linear(P(nn, i, "fc1.weight"), P(nn, i, "fc1.bias"), win, hid, in, h);
      ref_ln(P(nn, i, "norm1.weight"), P(nn, i, "norm1.bias"), hid, h, 1);
      ref_linear(P(nn, i, "fc2.weight"), P(nn, i, "fc2.bias"), hid, wout, h, out);
      for (int c = 0; c < wout; c++)
        out[c] += in[c] + skip[c];
      ref_ln(P(nn, i, "norm2.weight"), P(nn, i, "norm2.bias"), wout, out, 1);
      break;
    }
    case NBRDF_NN_LAYERNORM:
      for (int c = 0; c < wout; c++)
        out[c] = in[c];
      ref_ln(P(nn, i, "weight"), P(nn, i, "bias"), wout, out, 0);
      break;
    case NBRDF_NN_RELU:
      for (int c = 0; c < wout; c++)
        out[c] = in[c] < 0 ? 0 : in[c];
      break;
    }
  }
  for (int c = 0; c < w[s->n_layers]; c++)
    y[c] = act[s->n_layers][c];
}

/* ---- fixtures ---- */

/* Every block kind, identity and projected skips, widths that are not multiples of 8. */
static nn_network *make_mixed(uint64_t seed) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  nn_spec_init(&s, 13);
  nn_spec_add(&s, NBRDF_NN_PLAIN, 36);
  int r = nn_spec_add(&s, NBRDF_NN_RESIDUAL, 0);
  nn_spec_skip(&s, r, 0);
  nn_spec_add(&s, NBRDF_NN_LINEAR, 20);
  nn_spec_add(&s, NBRDF_NN_LAYERNORM, 0);
  nn_spec_add(&s, NBRDF_NN_RELU, 0);
  int p = nn_spec_add(&s, NBRDF_NN_PLAIN, 36);
  nn_spec_skip(&s, p, 2);
  int o = nn_spec_add(&s, NBRDF_NN_LINEAR, 3);
  nn_spec_skip(&s, o, 0);
  nn_network *nn = NULL;
  CHECK_OK(nn_create(&s, &nn, err), err);
  if (!nn) return NULL;
  nn_init_params(nn, seed);
  core_rng rng;
  core_rng_init(&rng, seed, 5);
  float *q = nn_params(nn);
  for (size_t i = 0; i < nn_param_count(nn); i++)
    q[i] += (float)(0.2 * core_rng_normal(&rng));
  return nn;
}

static float *random_rows(int rows, int w, uint64_t seed) {
  float *x = malloc(sizeof(float) * (size_t)rows * w);
  core_rng rng;
  core_rng_init(&rng, seed, 0);
  for (int i = 0; i < rows * w; i++)
    x[i] = (float)core_rng_normal(&rng);
  return x;
}

static void test_matches_reference(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_network *nn = make_mixed(3);
  if (!nn) return;
  const int rows = 37, in = nn_inputs(nn), out = nn_outputs(nn);
  float *x = random_rows(rows, in, 11), y[37 * 3];
  nn_workspace *ws = NULL;
  CHECK_OK(nn_workspace_create(nn, rows, NBRDF_NN_TRAIN, &ws, err), err);
  CHECK_OK(nn_forward(nn, ws, x, rows, y, err), err);
  /* Float32 rounding through seven layers: about 1e-6 of the outputs' scale. */
  static double ref[37][MAXW];
  double rms = 0, worst = 0;
  for (int r = 0; r < rows; r++) {
    ref_forward(nn, x + r * in, ref[r]);
    for (int c = 0; c < out; c++)
      rms += ref[r][c] * ref[r][c] / (rows * out);
  }
  rms = sqrt(rms);
  CHECK(rms > 0.1);
  for (int r = 0; r < rows; r++)
    for (int c = 0; c < out; c++) {
      double e = fabs(y[r * out + c] - ref[r][c]) / (rms + fabs(ref[r][c]));
      if (e > worst) worst = e;
    }
  CHECK_MSG(worst < 1e-5, "forward differs from the reference by %.3g (relative)", worst);
  nn_workspace_destroy(ws);
  free(x);
  nn_destroy(nn);
}

/* Inference (ping-pong buffers, chunks of max_batch, sgemv for one row) agrees with training
 * mode; the same input row gives the same output whatever batch it comes in. */
static void test_modes_and_chunks(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_network *nn = make_mixed(4);
  if (!nn) return;
  const int rows = 100, in = nn_inputs(nn), out = nn_outputs(nn);
  float *x = random_rows(rows, in, 12), ya[300], yb[300], yc[300];
  nn_workspace *wt = NULL, *wi = NULL, *w1 = NULL;
  CHECK_OK(nn_workspace_create(nn, rows, NBRDF_NN_TRAIN, &wt, err), err);
  CHECK_OK(nn_workspace_create(nn, 7, NBRDF_NN_INFER, &wi, err), err);
  CHECK_OK(nn_workspace_create(nn, 1, NBRDF_NN_INFER, &w1, err), err);
  CHECK(nn_workspace_max_batch(wi) == 7);
  CHECK_OK(nn_forward(nn, wt, x, rows, ya, err), err);
  CHECK_OK(nn_forward(nn, wi, x, rows, yb, err), err);
  CHECK_OK(nn_forward(nn, w1, x, rows, yc, err), err);
  for (int i = 0; i < rows * out; i++) {
    CHECK_REL(ya[i], yb[i], 1e-5, 1e-6);
    CHECK_REL(ya[i], yc[i], 1e-5, 1e-6);
  }
  /* Deterministic: the same call twice gives the same bits. */
  CHECK_OK(nn_forward(nn, wi, x, rows, yc, err), err);
  CHECK(memcmp(yb, yc, sizeof(float) * rows * out) == 0);
  /* A batch larger than the inference block (about 2 MiB per buffer: 14560 rows at width 36)
   * is processed block by block, and the workspace does not grow with max_batch. */
  const nn_spec *spec = nn_get_spec(nn);
  CHECK(nn_workspace_bytes(spec, 1 << 20, NBRDF_NN_INFER) ==
        nn_workspace_bytes(spec, 14560, NBRDF_NN_INFER));
  CHECK(nn_workspace_bytes(spec, 14560, NBRDF_NN_INFER) >
        nn_workspace_bytes(spec, 14000, NBRDF_NN_INFER));
  enum { BIG = 20000 };
  float *xb = random_rows(BIG, in, 14), *yd = malloc(sizeof(float) * BIG * out),
        *ye = malloc(sizeof(float) * BIG * out);
  nn_workspace *wbig = NULL, *wsmall = NULL;
  CHECK_OK(nn_workspace_create(nn, 1 << 20, NBRDF_NN_INFER, &wbig, err), err);
  CHECK_OK(nn_workspace_create(nn, 999, NBRDF_NN_INFER, &wsmall, err), err);
  CHECK_OK(nn_forward(nn, wbig, xb, BIG, yd, err), err);
  CHECK_OK(nn_forward(nn, wsmall, xb, BIG, ye, err), err);
  int differ = 0;
  for (int i = 0; i < BIG * out; i++)
    differ += !(fabsf(yd[i] - ye[i]) <= 1e-5f * (1.0f + fabsf(ye[i])));
  CHECK_MSG(differ == 0, "%d outputs differ between inference block sizes", differ);
  nn_workspace_destroy(wbig);
  nn_workspace_destroy(wsmall);
  free(xb);
  free(yd);
  free(ye);
  size_t train = nn_workspace_bytes(nn_get_spec(nn), 1000, NBRDF_NN_TRAIN);
  size_t infer = nn_workspace_bytes(nn_get_spec(nn), 1000, NBRDF_NN_INFER);
  CHECK(infer > 0 && train > 2 * infer);
  nn_workspace_destroy(wt);
  nn_workspace_destroy(wi);
  nn_workspace_destroy(w1);
  free(x);
  nn_destroy(nn);
}

/* One network, one workspace per thread, used at the same time: the same numbers as alone,
 * within float rounding. The threads call the BLAS from inside a parallel region, where an
 * OpenMP build of OpenBLAS runs each call on one thread while the lone call may use several
 * (and OPENBLAS_NUM_THREADS changes the GEMMs' last bits, nn.h): 1e-5 relative, as between
 * batch shapes above. The two threads' calls are alike in every way: the same bits. A race
 * on shared state would be off by far more. */
static void test_threads_share_a_network(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_network *nn = make_mixed(6);
  if (!nn) return;
  enum { ROWS = 300, T = 2 };
  const int in = nn_inputs(nn), out = nn_outputs(nn);
  float *x = random_rows(ROWS, in, 13), alone[ROWS * 3], together[T][ROWS * 3];
  nn_workspace *ws[T] = {NULL, NULL};
  for (int t = 0; t < T; t++)
    CHECK_OK(nn_workspace_create(nn, ROWS, NBRDF_NN_TRAIN, &ws[t], err), err);
  CHECK_OK(nn_forward(nn, ws[0], x, ROWS, alone, err), err);
  int failures = 0;
#pragma omp parallel for num_threads(T) reduction(+ : failures)
  for (int t = 0; t < T; t++)
    for (int rep = 0; rep < 20; rep++)
      failures += nn_forward(nn, ws[t], x, ROWS, together[t], NULL) != NBRDF_OK;
  CHECK(failures == 0);
  for (int t = 0; t < T; t++)
    for (int i = 0; i < ROWS * out; i++)
      CHECK_REL(alone[i], together[t][i], 1e-5, 1e-6);
  CHECK(memcmp(together[0], together[1], sizeof(float) * ROWS * out) == 0);
  for (int t = 0; t < T; t++)
    nn_workspace_destroy(ws[t]);
  free(x);
  nn_destroy(nn);
}

static void test_misuse_refused(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_network *nn = make_mixed(5);
  if (!nn) return;
  float x[4 * 13] = {0}, y[4 * 3], g[4 * 3] = {0};
  nn_workspace *wt = NULL, *wi = NULL, *other = NULL;
  CHECK_FAILS(nn_workspace_create(nn, 0, NBRDF_NN_TRAIN, &wt, err), NBRDF_ERR_ARGUMENT, err,
              "max_batch = 0");
  CHECK(wt == NULL);
  CHECK_OK(nn_workspace_create(nn, 2, NBRDF_NN_TRAIN, &wt, err), err);
  CHECK_OK(nn_workspace_create(nn, 2, NBRDF_NN_INFER, &wi, err), err);
  CHECK_FAILS(nn_backward(nn, wt, g, NULL, NULL, err), NBRDF_ERR_ARGUMENT, err, "no forward pass");
  CHECK_FAILS(nn_forward(nn, wt, x, 4, y, err), NBRDF_ERR_ARGUMENT, err, "batch 4 exceeds");
  CHECK_FAILS(nn_forward(nn, wt, x, 0, y, err), NBRDF_ERR_ARGUMENT, err, "batch = 0");
  CHECK_FAILS(nn_forward(nn, wt, NULL, 1, y, err), NBRDF_ERR_ARGUMENT, err, "NULL input");
  CHECK_OK(nn_forward(nn, wi, x, 4, y, err), err); /* inference chunks instead */
  CHECK_FAILS(nn_backward(nn, wi, g, NULL, NULL, err), NBRDF_ERR_ARGUMENT, err, "inference only");
  CHECK_OK(nn_forward(nn, wt, x, 2, y, err), err);
  CHECK_OK(nn_backward(nn, wt, g, NULL, NULL, err), err);
  CHECK_FAILS(nn_backward(nn, wt, g, NULL, NULL, err), NBRDF_ERR_ARGUMENT, err,
              "each forward allows one backward");
  nn_spec s;
  nn_spec_init(&s, 13);
  nn_spec_add(&s, NBRDF_NN_LINEAR, 3);
  nn_network *small = NULL;
  CHECK_OK(nn_create(&s, &small, err), err);
  CHECK_OK(nn_workspace_create(small, 2, NBRDF_NN_INFER, &other, err), err);
  CHECK_FAILS(nn_forward(nn, other, x, 1, y, err), NBRDF_ERR_MISMATCH, err, "another architecture");
  nn_workspace_destroy(wt);
  nn_workspace_destroy(wi);
  nn_workspace_destroy(other);
  nn_destroy(small);
  nn_destroy(nn);
}

int main(void) {
  RUN(test_matches_reference);
  RUN(test_modes_and_chunks);
  RUN(test_threads_share_a_network);
  RUN(test_misuse_refused);
  return testing_finish();
}
