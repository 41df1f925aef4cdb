/* Adam against hand-computed and textbook (Kingma & Ba, Algorithm 1) updates; decoupled
 * weight decay; the step decay schedule; per-group learning rates; refusal of bad input. */
#include <stdlib.h>
#include <string.h>

#include "nn/nn.h"
#include "testing.h"

static nn_adam *make(size_t n, nn_adam_options o) {
  nbrdf_error err_s, *err = &err_s;
  nn_adam *a = NULL;
  CHECK_OK(nn_adam_create(n, &o, &a, err), err);
  return a;
}

static void test_hand_computed(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = 0.1f;
  nn_adam *a = make(2, o);
  float p[2] = {1.0f, -2.0f}, g[2] = {0.5f, -1.0f};
  /* Step 1: m = 0.1 g, v = 0.001 g^2, m_hat = g, v_hat = g^2, so p -= lr * sign(g) (eps aside). */
  CHECK_OK(nn_adam_step(a, p, g, err), err);
  CHECK_NEAR(p[0], 0.9, 1e-6);
  CHECK_NEAR(p[1], -1.9, 1e-6);
  /* Step 2 with g = (0.5, 0): m = (0.095, -0.09), v = (0.00049975, 0.000999);
   * m_hat = (0.5, -0.47368421), v_hat = (0.25, 0.49974987), step = lr m_hat / sqrt(v_hat). */
  g[1] = 0.0f;
  CHECK_OK(nn_adam_step(a, p, g, err), err);
  CHECK_NEAR(p[0], 0.8, 1e-6);
  CHECK_NEAR(p[1], -1.9 + 0.1 * 0.47368421 / sqrt(0.49974987), 1e-6);
  CHECK(nn_adam_steps(a) == 2);
  nn_adam_destroy(a);
}

/* Many steps against Algorithm 1 in double, with eps added to sqrt(v_hat) as in PyTorch. */
static void test_against_textbook(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = 0.01f;
  o.beta1 = 0.8f;
  o.beta2 = 0.99f;
  o.eps = 1e-3f;
  enum { N = 5, STEPS = 50 };
  nn_adam *a = make(N, o);
  float p[N], g[N];
  double rp[N], m[N] = {0}, v[N] = {0};
  for (int i = 0; i < N; i++)
    rp[i] = p[i] = 0.3f * (float)(i - 2);
  for (int t = 1; t <= STEPS; t++) {
    for (int i = 0; i < N; i++)
      g[i] = (float)sin(0.7 * t + i) * (float)(i + 1);
    CHECK_OK(nn_adam_step(a, p, g, err), err);
    for (int i = 0; i < N; i++) {
      m[i] = 0.8 * m[i] + 0.2 * g[i];
      v[i] = 0.99 * v[i] + 0.01 * (double)g[i] * g[i];
      double mh = m[i] / (1 - pow(0.8, t)), vh = v[i] / (1 - pow(0.99, t));
      rp[i] -= 0.01 * mh / (sqrt(vh) + 1e-3);
    }
  }
  for (int i = 0; i < N; i++)
    CHECK_NEAR(p[i], rp[i], 2e-5);
  /* reset: the same sequence again gives the same result. */
  nn_adam_reset(a);
  CHECK(nn_adam_steps(a) == 0);
  float q[N];
  for (int i = 0; i < N; i++)
    q[i] = 0.3f * (float)(i - 2);
  for (int t = 1; t <= STEPS; t++) {
    for (int i = 0; i < N; i++)
      g[i] = (float)sin(0.7 * t + i) * (float)(i + 1);
    CHECK_OK(nn_adam_step(a, q, g, err), err);
  }
  CHECK(memcmp(p, q, sizeof p) == 0);
  nn_adam_destroy(a);
}

static void test_weight_decay(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = 0.1f;
  o.weight_decay = 0.5f;
  nn_adam *a = make(1, o);
  float p = 2.0f, g = 0.0f;
  /* Zero gradient: only the decoupled decay acts, p *= 1 - lr * wd. */
  CHECK_OK(nn_adam_step(a, &p, &g, err), err);
  CHECK_NEAR(p, 2.0 * 0.95, 1e-6);
  CHECK_OK(nn_adam_step(a, &p, &g, err), err);
  CHECK_NEAR(p, 2.0 * 0.95 * 0.95, 1e-6);
  nn_adam_destroy(a);
}

static void test_step_decay(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = 0.1f;
  o.decay_every = 3;
  o.decay_gamma = 0.5f;
  o.eps = 0.0f;
  nn_adam *a = make(1, o);
  /* With a constant gradient m_hat / sqrt(v_hat) = 1, so each step moves p by lr(t). */
  float p = 0.0f, g = 1.0f;
  const double want[9] = {0.1, 0.1, 0.1, 0.05, 0.05, 0.05, 0.025, 0.025, 0.025};
  for (int t = 0; t < 9; t++) {
    CHECK_NEAR(nn_adam_lr(a, 0), want[t], 1e-7);
    float before = p;
    CHECK_OK(nn_adam_step(a, &p, &g, err), err);
    CHECK_NEAR(before - p, want[t], 1e-6);
  }
  CHECK_NEAR(nn_adam_lr(a, 0), 0.0125, 1e-7);
  CHECK(nn_adam_lr(a, 5) == 0.0f);
  nn_adam_destroy(a);
}

static void test_groups(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = 0.1f;
  o.eps = 0.0f;
  o.decay_every = 1;
  o.decay_gamma = 0.5f;
  nn_adam *a = make(6, o);
  int g1 = 0, g2 = 0;
  CHECK_OK(nn_adam_add_group(a, 1, 3, 0.4f, 0.0f, &g1, err), err); /* [1, 4) */
  CHECK_OK(nn_adam_add_group(a, 3, 2, 0.0f, 0.0f, &g2, err), err); /* [3, 5) overrides */
  CHECK(g1 == 1 && g2 == 2);
  float p[6] = {0}, g[6] = {1, 1, 1, 1, 1, -1};
  CHECK_OK(nn_adam_step(a, p, g, err), err);
  const float want[6] = {-0.1f, -0.4f, -0.4f, 0.0f, 0.0f, 0.1f};
  for (int i = 0; i < 6; i++)
    CHECK_NEAR(p[i], want[i], 1e-6);
  /* The schedule scales every group. */
  CHECK_NEAR(nn_adam_lr(a, g1), 0.2, 1e-7);
  CHECK_NEAR(nn_adam_lr(a, 0), 0.05, 1e-7);
  CHECK_FAILS(nn_adam_add_group(a, 4, 3, 0.1f, 0.0f, NULL, err), NBRDF_ERR_ARGUMENT, err,
              "outside the 6 parameters");
  CHECK_FAILS(nn_adam_add_group(a, 0, 0, 0.1f, 0.0f, NULL, err), NBRDF_ERR_ARGUMENT, err, "empty");
  CHECK_FAILS(nn_adam_add_group(a, 0, 1, -0.1f, 0.0f, NULL, err), NBRDF_ERR_ARGUMENT, err, "lr");
  nn_adam_destroy(a);
}

/* Groups by tensor name on a network's parameter array, e.g. no decay on LayerNorm. */
static void test_groups_by_tensor(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  CHECK_OK(nn_spec_resmlp(&s, 4, 8, 1, 0, 2, err), err);
  nn_network *nn = NULL;
  CHECK_OK(nn_create(&s, &nn, err), err);
  size_t n = nn_param_count(nn);
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = 0.01f;
  nn_adam *a = make(n, o);
  int frozen = 0;
  CHECK_OK(nn_adam_add_group_tensors(a, nn, "norm", 0.0f, 0.0f, &frozen, err), err);
  CHECK_FAILS(nn_adam_add_group_tensors(a, nn, "conv", 0.0f, 0.0f, NULL, err), NBRDF_ERR_ARGUMENT,
              err, "no tensor name contains \"conv\"");
  nn_init_params(nn, 1);
  float *p = nn_params(nn), *before = malloc(n * sizeof *p), *g = malloc(n * sizeof *g);
  memcpy(before, p, n * sizeof *p);
  for (size_t i = 0; i < n; i++)
    g[i] = 1.0f;
  CHECK_OK(nn_adam_step(a, p, g, err), err);
  for (int k = 0; k < nn_tensor_count(nn); k++) {
    const nn_tensor *t = nn_tensor_at(nn, k);
    int is_norm = strstr(t->name, "norm") != NULL;
    for (size_t i = t->offset; i < t->offset + t->count; i++)
      CHECK_MSG(is_norm ? p[i] == before[i] : fabs(before[i] - p[i] - 0.01) < 1e-6, "%s: %g -> %g",
                t->name, before[i], p[i]);
  }
  nn_adam *wrong = make(n + 1, o);
  CHECK_FAILS(nn_adam_add_group_tensors(wrong, nn, "norm", 0.0f, 0.0f, NULL, err),
              NBRDF_ERR_MISMATCH, err, "network has");
  nn_adam_destroy(wrong);
  free(before);
  free(g);
  nn_adam_destroy(a);
  nn_destroy(nn);
}

static void test_refusals(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_adam *a = NULL;
  nn_adam_options o = NBRDF_ADAM_OPTIONS_DEFAULT;
  o.beta1 = 1.0f;
  CHECK_FAILS(nn_adam_create(4, &o, &a, err), NBRDF_ERR_ARGUMENT, err, "beta1");
  o = (nn_adam_options)NBRDF_ADAM_OPTIONS_DEFAULT;
  o.lr = NAN;
  CHECK_FAILS(nn_adam_create(4, &o, &a, err), NBRDF_ERR_ARGUMENT, err, "adam lr is NaN");
  o = (nn_adam_options)NBRDF_ADAM_OPTIONS_DEFAULT;
  o.decay_gamma = 0.0f;
  CHECK_FAILS(nn_adam_create(4, &o, &a, err), NBRDF_ERR_ARGUMENT, err, "decay_gamma");
  CHECK_FAILS(nn_adam_create(0, NULL, &a, err), NBRDF_ERR_ARGUMENT, err, "no parameters");
  CHECK(a == NULL);
  CHECK_OK(nn_adam_create(3, NULL, &a, err), err); /* NULL options: the defaults */
  float p[3] = {1, 2, 3}, g[3] = {0.1f, INFINITY, 0.2f};
  CHECK_FAILS(nn_adam_step(a, p, g, err), NBRDF_ERR_ARGUMENT, err, "gradient 1 is inf");
  CHECK(p[0] == 1 && p[1] == 2 && p[2] == 3 && nn_adam_steps(a) == 0);
  g[1] = NAN;
  CHECK_FAILS(nn_adam_step(a, p, g, err), NBRDF_ERR_ARGUMENT, err, "gradient 1 is nan");
  nn_adam_destroy(a);
}

int main(void) {
  RUN(test_hand_computed);
  RUN(test_against_textbook);
  RUN(test_weight_decay);
  RUN(test_step_decay);
  RUN(test_groups);
  RUN(test_groups_by_tensor);
  RUN(test_refusals);
  return testing_finish();
}
