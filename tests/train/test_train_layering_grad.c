/* Finite-difference check of the decoded layering loss's gradient: through
 * the frozen decoder's input gradient, summed over each pair's rows, into the
 * layering network's weights (train/train_layering.h), for two-layer pairs
 * and a three-layer pair (the network applied to its own output). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "fd_check.h"
#include "testing.h"
#include "train/train_layering.h"

enum { NB = 3, PER = 7, D = 8, ROWS = 5 };

typedef struct ctx {
  train_layering_decoded *engine;
  const train_layering_pairs *pairs;
  size_t idx[NB];
  float *scratch;
} ctx;

static double decoded_loss(void *p) {
  ctx *c = p;
  double l = NAN;
  /* Step 0 again: the same rows are drawn every time. */
  if (train_layering_decoded_gradient(c->engine, c->pairs, c->idx, NB, 0, c->scratch, &l, NULL))
    return NAN;
  return l;
}

static void test_decoded_gradient(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  core_rng rng;
  core_rng_init(&rng, 31, 0);
  float wi[NB * PER * 3], wo[NB * PER * 3], f[NB * PER];
  for (int k = 0; k < NB * PER; k++) {
    float *w[2] = {wi + 3 * k, wo + 3 * k};
    for (int j = 0; j < 2; j++) {
      double z = 0.05 + 0.95 * core_rng_uniform(&rng), r = sqrt(1 - z * z);
      double phi = 2 * M_PI * core_rng_uniform(&rng);
      w[j][0] = (float)(r * cos(phi)), w[j][1] = (float)(r * sin(phi)), w[j][2] = (float)z;
    }
    /* Targets far above what fresh networks predict: no residual changes sign. */
    f[k] = (float)(30.0 + 20.0 * core_rng_uniform(&rng));
  }
  size_t offsets[NB + 1] = {0, PER, 2 * PER, 3 * PER}, brdf[NB] = {2, 0, 1};
  /* Dim rough conductors (R0 = 0): energy ceilings of a few percent, far
   * below what a fresh decoder reflects, so the energy penalty (kind 2) is on. */
  train_params params[NB];
  memset(params, 0, sizeof params);
  for (int b = 0; b < NB; b++)
    params[b].kind = TRAIN_CONDUCTOR, params[b].base_alpha = 0.6, params[b].base_r0 = 0.0;
  train_samples data = {.n_brdfs = NB,
                        .n_rows = NB * PER,
                        .offsets = offsets,
                        .wi = wi,
                        .wo = wo,
                        .f = f,
                        .params = params};
  float top[NB * D], bottom[NB * D], mid[NB * D], albedo[NB] = {0.2f, 0.7f, 1.0f};
  float sig[NB] = {0, 1.5f, 5}, albedo2[NB] = {0, 0.9f, 0}, sig2[NB] = {0, 2.0f, 0};
  unsigned char coats[NB] = {1, 2, 1};
  for (int i = 0; i < NB * D; i++) {
    top[i] = (float)(0.5 * core_rng_normal(&rng));
    bottom[i] = (float)(0.5 * core_rng_normal(&rng));
    mid[i] = (float)(0.5 * core_rng_normal(&rng));
  }
  train_layering_pairs pairs = {.n = NB,
                                .top = top,
                                .bottom = bottom,
                                .albedo = albedo,
                                .sigma_t = sig,
                                .coats = coats,
                                .mid = mid,
                                .albedo2 = albedo2,
                                .sigma_t2 = sig2,
                                .brdf = brdf};
  /* kind 0, 1: the two losses; 2: l1-log1p with the energy penalty. */
  for (int kind = 0; kind < 3; kind++) {
    model_loss_kind loss = kind == 1 ? MODEL_LOSS_L1 : MODEL_LOSS_L1_LOG1P;
    model_decoder_config cfg;
    model_encoding enc = {MODEL_ENCODING_HALFDIFF, 1};
    CHECK_OK(model_decoder_config_make(D, enc, MODEL_OUTPUT_LOG1P, 12, 1, 1, &cfg, err), err);
    model_decoder *dec = NULL;
    model_layering *net = NULL;
    train_layering_decoded *engine = NULL;
    CHECK_OK(model_decoder_create(&cfg, 9, &dec, err), err);
    CHECK_OK(model_layering_create("small", D, 4, &net, err), err);
    if (dec && net)
      CHECK_OK(train_layering_decoded_create(net, dec, &data, NB, ROWS, loss, 7, &engine, err),
               err);
    double l_plain = NAN;
    if (engine && kind == 2) {
      size_t np0 = nn_param_count(net->nn);
      float *g0 = calloc(np0, sizeof *g0);
      size_t i3[NB] = {0, 1, 2};
      CHECK_OK(train_layering_decoded_gradient(engine, &pairs, i3, NB, 0, g0, &l_plain, err), err);
      free(g0);
      model_energy_options eo = MODEL_ENERGY_OPTIONS_DEFAULT;
      eo.lambda = 20.0f, eo.samples = 32;
      CHECK_OK(train_layering_decoded_set_energy(engine, &eo, 2, err), err);
    }
    if (!engine) {
      model_decoder_destroy(dec), model_layering_destroy(net);
      continue;
    }
    size_t np = nn_param_count(net->nn);
    float *grad = calloc(np, sizeof *grad), *scratch = malloc(np * sizeof *scratch);
    ctx c = {engine, &pairs, {0, 1, 2}, scratch};
    double l0;
    CHECK_OK(train_layering_decoded_gradient(engine, &pairs, c.idx, NB, 0, grad, &l0, err), err);
    CHECK(isfinite(l0) && l0 > 1.0);
    if (kind == 2) CHECK_MSG(l0 > l_plain + 1e-3, "energy penalty inactive: %g vs %g", l0, l_plain);
    double gs = 1e-12;
    for (size_t i = 0; i < np; i++)
      gs = fmax(gs, fabs(grad[i]));
    CHECK(gs > 1e-6); /* the gradient reaches the layering weights */
    float *weights = nn_params(net->nn);
    for (int t = 0; t < 60; t++) {
      int i = (int)(core_rng_uniform(&rng) * (double)np);
      fd_check(kind == 2 ? "energy" : model_loss_name(loss), i, weights + i, grad[i], decoded_loss,
               &c, 1e-3, gs);
    }
    /* More pairs than the batch: refused. */
    nbrdf_error e2 = {0};
    CHECK(train_layering_decoded_gradient(engine, &pairs, c.idx, NB + 1, 0, grad, &l0, &e2) ==
          NBRDF_ERR_ARGUMENT);
    free(grad), free(scratch);
    train_layering_decoded_destroy(engine);
    model_layering_destroy(net);
    model_decoder_destroy(dec);
  }
}

int main(void) {
  RUN(test_decoded_gradient);
  return testing_finish();
}
