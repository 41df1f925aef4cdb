/* A tiny end-to-end training: a residual MLP learns the projected GGX normal distribution
 * D(h) cos(theta_h) over the unit disk of projected half vectors (alpha = 0.4) with Adam.
 * The held-out loss must fall by a large factor, and two runs with one seed must agree bit
 * for bit. Also: projection-style optimisation of an input column with the network frozen. */
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "nn/nn.h"
#include "testing.h"

#define BATCH 256
#define EVAL 512
#define STEPS 400

/* GGX / Trowbridge-Reitz NDF times cos(theta_h) at projected half vector (hx, hy). */
static float target(float hx, float hy) {
  const double alpha = 0.4, a2 = alpha * alpha;
  double s2 = (double)hx * hx + (double)hy * hy, c2 = 1.0 - s2;
  double d = c2 * (a2 - 1.0) + 1.0;
  return (float)(a2 / (M_PI * d * d) * sqrt(c2));
}

static void sample(core_rng *rng, float *x, float *t, int n) {
  for (int i = 0; i < n; i++) {
    double r = sqrt(core_rng_uniform(rng)) * 0.999, phi = 2 * M_PI * core_rng_uniform(rng);
    x[2 * i] = (float)(r * cos(phi));
    x[2 * i + 1] = (float)(r * sin(phi));
    t[i] = target(x[2 * i], x[2 * i + 1]);
  }
}

static double mse(const float *y, const float *t, int n, float *dy) {
  double l = 0;
  for (int i = 0; i < n; i++) {
    double d = (double)y[i] - t[i];
    l += d * d / n;
    if (dy) dy[i] = (float)(2.0 * d / n);
  }
  return l;
}

/* Trains from seed; returns the initial and final held-out MSE. */
static void train(uint64_t seed, double *first, double *last, float *final_params) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  CHECK_OK(nn_spec_resmlp(&s, 2, 32, 2, 1, 1, err), err);
  nn_network *nn = NULL;
  nn_workspace *ws = NULL, *wi = NULL;
  nn_adam *adam = NULL;
  CHECK_OK(nn_create(&s, &nn, err), err);
  if (!nn) return;
  nn_init_params(nn, seed);
  size_t n = nn_param_count(nn);
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = 3e-3f;
  o.decay_every = 150;
  o.decay_gamma = 0.5f;
  CHECK_OK(nn_workspace_create(nn, BATCH, NBRDF_NN_TRAIN, &ws, err), err);
  CHECK_OK(nn_workspace_create(nn, EVAL, NBRDF_NN_INFER, &wi, err), err);
  CHECK_OK(nn_adam_create(n, &o, &adam, err), err);
  float *grad = malloc(n * sizeof *grad);
  static float ex[2 * EVAL], et[EVAL], ey[EVAL], x[2 * BATCH], t[BATCH], y[BATCH], dy[BATCH];
  core_rng rng;
  core_rng_init(&rng, seed, 1000);
  sample(&rng, ex, et, EVAL);
  CHECK_OK(nn_forward(nn, wi, ex, EVAL, ey, err), err);
  *first = mse(ey, et, EVAL, NULL);
  for (int step = 0; step < STEPS; step++) {
    sample(&rng, x, t, BATCH);
    CHECK_OK(nn_forward(nn, ws, x, BATCH, y, err), err);
    mse(y, t, BATCH, dy);
    memset(grad, 0, n * sizeof *grad);
    CHECK_OK(nn_backward(nn, ws, dy, NULL, grad, err), err);
    CHECK_OK(nn_adam_step(adam, nn_params(nn), grad, err), err);
  }
  CHECK_OK(nn_forward(nn, wi, ex, EVAL, ey, err), err);
  *last = mse(ey, et, EVAL, NULL);
  memcpy(final_params, nn_params(nn), n * sizeof(float));
  free(grad);
  nn_adam_destroy(adam);
  nn_workspace_destroy(ws);
  nn_workspace_destroy(wi);
  nn_destroy(nn);
}

static void test_loss_falls(void) {
  static float pa[1 << 16], pb[1 << 16];
  double first = 0, last = 1, first2 = 0, last2 = 1;
  train(7, &first, &last, pa);
  printf("  held-out MSE %.5g -> %.5g (%.0fx lower)\n", first, last, first / last);
  CHECK_MSG(first / last >= 20.0, "loss fell only %.1fx (%.4g -> %.4g)", first / last, first, last);
  train(7, &first2, &last2, pb);
  CHECK(first == first2 && last == last2);
  CHECK(memcmp(pa, pb, sizeof pa) == 0);
}

/* Projection in miniature: the network is frozen and one input column (a "latent") is fitted by
 * Adam through dL/dx, as src/model's projection does with whole latent vectors. */
static void test_input_optimisation(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  CHECK_OK(nn_spec_resmlp(&s, 3, 16, 1, 1, 1, err), err);
  nn_network *nn = NULL;
  nn_workspace *ws = NULL;
  CHECK_OK(nn_create(&s, &nn, err), err);
  if (!nn) return;
  nn_init_params(nn, 3);
  enum { R = 64 };
  CHECK_OK(nn_workspace_create(nn, R, NBRDF_NN_TRAIN, &ws, err), err);
  /* Targets: the network's own outputs at latent z* = 0.7 over random (u, v). */
  float x[3 * R], t[R], y[R], dy[R], dx[3 * R];
  core_rng rng;
  core_rng_init(&rng, 3, 0);
  for (int i = 0; i < R; i++) {
    x[3 * i] = 0.7f;
    x[3 * i + 1] = 2 * core_rng_uniformf(&rng) - 1;
    x[3 * i + 2] = 2 * core_rng_uniformf(&rng) - 1;
  }
  CHECK_OK(nn_forward(nn, ws, x, R, t, err), err);
  float z = -0.5f;
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = 0.05f;
  nn_adam *adam = NULL;
  CHECK_OK(nn_adam_create(1, &o, &adam, err), err);
  size_t n = nn_param_count(nn);
  float *before = malloc(n * sizeof *before);
  memcpy(before, nn_params(nn), n * sizeof *before);
  double l0 = 0, l = 0;
  for (int step = 0; step < 200; step++) {
    for (int i = 0; i < R; i++)
      x[3 * i] = z;
    CHECK_OK(nn_forward(nn, ws, x, R, y, err), err);
    l = mse(y, t, R, dy);
    if (step == 0) l0 = l;
    CHECK_OK(nn_backward(nn, ws, dy, dx, NULL, err), err);
    float gz = 0;
    for (int i = 0; i < R; i++)
      gz += dx[3 * i];
    CHECK_OK(nn_adam_step(adam, &z, &gz, err), err);
  }
  printf("  latent -0.5 -> %.4f (target 0.7), loss %.3g -> %.3g\n", z, l0, l);
  CHECK_NEAR(z, 0.7, 0.05);
  CHECK(l < 1e-3 * l0);
  CHECK(memcmp(before, nn_params(nn), n * sizeof *before) == 0);
  free(before);
  nn_adam_destroy(adam);
  nn_workspace_destroy(ws);
  nn_destroy(nn);
}

int main(void) {
  RUN(test_loss_falls);
  RUN(test_input_optimisation);
  return testing_finish();
}
