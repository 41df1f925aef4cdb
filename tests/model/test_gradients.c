/* Finite-difference checks of the networks as src/model assembles them
 * (decoder presets at small width, layering, sampler with its output
 * transform) with respect to weights and inputs, of the losses, and of the
 * auto-decoder / projection loss with respect to the latents. The blocks
 * themselves are checked in tests/nn. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "fd_check.h"
#include "model/autodecoder.h"
#include "model/decoder.h"
#include "model/layering.h"
#include "model/loss.h"
#include "model/sampler.h"
#include "testing.h"

static double max_abs(const float *x, size_t n) {
  double m = 1e-12;
  for (size_t i = 0; i < n; i++)
    m = fmax(m, fabs(x[i]));
  return m;
}

static void fill_normal(core_rng *rng, float *x, size_t n, double s) {
  for (size_t i = 0; i < n; i++)
    x[i] = (float)(s * core_rng_normal(rng));
}

static void random_dirs(core_rng *rng, float *w, size_t n) {
  for (size_t k = 0; k < n; k++) {
    double z = 0.05 + 0.95 * core_rng_uniform(rng), r = sqrt(1 - z * z);
    double phi = 2 * M_PI * core_rng_uniform(rng);
    w[3 * k] = (float)(r * cos(phi)), w[3 * k + 1] = (float)(r * sin(phi)), w[3 * k + 2] = (float)z;
  }
}

/* ------------------------------------------------------------ L = Σ a · y */

enum { BATCH = 5 };

typedef struct linear_ctx {
  nn_network *nn;
  nn_workspace *ws;
  float *x, *y, *a;
  int rows, outputs;
} linear_ctx;

static double linear_loss(void *p) {
  linear_ctx *c = p;
  nn_forward(c->nn, c->ws, c->x, c->rows, c->y, NULL);
  double l = 0.0;
  for (int i = 0; i < c->rows * c->outputs; i++)
    l += (double)c->a[i] * c->y[i];
  return l;
}

/* Checks d(Σ a·y)/d(weights) and /d(inputs [cols lo, hi)) of a network on x. */
static void check_network(const char *what, nn_network *nn, float *x, int rows, int lo, int hi,
                          core_rng *rng) {
  nbrdf_error err_ = {0}, *err = &err_;
  linear_ctx c = {nn, NULL, x, NULL, NULL, rows, nn_outputs(nn)};
  int in = nn_inputs(nn);
  size_t np = nn_param_count(nn);
  c.y = malloc(sizeof(float) * rows * c.outputs);
  c.a = malloc(sizeof(float) * rows * c.outputs);
  float *dx = malloc(sizeof(float) * rows * in), *grad = calloc(np, sizeof(float));
  fill_normal(rng, c.a, (size_t)rows * c.outputs, 1.0);
  CHECK_OK(nn_workspace_create(nn, rows, NBRDF_NN_TRAIN, &c.ws, err), err);
  linear_loss(&c);
  CHECK_OK(nn_backward(nn, c.ws, c.a, dx, grad, err), err);
  double gs = max_abs(grad, np), xs = max_abs(dx, (size_t)rows * in);
  float *params = nn_params(nn);
  for (int t = 0; t < 60; t++) {
    int i = (int)(core_rng_uniform(rng) * np);
    fd_check(what, i, params + i, grad[i], linear_loss, &c, 1e-3, gs);
  }
  for (int r = 0; r < rows; r++)
    for (int j = lo; j < hi; j++)
      fd_check(what, r * in + j, x + r * in + j, dx[r * in + j], linear_loss, &c, 1e-3, xs);
  nn_workspace_destroy(c.ws);
  free(c.y), free(c.a), free(dx), free(grad);
}

static void test_decoder_presets_small(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  core_rng rng;
  core_rng_init(&rng, 21, 0);
  for (int p = 0; model_decoder_presets[p]; p++) {
    model_decoder_config preset, cfg;
    CHECK_OK(model_decoder_preset(model_decoder_presets[p], 8, &preset, err), err);
    /* The preset's encoding, output and block pattern at a width a check can afford. */
    int interleave = preset.spec.n_layers > 2 && preset.spec.layers[2].kind == NBRDF_NN_PLAIN;
    CHECK_OK(
        model_decoder_config_make(8, preset.encoding, preset.output, 12, 2, interleave, &cfg, err),
        err);
    model_decoder *dec = NULL;
    CHECK_OK(model_decoder_create(&cfg, 3, &dec, err), err);
    if (!dec) continue;
    int in = model_decoder_inputs(dec);
    float latents[BATCH * 8], wi[BATCH * 3], wo[BATCH * 3], x[BATCH * 64];
    fill_normal(&rng, latents, BATCH * 8, 1.0);
    random_dirs(&rng, wi, BATCH);
    random_dirs(&rng, wo, BATCH);
    model_decoder_fill_inputs(dec, BATCH, 1, latents, wi, wo, x);
    CHECK(in <= 64);
    /* Weights, and the latent part of the input (what projection differentiates). */
    check_network(model_decoder_presets[p], dec->nn, x, BATCH, 0, 8, &rng);
    model_decoder_destroy(dec);
  }
}

static void test_layering_network(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  core_rng rng;
  core_rng_init(&rng, 22, 0);
  model_layering *net = NULL;
  CHECK_OK(model_layering_create("small", 6, 4, &net, err), err);
  if (!net) return;
  float top[BATCH * 6], bottom[BATCH * 6], albedo[BATCH], sigma_t[BATCH], x[BATCH * 14];
  fill_normal(&rng, top, BATCH * 6, 1.0);
  fill_normal(&rng, bottom, BATCH * 6, 1.0);
  for (int k = 0; k < BATCH; k++)
    albedo[k] = (float)core_rng_uniform(&rng), sigma_t[k] = (float)k;
  model_layering_fill_inputs(net, BATCH, top, bottom, albedo, sigma_t, x);
  CHECK_NEAR(x[13], log1p(0.0), 0.0);
  CHECK_NEAR(x[4 * 14 + 13], log1p(4.0), 1e-6);
  check_network("layering", net->nn, x, BATCH, 0, 14, &rng);
  model_layering_destroy(net);
}

/* The sampler through its output transform: L = Σ a0 σ + a1 w. */
typedef struct sampler_ctx {
  model_sampler *net;
  nn_workspace *ws;
  float *x, y[2 * BATCH], a[2 * BATCH];
} sampler_ctx;

static double sampler_loss(void *p) {
  sampler_ctx *c = p;
  nn_forward(c->net->nn, c->ws, c->x, BATCH, c->y, NULL);
  double l = 0.0;
  for (int k = 0; k < BATCH; k++) {
    float sigma, w;
    model_sampler_transform(c->y + 2 * k, &sigma, &w, NULL, NULL);
    l += (double)c->a[2 * k] * sigma + (double)c->a[2 * k + 1] * w;
  }
  return l;
}

static void test_sampler_network(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  core_rng rng;
  core_rng_init(&rng, 23, 0);
  sampler_ctx c = {0};
  CHECK_OK(model_sampler_create("default", 6, 5, &c.net, err), err);
  if (!c.net) return;
  float x[BATCH * 6], dx[BATCH * 6], dy[2 * BATCH];
  size_t np = nn_param_count(c.net->nn);
  float *grad = calloc(np, sizeof(float));
  c.x = x;
  fill_normal(&rng, x, BATCH * 6, 1.0);
  fill_normal(&rng, c.a, 2 * BATCH, 1.0);
  CHECK_OK(nn_workspace_create(c.net->nn, BATCH, NBRDF_NN_TRAIN, &c.ws, err), err);
  sampler_loss(&c);
  for (int k = 0; k < BATCH; k++) {
    float sigma, w, ds, dw;
    model_sampler_transform(c.y + 2 * k, &sigma, &w, &ds, &dw);
    CHECK(sigma > 0.0f && w >= 0.0f && w <= 1.0f);
    dy[2 * k] = c.a[2 * k] * ds, dy[2 * k + 1] = c.a[2 * k + 1] * dw;
  }
  CHECK_OK(nn_backward(c.net->nn, c.ws, dy, dx, grad, err), err);
  double gs = max_abs(grad, np), xs = max_abs(dx, BATCH * 6);
  float *params = nn_params(c.net->nn);
  for (int t = 0; t < 60; t++) {
    int i = (int)(core_rng_uniform(&rng) * np);
    fd_check("sampler", i, params + i, grad[i], sampler_loss, &c, 1e-3, gs);
  }
  for (int i = 0; i < BATCH * 6; i++)
    fd_check("sampler input", i, x + i, dx[i], sampler_loss, &c, 1e-3, xs);
  /* Extremes of the transform stay finite and in range. */
  float big[2] = {200.0f, -200.0f}, small[2] = {-200.0f, 200.0f}, s, w;
  model_sampler_transform(big, &s, &w, NULL, NULL);
  CHECK(isfinite(s) && s > 100.0f && w == 0.0f);
  model_sampler_transform(small, &s, &w, NULL, NULL);
  CHECK(s >= 1e-3f && w == 1.0f);
  nn_workspace_destroy(c.ws);
  model_sampler_destroy(c.net);
  free(grad);
}

/* --------------------------------------------------------------- losses */

typedef struct loss_ctx {
  model_loss_kind kind;
  model_output output;
  float o[4], f[4], w[4];
} loss_ctx;

static double loss_value(void *p) {
  loss_ctx *c = p;
  return model_loss_sum(c->kind, c->output, 4, c->o, c->f, c->w, 1.0f, NULL);
}

static void test_losses(void) {
  for (int kind = 0; kind < 2; kind++) {
    for (int out = 0; out < 2; out++) {
      loss_ctx c = {(model_loss_kind)kind,
                    (model_output)out,
                    {-0.4f, 0.3f, 1.7f, 2.5f},
                    {0.5f, 3.0f, 0.2f, 40.0f},
                    {1.0f, 0.25f, 3.0f, 1.5f}};
      float d[4], d1[4];
      double l = model_loss_sum(c.kind, c.output, 4, c.o, c.f, c.w, 1.0f, d);
      double l1 = model_loss_sum(c.kind, c.output, 4, c.o, c.f, NULL, 1.0f, d1);
      CHECK(isfinite(l) && l > 0.0 && fabs(l - l1) > 1e-3);
      /* Per-row weights scale each row's gradient (NULL weights are all 1). */
      for (int i = 0; i < 4; i++)
        CHECK_NEAR(d[i], c.w[i] * d1[i], 1e-6 * (1.0 + fabs(d[i])));
      for (int i = 0; i < 4; i++)
        fd_check(model_loss_name(c.kind), i, c.o + i, d[i], loss_value, &c, 1e-3, 1.0);
    }
  }
  /* A perfect prediction has zero loss under both losses. */
  float o_log[1] = {(float)log1p(2.0)}, o_f[1] = {2.0f}, f[1] = {2.0f};
  CHECK_NEAR(model_loss_sum(MODEL_LOSS_L1_LOG1P, MODEL_OUTPUT_LOG1P, 1, o_log, f, NULL, 1.0f, NULL),
             0.0, 1e-6);
  CHECK_NEAR(model_loss_sum(MODEL_LOSS_L1, MODEL_OUTPUT_F, 1, o_f, f, NULL, 1.0f, NULL), 0.0, 0.0);
  model_loss_kind k;
  CHECK(model_loss_parse("l1-log1p", &k) && k == MODEL_LOSS_L1_LOG1P);
  CHECK(!model_loss_parse("l2", &k));
}

/* ---------------------------------------- projection / auto-decoder loss */

typedef struct fit_ctx {
  model_fit *fit;
  const model_samples *s;
} fit_ctx;

static double fit_loss(void *p) {
  fit_ctx *c = p;
  double l = 0.0;
  model_fit_gradient(c->fit, c->s, 3, &l, NULL);
  return l;
}

static void test_fit_gradients(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  core_rng rng;
  core_rng_init(&rng, 24, 0);
  enum { NB = 3, PER = 6, D = 8 };
  float wi[NB * PER * 3], wo[NB * PER * 3], f[NB * PER], latents[NB * D];
  size_t offsets[NB + 1] = {0, PER, 2 * PER, 3 * PER};
  random_dirs(&rng, wi, NB * PER);
  random_dirs(&rng, wo, NB * PER);
  /* Targets far above what a fresh network predicts, so no residual changes sign. */
  for (int i = 0; i < NB * PER; i++)
    f[i] = (float)(30.0 + 20.0 * core_rng_uniform(&rng));
  const float brdf_weight[NB] = {0.5f, 2.0f, 1.25f};
  model_samples s = {NB, offsets, wi, wo, f, brdf_weight};
  for (int out = 0; out < 2; out++) {
    for (int kind = 0; kind < 2; kind++) {
      model_decoder_config cfg;
      model_encoding enc = {MODEL_ENCODING_HALFDIFF, 1};
      CHECK_OK(model_decoder_config_make(D, enc, (model_output)out, 12, 1, 1, &cfg, err), err);
      model_decoder *dec = NULL;
      CHECK_OK(model_decoder_create(&cfg, 9, &dec, err), err);
      fill_normal(&rng, latents, NB * D, 0.5);
      model_fit_options o = MODEL_FIT_OPTIONS_DEFAULT;
      o.loss = (model_loss_kind)kind;
      o.rows_per_brdf = 5;
      o.max_batch = 4; /* several GEMM batches per step: accumulation is checked too */
      o.lr_weights = 1e-3f;
      o.latent_l2 = 0.1f;
      model_fit *fit = NULL;
      CHECK_OK(model_fit_create(dec, NB, latents, &o, &fit, err), err);
      if (!fit) {
        model_decoder_destroy(dec);
        continue;
      }
      double l0;
      CHECK_OK(model_fit_gradient(fit, &s, 3, &l0, err), err);
      float gl[NB * D];
      memcpy(gl, model_fit_grad_latent(fit), sizeof gl);
      size_t np = nn_param_count(dec->nn);
      float *gw = malloc(np * sizeof(float));
      memcpy(gw, model_fit_grad_weights(fit), np * sizeof(float));
      fit_ctx c = {fit, &s};
      const char *name = model_loss_name(o.loss);
      for (int i = 0; i < NB * D; i++)
        fd_check(name, i, latents + i, gl[i], fit_loss, &c, 1e-3, max_abs(gl, NB * D));
      float *params = nn_params(dec->nn);
      for (int t = 0; t < 30; t++) {
        int i = (int)(core_rng_uniform(&rng) * np);
        fd_check(name, i, params + i, gw[i], fit_loss, &c, 1e-3, max_abs(gw, np));
      }
      /* Another step draws other rows: another loss at the same latents. */
      double l4 = l0;
      CHECK_OK(model_fit_gradient(fit, &s, 4, &l4, err), err);
      CHECK(l4 != l0);
      free(gw);
      model_fit_destroy(fit);
      model_decoder_destroy(dec);
    }
  }
}

int main(void) {
  RUN(test_decoder_presets_small);
  RUN(test_layering_network);
  RUN(test_sampler_network);
  RUN(test_losses);
  RUN(test_fit_gradients);
  return testing_finish();
}
