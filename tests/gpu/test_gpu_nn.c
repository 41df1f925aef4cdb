/* The GPU backend (src/gpu) against the CPU forward pass (src/nn) on every network the
 * library runs: decoder presets (both encodings, both output transforms), the trained
 * models/default decoder, layering and sampler networks, a compact decoder, and specs with
 * identity and projected skips and standalone LayerNorm / ReLU layers. Random inputs,
 * parameters perturbed so that LayerNorm's gamma and beta are not 1 and 0.
 *
 * Runs on lavapipe (NBRDF_VK_DEVICE=llvmpipe unless set otherwise); skips, passing, where
 * there is no Vulkan device or the build has no GPU backend. Tolerance: fp32, sums in another
 * order than OpenBLAS: max |gpu - cpu| / max(|cpu|, 1) <= 1e-5 over every output. The
 * tensor-core (fp16) path is checked only where the device has it, at a 2e-2 tolerance. */
#include "testing.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "gpu/gpu.h"
#include "model/bundle.h"
#include "model/decoder.h"
#include "model/layering.h"
#include "model/sampler.h"
#include "nbrdf/model.h"

#define TOL 1e-5

static gpu_context *ctx;

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return x < y ? -1 : x > y;
}

/* Runs `nn` on n random rows through both paths; returns the max error (see the top). */
static double compare(const char *name, nn_network *nn, int n, gpu_precision precision,
                      double tol) {
  const int in = nn_inputs(nn), out = nn_outputs(nn);
  core_rng rng;
  core_rng_init(&rng, 7, (uint64_t)in * 131 + (uint64_t)out);
  float *x = malloc(sizeof(float) * (size_t)n * in);
  float *yc = malloc(sizeof(float) * (size_t)n * out);
  float *yg = malloc(sizeof(float) * (size_t)n * out);
  float *rel = malloc(sizeof(float) * (size_t)n * out);
  for (size_t k = 0; k < (size_t)n * in; k++)
    x[k] = (float)(2.0 * core_rng_uniform(&rng) - 1.0);
  nn_workspace *ws = NULL;
  nbrdf_error err;
  CHECK(nn_workspace_create(nn, 1024, NBRDF_NN_INFER, &ws, &err) == NBRDF_OK);
  CHECK(nn_forward(nn, ws, x, n, yc, &err) == NBRDF_OK);
  nn_workspace_destroy(ws);
  gpu_network *g = NULL;
  /* A small chunk, so that streaming over several chunks is exercised too. */
  nbrdf_status st = gpu_network_create(ctx, nn, precision, 256, &g, &err);
  CHECK_MSG(st == NBRDF_OK, "%s: %s", name, testing_message(&err));
  double worst = 0.0;
  if (st == NBRDF_OK) {
    CHECK(gpu_network_forward(g, x, (size_t)n, yg, &err) == NBRDF_OK);
    for (size_t k = 0; k < (size_t)n * out; k++) {
      double d = fabs((double)yg[k] - yc[k]) / fmax(fabs((double)yc[k]), 1.0);
      if (!(d <= worst)) worst = d; /* NaN counts as the worst */
      rel[k] = (float)(fabs((double)yg[k] - yc[k]) / fmax(fabs((double)yc[k]), 1e-6));
    }
    qsort(rel, (size_t)n * out, sizeof *rel, cmp_float);
    printf("%-34s %-5s %5d rows: max err %.2e, median rel %.2e\n", name,
           precision == GPU_FP32 ? "fp32" : "fp16", n, worst, (double)rel[(size_t)n * out / 2]);
    CHECK_MSG(worst <= tol, "%s: max error %.3g above %.3g", name, worst, tol);
  }
  gpu_network_destroy(g);
  free(x), free(yc), free(yg), free(rel);
  return worst;
}

static void perturb(nn_network *nn, uint64_t seed) {
  core_rng rng;
  core_rng_init(&rng, seed, 3);
  float *p = nn_params(nn);
  for (size_t k = 0; k < nn_param_count(nn); k++)
    p[k] += (float)(0.1 * (2.0 * core_rng_uniform(&rng) - 1.0));
}

static void both(const char *name, nn_network *nn, int n) {
  compare(name, nn, n, GPU_FP32, TOL);
  if (gpu_context_limits(ctx)->coop_matrix) compare(name, nn, n, GPU_FP16_COOP, 2e-2);
}

static void test_decoders(void) {
  nbrdf_error err;
  for (int i = 0; model_decoder_presets[i]; i++) {
    model_decoder_config cfg;
    CHECK(model_decoder_preset(model_decoder_presets[i], 32, &cfg, &err) == NBRDF_OK);
    model_decoder *dec = NULL;
    CHECK(model_decoder_create(&cfg, 11, &dec, &err) == NBRDF_OK);
    perturb(dec->nn, 5);
    char name[64];
    snprintf(name, sizeof name, "decoder %s (%s)", cfg.preset,
             cfg.encoding.kind == MODEL_ENCODING_CARTESIAN ? "cartesian" : "halfdiff");
    /* paper: 1 M MACs a row, slow on lavapipe: fewer rows */
    both(name, dec->nn, model_decoder_macs(dec) > 500000 ? 300 : 1000);
    model_decoder_destroy(dec);
  }
  /* the other encoding at a small size */
  model_decoder_config cfg;
  CHECK(model_decoder_config_make(32, (model_encoding){MODEL_ENCODING_CARTESIAN, 0}, MODEL_OUTPUT_LOG1P, 32, 2, 1, &cfg,
                                  &err) == NBRDF_OK);
  model_decoder *dec = NULL;
  CHECK(model_decoder_create(&cfg, 12, &dec, &err) == NBRDF_OK);
  perturb(dec->nn, 6);
  both("decoder small (cartesian)", dec->nn, 1000);
  model_decoder_destroy(dec);
  CHECK(model_decoder_compact_config(8, 32, &cfg, &err) == NBRDF_OK);
  CHECK(model_decoder_create(&cfg, 13, &dec, &err) == NBRDF_OK);
  perturb(dec->nn, 7);
  both("decoder compact 8 x 32", dec->nn, 1000);
  model_decoder_destroy(dec);
}

static void test_layering_sampler(void) {
  nbrdf_error err;
  for (int i = 0; model_layering_presets[i]; i++) {
    model_layering *net = NULL;
    CHECK(model_layering_create(model_layering_presets[i], 32, 21, &net, &err) == NBRDF_OK);
    perturb(net->nn, 8);
    char name[64];
    snprintf(name, sizeof name, "layering %s", model_layering_presets[i]);
    both(name, net->nn, i == 0 ? 300 : 1000);
    model_layering_destroy(net);
  }
  model_sampler *s = NULL;
  CHECK(model_sampler_create("default", 32, 22, &s, &err) == NBRDF_OK);
  perturb(s->nn, 9);
  both("sampler default", s->nn, 2000);
  model_sampler_destroy(s);
}

static void test_trained_default(void) {
  nbrdf_model *m = NULL;
  nbrdf_error err;
  char path[4096];
  snprintf(path, sizeof path, "%s/models/default", testing_source_dir());
  CHECK_MSG(nbrdf_model_load(path, &m, &err) == NBRDF_OK, "%s", testing_message(&err));
  if (!m) return;
  both("models/default decoder", m->decoder->nn, 1000);
  both("models/default layering", m->layering->nn, 300);
  both("models/default sampler", m->sampler->nn, 1000);
  nbrdf_model_destroy(m);
}

/* Identity and projected skips, standalone LayerNorm and ReLU layers, odd widths. */
static void test_skips(void) {
  nn_spec spec;
  nn_spec_init(&spec, 37);
  nn_spec_add(&spec, NBRDF_NN_PLAIN, 48);     /* 0 */
  nn_spec_add(&spec, NBRDF_NN_RESIDUAL, 0);   /* 1 */
  nn_spec_skip(&spec, 1, 0);                  /* projected 37 -> 48 */
  nn_spec_add(&spec, NBRDF_NN_LINEAR, 48);    /* 2 */
  nn_spec_skip(&spec, 2, 1);                  /* identity from layer 0's output */
  nn_spec_add(&spec, NBRDF_NN_LAYERNORM, 0);  /* 3 */
  nn_spec_add(&spec, NBRDF_NN_RELU, 0);       /* 4 */
  nn_spec_add(&spec, NBRDF_NN_PLAIN, 20);     /* 5 */
  nn_spec_skip(&spec, 5, 2);                  /* projected 48 -> 20 */
  nn_spec_add(&spec, NBRDF_NN_LINEAR, 3);     /* 6 */
  nn_spec_skip(&spec, 6, 0);                  /* projected 37 -> 3 */
  nn_network *nn = NULL;
  nbrdf_error err;
  CHECK_MSG(nn_create(&spec, &nn, &err) == NBRDF_OK, "%s", testing_message(&err));
  if (!nn) return;
  nn_init_params(nn, 31);
  perturb(nn, 10);
  both("skips, layernorm, relu", nn, 777);
  nn_destroy(nn);
}

/* Two networks of one context, each driven by its own thread at the same time (the queue is
 * shared; submissions are serialised by the context): both give the CPU's results. */
typedef struct job {
  nn_network *nn;
  int rows;
  double err;
  int ok;
} job;

static void *run_job(void *arg) {
  job *j = arg;
  const int in = nn_inputs(j->nn), out = nn_outputs(j->nn);
  float *x = malloc(sizeof(float) * (size_t)j->rows * in);
  float *yc = malloc(sizeof(float) * (size_t)j->rows * out);
  float *yg = malloc(sizeof(float) * (size_t)j->rows * out);
  core_rng rng;
  core_rng_init(&rng, 99, (uint64_t)in);
  for (size_t k = 0; k < (size_t)j->rows * in; k++)
    x[k] = (float)(2.0 * core_rng_uniform(&rng) - 1.0);
  nbrdf_error err;
  nn_workspace *ws = NULL;
  gpu_network *g = NULL;
  j->ok = nn_workspace_create(j->nn, 512, NBRDF_NN_INFER, &ws, &err) == NBRDF_OK &&
          nn_forward(j->nn, ws, x, j->rows, yc, &err) == NBRDF_OK &&
          gpu_network_create(ctx, j->nn, GPU_FP32, 256, &g, &err) == NBRDF_OK;
  for (int rep = 0; j->ok && rep < 3; rep++)
    j->ok = gpu_network_forward(g, x, (size_t)j->rows, yg, &err) == NBRDF_OK;
  j->err = 0.0;
  for (size_t k = 0; j->ok && k < (size_t)j->rows * out; k++) {
    double d = fabs((double)yg[k] - yc[k]) / fmax(fabs((double)yc[k]), 1.0);
    if (!(d <= j->err)) j->err = d;
  }
  gpu_network_destroy(g);
  nn_workspace_destroy(ws);
  free(x), free(yc), free(yg);
  return NULL;
}

static void test_threads(void) {
  nbrdf_error err;
  model_sampler *s = NULL;
  model_decoder_config cfg;
  model_decoder *dec = NULL;
  CHECK(model_sampler_create("default", 32, 41, &s, &err) == NBRDF_OK);
  CHECK(model_decoder_preset("small", 32, &cfg, &err) == NBRDF_OK);
  CHECK(model_decoder_create(&cfg, 42, &dec, &err) == NBRDF_OK);
  if (!s || !dec) return;
  job jobs[2] = {{s->nn, 1500, 0.0, 0}, {dec->nn, 1200, 0.0, 0}};
  pthread_t t[2];
  for (int i = 0; i < 2; i++)
    CHECK(pthread_create(&t[i], NULL, run_job, &jobs[i]) == 0);
  for (int i = 0; i < 2; i++) {
    pthread_join(t[i], NULL);
    CHECK_MSG(jobs[i].ok && jobs[i].err <= TOL, "thread %d: ok %d, max error %.3g", i, jobs[i].ok,
              jobs[i].err);
  }
  printf("two threads, two networks: max err %.2e, %.2e\n", jobs[0].err, jobs[1].err);
  model_sampler_destroy(s);
  model_decoder_destroy(dec);
}

int main(void) {
  if (!gpu_built()) {
    printf("skipped: built without GPU support\n");
    return 0;
  }
  if (!getenv("NBRDF_VK_DEVICE")) setenv("NBRDF_VK_DEVICE", "llvmpipe", 1);
  nbrdf_error err;
  if (gpu_context_open(GPU_CHOICE_GPU, &ctx, &err) != NBRDF_OK) {
    printf("skipped: %s\n", testing_message(&err));
    return 0;
  }
  printf("device: %s%s; tensor-core path: %s\n", gpu_context_name(ctx),
         gpu_context_is_cpu(ctx) ? " (CPU)" : "",
         gpu_context_limits(ctx)->coop_matrix ? "checked" : gpu_context_limits(ctx)->coop_note);
  RUN(test_skips);
  RUN(test_threads);
  RUN(test_layering_sampler);
  RUN(test_decoders);
  RUN(test_trained_default);
  gpu_context_close(ctx);
  return testing_finish();
}
