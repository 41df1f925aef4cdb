/* Finite-difference checks of nn_backward: every block kind and whole networks shaped
 * like the decoder, the layering and the sampling networks, with respect to parameters AND
 * inputs. The loss is L = sum(c * y) with fixed random c, so dL/dy = c. */
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "nn/nn.h"
#include "testing.h"

#define B 4
#define MAX_IN 64

/* Sabotage of the analytic gradient, to show that the check fails when it should. */
typedef enum { GC_HONEST, GC_FLIP_TENSOR, GC_ZERO_TENSOR, GC_FLIP_INPUT } gc_sabotage;

typedef struct gc {
  nn_network *nn;
  nn_workspace *ws;
  float x[B * MAX_IN], c[B * MAX_IN], y[B * MAX_IN];
  int in, out;
} gc;

static double loss(gc *g) {
  nbrdf_error err_s, *err = &err_s;
  CHECK_OK(nn_forward(g->nn, g->ws, g->x, B, g->y, err), err);
  double l = 0;
  for (int i = 0; i < B * g->out; i++)
    l += (double)g->c[i] * g->y[i];
  return l;
}

/* Central difference of L in *v, at step h. */
static double fd(gc *g, float *v, double h) {
  float keep = *v;
  *v = (float)(keep + h);
  double lp = loss(g);
  *v = (float)(keep - h);
  double lm = loss(g);
  double step = (double)(float)(keep + h) - (double)(float)(keep - h);
  *v = keep;
  return (lp - lm) / step;
}

/* Agreement at one coordinate. A ReLU kink inside [v - h, v + h] spoils a difference, so a
 * mismatch is re-tried with a 10x smaller step before it counts. */
static int agrees(gc *g, float *v, double analytic, const char *what, int index, int verbose) {
  double best = 1e30, num = 0;
  for (double h = 1e-2; h > 1e-4; h *= 0.1) {
    num = fd(g, v, h);
    double tol = 2e-2 * fmax(fabs(num), fabs(analytic)) + 2e-3;
    double e = fabs(num - analytic) / tol;
    if (e < best) best = e;
    if (e <= 1.0) return 1;
  }
  if (verbose)
    fprintf(stderr, "  mismatch %s[%d]: analytic %.6g, numeric %.6g\n", what, index, analytic, num);
  return 0;
}

/* Checks the network's gradients; returns the number of coordinates that disagree. */
static int grad_check(nn_network *nn, uint64_t seed, gc_sabotage sabotage, int verbose) {
  nbrdf_error err_s, *err = &err_s;
  static gc g;
  memset(&g, 0, sizeof g);
  g.nn = nn;
  g.in = nn_inputs(nn);
  g.out = nn_outputs(nn);
  CHECK(g.in <= MAX_IN && g.out <= MAX_IN);
  CHECK_OK(nn_workspace_create(nn, B, NBRDF_NN_TRAIN, &g.ws, err), err);
  /* Parameters away from their initial 1/0 values, so that every term of every gradient
   * matters (a missing gamma factor would hide behind gamma = 1). */
  nn_init_params(nn, seed);
  core_rng rng;
  core_rng_init(&rng, seed, 99);
  float *p = nn_params(nn);
  size_t np = nn_param_count(nn);
  for (size_t i = 0; i < np; i++)
    p[i] += (float)(0.3 * core_rng_normal(&rng));
  for (int i = 0; i < B * g.in; i++)
    g.x[i] = (float)core_rng_normal(&rng);
  for (int i = 0; i < B * g.out; i++)
    g.c[i] = (float)(2.0 * core_rng_uniform(&rng) - 1.0);

  float *grad = calloc(np, sizeof *grad);
  float dx[B * MAX_IN];
  loss(&g);
  CHECK_OK(nn_backward(nn, g.ws, g.c, dx, grad, err), err);
  int victim = nn_tensor_count(nn) > 0 ? (int)(seed % nn_tensor_count(nn)) : -1;
  if (victim >= 0 && (sabotage == GC_FLIP_TENSOR || sabotage == GC_ZERO_TENSOR)) {
    const nn_tensor *t = nn_tensor_at(nn, victim);
    for (size_t i = 0; i < t->count; i++)
      grad[t->offset + i] = sabotage == GC_FLIP_TENSOR ? -grad[t->offset + i] : 0.0f;
  }
  if (sabotage == GC_FLIP_INPUT) dx[0] = -dx[0];

  int bad = 0;
  for (int k = 0; k < nn_tensor_count(nn); k++) {
    const nn_tensor *t = nn_tensor_at(nn, k);
    int n = t->count < 8 ? (int)t->count : 8;
    for (int s = 0; s < n; s++) {
      size_t i = t->count <= 8 ? (size_t)s : core_rng_u32(&rng) % t->count;
      /* The victim tensor is checked everywhere, so that sabotage cannot slip through
       * coordinates whose gradient happens to be zero. */
      if (k == victim && sabotage != GC_HONEST && sabotage != GC_FLIP_INPUT) i = (size_t)s;
      bad += !agrees(&g, p + t->offset + i, grad[t->offset + i], t->name, (int)i, verbose);
    }
  }
  for (int i = 0; i < B * g.in; i++)
    bad += !agrees(&g, &g.x[i], dx[i], "input", i, verbose);

  /* The partial backward passes must give the same numbers as the full one. */
  if (sabotage == GC_HONEST) {
    float *grad2 = calloc(np, sizeof *grad2);
    float dx2[B * MAX_IN];
    loss(&g);
    CHECK_OK(nn_backward(nn, g.ws, g.c, NULL, grad2, err), err);
    CHECK(memcmp(grad, grad2, np * sizeof *grad) == 0);
    loss(&g);
    CHECK_OK(nn_backward(nn, g.ws, g.c, dx2, NULL, err), err);
    CHECK(memcmp(dx, dx2, sizeof(float) * B * g.in) == 0);
    free(grad2);
  }
  free(grad);
  nn_workspace_destroy(g.ws);
  return bad;
}

static nn_network *make(const nn_spec *spec) {
  nbrdf_error err_s, *err = &err_s;
  nn_network *nn = NULL;
  CHECK_OK(nn_create(spec, &nn, err), err);
  return nn;
}

static void check_spec(const nn_spec *spec, const char *label, uint64_t seed) {
  nn_network *nn = make(spec);
  if (!nn) return;
  int bad = grad_check(nn, seed, GC_HONEST, 1);
  CHECK_MSG(bad == 0, "%s: %d gradient coordinates disagree with finite differences", label, bad);
  nn_destroy(nn);
}

static void one_block(nn_kind kind, int in, int width, int hidden, int skip_from,
                      const char *label) {
  nn_spec s;
  nn_spec_init(&s, in);
  int i = nn_spec_add(&s, kind, width);
  s.layers[i].hidden = hidden;
  if (skip_from >= 0) nn_spec_skip(&s, i, skip_from);
  check_spec(&s, label, 7 + (uint64_t)kind);
}

static void test_blocks(void) {
  one_block(NBRDF_NN_LINEAR, 5, 4, 0, -1, "linear");
  one_block(NBRDF_NN_LAYERNORM, 6, 0, 0, -1, "layernorm");
  one_block(NBRDF_NN_RELU, 6, 0, 0, -1, "relu");
  one_block(NBRDF_NN_PLAIN, 5, 6, 0, -1, "plain");
  one_block(NBRDF_NN_RESIDUAL, 8, 0, 0, -1, "residual (hidden w/2)");
  one_block(NBRDF_NN_RESIDUAL, 6, 0, 5, -1, "residual (hidden 5)");
  one_block(NBRDF_NN_PLAIN, 6, 6, 0, 0, "plain + identity skip from input");
  one_block(NBRDF_NN_PLAIN, 5, 7, 0, 0, "plain + projected skip from input");
  one_block(NBRDF_NN_LINEAR, 5, 3, 0, 0, "linear + projected skip");
  one_block(NBRDF_NN_RESIDUAL, 6, 0, 0, 0, "residual + identity skip");
}

/* Skips between inner activations, identity and projected, and in-place layers in front. */
static void test_skips_between_layers(void) {
  nn_spec s;
  nn_spec_init(&s, 5);
  nn_spec_add(&s, NBRDF_NN_LAYERNORM, 0); /* in-place layer as layer 0 */
  nn_spec_add(&s, NBRDF_NN_PLAIN, 8);
  int r = nn_spec_add(&s, NBRDF_NN_RESIDUAL, 0);
  nn_spec_skip(&s, r, 2); /* identity from the plain layer's output (= own input) */
  int p = nn_spec_add(&s, NBRDF_NN_PLAIN, 8);
  nn_spec_skip(&s, p, 1); /* projected from the normalised input (width 5) */
  nn_spec_add(&s, NBRDF_NN_RELU, 0);
  int o = nn_spec_add(&s, NBRDF_NN_LINEAR, 3);
  nn_spec_skip(&s, o, 0); /* projected from the raw input */
  check_spec(&s, "skips between layers", 21);
}

static void test_networks(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  /* Decoder-like: latent + directions -> 1 value, residual blocks alternating with plain
   * layers, plus a skip from the network input into the middle. */
  CHECK_OK(nn_spec_resmlp(&s, 10, 16, 2, 1, 1, err), err);
  nn_spec_skip(&s, 3, 0);
  check_spec(&s, "decoder-like", 31);
  /* Layering-like: two latents + A + sigma_t -> a latent. */
  CHECK_OK(nn_spec_resmlp(&s, 14, 16, 3, 0, 6, err), err);
  check_spec(&s, "layering-like", 32);
  /* Sampler-like: latent + direction -> (sigma, w). */
  nn_spec_init(&s, 9);
  nn_spec_add(&s, NBRDF_NN_PLAIN, 12);
  nn_spec_add(&s, NBRDF_NN_PLAIN, 12);
  nn_spec_add(&s, NBRDF_NN_LINEAR, 2);
  check_spec(&s, "sampler-like", 33);
}

/* The check itself must fail on a wrong sign, a missing term or a wrong input gradient. */
static void test_check_catches_errors(void) {
  nbrdf_error err_s, *err = &err_s;
  nn_spec s;
  CHECK_OK(nn_spec_resmlp(&s, 6, 8, 1, 1, 2, err), err);
  nn_network *nn = make(&s);
  int n = nn_tensor_count(nn);
  for (uint64_t seed = 0; seed < (uint64_t)n; seed++) {
    CHECK_MSG(grad_check(nn, seed, GC_FLIP_TENSOR, 0) > 0, "flipped %s not caught",
              nn_tensor_at(nn, (int)seed)->name);
    CHECK_MSG(grad_check(nn, seed, GC_ZERO_TENSOR, 0) > 0, "zeroed %s not caught",
              nn_tensor_at(nn, (int)seed)->name);
  }
  CHECK(grad_check(nn, 1, GC_FLIP_INPUT, 0) > 0);
  nn_destroy(nn);
}

int main(void) {
  RUN(test_blocks);
  RUN(test_skips_between_layers);
  RUN(test_networks);
  RUN(test_check_catches_errors);
  return testing_finish();
}
