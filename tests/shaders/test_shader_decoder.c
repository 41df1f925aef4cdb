/* shaders/nbrdf_decoder.glsl + nbrdf_encoding.glsl on Vulkan (lavapipe) against the C
 * decoder: thousands of random latents and direction pairs (a quarter grazing, cos θ down
 * to 1e-4), every preset, both encodings, frequency octaves, both output transforms.
 *
 * Tolerance (float32; the C side sums in sgemm's blocked order, the shader sequentially):
 * the raw network output o within 1e-4 · (1 + |o|), f within 1e-4 · (1 + f). For log1p
 * decoders the second is the error of log(1 + f), i.e. relative where f >> 1. */
#include "testing.h"

#ifdef NBRDF_HAVE_VULKAN
#include <stdlib.h>
#include <string.h>

#include "bake/bake_compact.h"
#include "model/bundle.h"
#include "model/encoding.h"
#include "model/gpu_pack.h"
#include "nbrdf/bake.h"
#include "nbrdf/gpu_pack.h"
#include "nbrdf/model.h"
#include "shader_fixture.h"

#define TOL 1e-4

static vkh *vk;

typedef struct queries {
  size_t n;
  int dim;
  float *q; /* n x (6 + dim): wi, wo, latent */
  float *wi, *wo, *latents;
} queries;

static void queries_make(queries *s, size_t n, int dim, uint64_t seed) {
  core_rng rng;
  core_rng_init(&rng, seed, 9);
  s->n = n;
  s->dim = dim;
  s->q = malloc(sizeof(float) * n * (6 + dim));
  s->wi = malloc(sizeof(float) * n * 3);
  s->wo = malloc(sizeof(float) * n * 3);
  s->latents = malloc(sizeof(float) * n * dim);
  for (size_t k = 0; k < n; k++) {
    fixture_direction(&rng, s->wi + 3 * k);
    fixture_direction(&rng, s->wo + 3 * k);
    for (int i = 0; i < dim; i++)
      s->latents[k * dim + i] = (float)(3.0 * core_rng_uniform(&rng) - 1.5);
    float *row = s->q + k * (6 + dim);
    memcpy(row, s->wi + 3 * k, 3 * sizeof(float));
    memcpy(row + 3, s->wo + 3 * k, 3 * sizeof(float));
    memcpy(row + 6, s->latents + k * dim, dim * sizeof(float));
  }
}

static void queries_free(queries *s) {
  free(s->q);
  free(s->wi);
  free(s->wo);
  free(s->latents);
}

/* Compares the shader's (f, o) with the C reference; raw == NULL skips o. */
static void compare(const char *label, const queries *s, const float *gpu, const float *f,
                    const float *raw) {
  double worst_f = 0, worst_o = 0;
  size_t bad = 0, positive = 0;
  for (size_t k = 0; k < s->n; k++) {
    double ef = fabs(gpu[2 * k] - f[k]) / (1.0 + fabs(f[k]));
    double eo = raw ? fabs(gpu[2 * k + 1] - raw[k]) / (1.0 + fabs(raw[k])) : 0.0;
    if (!(ef <= TOL) || !(eo <= TOL)) {
      if (bad++ < 3)
        printf("  %s query %zu: f %.9g vs %.9g, o %.9g vs %.9g (wi.z %g wo.z %g)\n", label, k,
               gpu[2 * k], f[k], gpu[2 * k + 1], raw ? raw[k] : 0.0, s->wi[3 * k + 2],
               s->wo[3 * k + 2]);
    }
    if (ef > worst_f || ef != ef) worst_f = ef;
    if (eo > worst_o || eo != eo) worst_o = eo;
    /* Raw outputs away from 0 show that the network did something (f clamps at 0). */
    positive += raw ? fabsf(raw[k]) > 1e-3f : f[k] > 1e-3f;
  }
  printf("  %-28s %zu queries: max error f %.2e, raw %.2e; %zu with |o| or f > 1e-3\n", label, s->n,
         worst_f, worst_o, positive);
  CHECK_MSG(bad == 0, "%s: %zu of %zu queries beyond %.0e", label, bad, s->n, TOL);
  /* A decoder whose output is clamped to 0 everywhere would compare equal vacuously. */
  CHECK_MSG(positive > s->n / 10, "%s: only %zu of %zu values are away from 0", label, positive,
            s->n);
}

/* A decoder made in memory, compared on its raw output too (model_decoder_eval is what
 * nbrdf_model_decode runs). */
static void check_config(const char *label, const model_decoder_config *cfg, size_t n,
                         uint64_t seed) {
  nbrdf_error err = {0};
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_create(cfg, seed, &dec, &err), &err);
  if (!dec) return;
  size_t words_n = 0;
  CHECK_OK(model_gpu_pack_decoder(dec, NULL, 0, &words_n, &err), &err);
  uint32_t *words = malloc(words_n * 4);
  CHECK_OK(model_gpu_pack_decoder(dec, words, words_n, NULL, &err), &err);
  queries s;
  queries_make(&s, n, cfg->latent_dim, seed);
  int in = model_decoder_inputs(dec);
  float *x = malloc(sizeof(float) * n * in), *raw = malloc(sizeof(float) * n);
  float *f = malloc(sizeof(float) * n), *gpu = malloc(sizeof(float) * 2 * n);
  model_decoder_fill_inputs(dec, n, 1, s.latents, s.wi, s.wo, x);
  nn_workspace *ws = NULL;
  CHECK_OK(nn_workspace_create(dec->nn, 1024, NBRDF_NN_INFER, &ws, &err), &err);
  CHECK_OK(nn_forward(dec->nn, ws, x, (int)n, raw, &err), &err);
  for (size_t k = 0; k < n; k++)
    f[k] = model_output_to_f(cfg->output, raw[k]);
  int rc = fixture_run_decoder(vk, words, words_n, s.q, n, gpu, NULL);
  CHECK_MSG(rc == 0, "%s: %s", label, vkh_error(vk));
  if (rc == 0) compare(label, &s, gpu, f, raw);
  nn_workspace_destroy(ws);
  free(x), free(raw), free(f), free(gpu), free(words);
  queries_free(&s);
  model_decoder_destroy(dec);
}

static void test_presets(void) {
  const char *presets[] = {"small", "medium", "large", "paper"};
  const size_t counts[] = {4096, 4096, 2048, 1024};
  for (int p = 0; p < 4; p++) {
    model_decoder_config cfg;
    nbrdf_error err = {0};
    CHECK_OK(model_decoder_preset(presets[p], 32, &cfg, &err), &err);
    char label[64];
    snprintf(label, sizeof label, "preset %s", presets[p]);
    check_config(label, &cfg, counts[p], 11 + (uint64_t)p);
  }
}

static void test_encodings_and_outputs(void) {
  struct {
    model_encoding_kind kind;
    int octaves;
    model_output output;
    const char *label;
  } cases[] = {{MODEL_ENCODING_HALFDIFF, 4, MODEL_OUTPUT_LOG1P, "halfdiff, 4 octaves, log1p"},
               /* 6 octaves: at 8, a few of 4,096 near-grazing queries go past 1e-4 (the
                * encoding kernel's own bound below says why) */
               {MODEL_ENCODING_HALFDIFF, 6, MODEL_OUTPUT_F, "halfdiff, 6 octaves, f"},
               {MODEL_ENCODING_CARTESIAN, 2, MODEL_OUTPUT_LOG1P, "cartesian, 2 octaves, log1p"},
               {MODEL_ENCODING_CARTESIAN, 0, MODEL_OUTPUT_F, "cartesian, f"}};
  for (int c = 0; c < 4; c++) {
    model_decoder_config cfg;
    nbrdf_error err = {0};
    model_encoding enc = {cases[c].kind, cases[c].octaves};
    CHECK_OK(model_decoder_config_make(16, enc, cases[c].output, 48, 2, 1, &cfg, &err), &err);
    check_config(cases[c].label, &cfg, 4096, 100 + (uint64_t)c);
  }
}

/* Skip connections from the network input: projected (widths differ) and identity (equal
 * widths) run in the shader; a skip from any other activation is refused by the packer. */
static void test_skips(void) {
  nbrdf_error err = {0};
  model_decoder_config cfg;
  model_encoding hd = {MODEL_ENCODING_HALFDIFF, 0};
  /* 26 + 6 = 32 inputs = the width: layer 2 (plain) gets an identity skip, layer 4 (plain)
   * and the output (linear, 1 wide) projected ones. */
  CHECK_OK(model_decoder_config_make(26, hd, MODEL_OUTPUT_LOG1P, 32, 2, 1, &cfg, &err), &err);
  nn_spec_skip(&cfg.spec, 2, 0);
  nn_spec_skip(&cfg.spec, 5, 0);
  CHECK_OK(nn_spec_validate(&cfg.spec, &err), &err);
  check_config("skips from the input", &cfg, 2048, 31);

  nn_spec_skip(&cfg.spec, 4, 2);
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_create(&cfg, 1, &dec, &err), &err);
  size_t n = 0;
  if (dec)
    CHECK_FAILS(model_gpu_pack_decoder(dec, NULL, 0, &n, &err), NBRDF_ERR_UNSUPPORTED, &err,
                "skip from activation 2");
  model_decoder_destroy(dec);
}

/* The public path a renderer integration takes: a bundle on disk (`nbrdf bundle init`),
 * nbrdf_gpu_pack_decoder, and nbrdf_model_decode as the reference. */
static void test_bundle(void) {
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/bundle", testing_tmpdir());
  nbrdf_error err = {0};
  CHECK_OK(model_bundle_init_random(dir, "shader-test", 7, "medium", &err), &err);
  nbrdf_model *model = NULL;
  CHECK_OK(nbrdf_model_load(dir, &model, &err), &err);
  if (!model) return;
  size_t words_n = 0;
  CHECK_OK(nbrdf_gpu_pack_decoder(model, NULL, 0, &words_n, &err), &err);
  uint32_t *words = malloc(words_n * 4);
  CHECK_FAILS(nbrdf_gpu_pack_decoder(model, words, words_n - 1, NULL, &err), NBRDF_ERR_ARGUMENT,
              &err, "needs");
  CHECK_OK(nbrdf_gpu_pack_decoder(model, words, words_n, NULL, &err), &err);
  CHECK(words[NBRDF_GPU_W_MAGIC] == NBRDF_GPU_DECODER_MAGIC);
  CHECK(words[NBRDF_GPU_W_MACS] == (uint32_t)nbrdf_model_decoder_macs(model));
  CHECK(words[NBRDF_GPU_W_MAX_WIDTH] == 64); /* medium: width 64 > 38 inputs */
  queries s;
  size_t n = 4000;
  int dim = nbrdf_model_latent_dim(model);
  queries_make(&s, n, dim, 21);
  float *f = malloc(sizeof(float) * n), *gpu = malloc(sizeof(float) * 2 * n);
  CHECK_OK(nbrdf_model_decode(model, n, 1, s.latents, s.wi, s.wo, f, &err), &err);
  int rc = fixture_run_decoder(vk, words, words_n, s.q, n, gpu, NULL);
  CHECK_MSG(rc == 0, "bundle: %s", vkh_error(vk));
  if (rc == 0) compare("bundle (nbrdf_model_decode)", &s, gpu, f, NULL);
  free(f), free(gpu), free(words);
  queries_free(&s);
  nbrdf_model_destroy(model);
}

/* A texture that carries its own decoder (format version 2): the buffer packed from
 * nbrdf_model_for_texture's model runs the embedded decoder on the GPU, not the bundle's. */
static void test_texture_own_decoder(void) {
  char dir[1024], tex[1100];
  snprintf(dir, sizeof dir, "%s/bundle-own", testing_tmpdir());
  snprintf(tex, sizeof tex, "%s/own.exr", testing_tmpdir());
  nbrdf_error err = {0};
  CHECK_OK(model_bundle_init_random(dir, "shader-own", 7, "medium", &err), &err);
  nbrdf_model *bundle = NULL, *own = NULL, *for_tex = NULL;
  CHECK_OK(nbrdf_model_load(dir, &bundle, &err), &err);
  if (!bundle) return;
  /* The bundle's decoder with every 5th weight scaled: decodes differently. */
  char file[1100];
  snprintf(file, sizeof file, "%s/decoder.safetensors", dir);
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_load(file, &dec, &err), &err);
  size_t n_params = dec ? nn_param_count(dec->nn) : 0;
  float *params = dec ? nn_params(dec->nn) : NULL;
  for (size_t k = 0; k < n_params; k += 5)
    params[k] *= 0.7f;
  if (dec) CHECK_OK(model_with_decoder_net(bundle, dec, &own, &err), &err);
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  const float p[NBRDF_BAKE_PARAM_COUNT] = {0.2f, 1.5f, 0.3f, 0.8f, 0.5f, 1.0f};
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    nbrdf_bake_param_constant(&in.param[id], p[id]);
  if (own) CHECK_OK(nbrdf_bake(own, &in, NULL, tex, NULL, &err), &err);
  CHECK_OK(nbrdf_model_for_texture(bundle, tex, &for_tex, &err), &err);
  if (!for_tex) {
    model_decoder_destroy(dec), nbrdf_model_destroy(own), nbrdf_model_destroy(bundle);
    return;
  }
  size_t words_n = 0;
  CHECK_OK(nbrdf_gpu_pack_decoder(for_tex, NULL, 0, &words_n, &err), &err);
  uint32_t *words = malloc(words_n * 4);
  CHECK_OK(nbrdf_gpu_pack_decoder(for_tex, words, words_n, NULL, &err), &err);
  /* The embedded weights, exactly. */
  CHECK(words[NBRDF_GPU_W_PARAM_COUNT] == n_params &&
        words[NBRDF_GPU_W_PARAMS] + n_params == words_n &&
        !memcmp(words + words[NBRDF_GPU_W_PARAMS], params, n_params * 4));
  model_decoder_destroy(dec);
  queries s;
  size_t n = 2000;
  queries_make(&s, n, nbrdf_model_latent_dim(bundle), 23);
  float *f = malloc(sizeof(float) * n), *fb = malloc(sizeof(float) * n);
  float *gpu = malloc(sizeof(float) * 2 * n);
  CHECK_OK(nbrdf_model_decode(own, n, 1, s.latents, s.wi, s.wo, f, &err), &err);
  CHECK_OK(nbrdf_model_decode(bundle, n, 1, s.latents, s.wi, s.wo, fb, &err), &err);
  int rc = fixture_run_decoder(vk, words, words_n, s.q, n, gpu, NULL);
  CHECK_MSG(rc == 0, "own decoder: %s", vkh_error(vk));
  if (rc == 0) compare("texture's own decoder", &s, gpu, f, NULL);
  size_t differ = 0;
  for (size_t k = 0; k < n; k++)
    differ += fabs(gpu[2 * k] - fb[k]) > 1e-3 * (1.0 + fabs(fb[k]));
  CHECK_MSG(differ > n / 2, "only %zu of %zu GPU values differ from the bundle's decoder", differ,
            n);
  free(f), free(fb), free(gpu), free(words);
  queries_free(&s);
  nbrdf_model_destroy(for_tex), nbrdf_model_destroy(own), nbrdf_model_destroy(bundle);
}

/* A compact texture's decoder (issue 19): 8 latents, one frequency octave,
 * one residual block; packed from a model derived for it (nbrdf_model's
 * latent dimension 8, the bundle's 32) and run on the GPU as the C decoder
 * runs it. */
static void test_compact_decoder(void) {
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/bundle-compact", testing_tmpdir());
  nbrdf_error err = {0};
  CHECK_OK(model_bundle_init_random(dir, "shader-compact", 9, "medium", &err), &err);
  nbrdf_model *bundle = NULL, *compact = NULL;
  CHECK_OK(nbrdf_model_load(dir, &bundle, &err), &err);
  if (!bundle) return;
  model_decoder_config cfg;
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_compact_config(BAKE_COMPACT_DEFAULT_DIM, BAKE_COMPACT_DEFAULT_WIDTH, &cfg, &err),
           &err);
  CHECK_OK(model_decoder_create(&cfg, 5, &dec, &err), &err);
  if (dec) CHECK_OK(model_with_decoder_net(bundle, dec, &compact, &err), &err);
  model_decoder_destroy(dec);
  if (!compact) {
    nbrdf_model_destroy(bundle);
    return;
  }
  CHECK(nbrdf_model_latent_dim(compact) == BAKE_COMPACT_DEFAULT_DIM);
  size_t words_n = 0;
  CHECK_OK(nbrdf_gpu_pack_decoder(compact, NULL, 0, &words_n, &err), &err);
  uint32_t *words = malloc(words_n * 4);
  CHECK_OK(nbrdf_gpu_pack_decoder(compact, words, words_n, NULL, &err), &err);
  CHECK(words[NBRDF_GPU_W_LATENT_DIM] == BAKE_COMPACT_DEFAULT_DIM);
  queries s;
  size_t n = 4096;
  queries_make(&s, n, BAKE_COMPACT_DEFAULT_DIM, 29);
  float *f = malloc(sizeof(float) * n), *gpu = malloc(sizeof(float) * 2 * n);
  CHECK_OK(nbrdf_model_decode(compact, n, 1, s.latents, s.wi, s.wo, f, &err), &err);
  int rc = fixture_run_decoder(vk, words, words_n, s.q, n, gpu, NULL);
  CHECK_MSG(rc == 0, "compact decoder: %s", vkh_error(vk));
  if (rc == 0) compare("compact decoder", &s, gpu, f, NULL);
  free(f), free(gpu), free(words);
  queries_free(&s);
  nbrdf_model_destroy(compact), nbrdf_model_destroy(bundle);
}

/* The encoding kernel alone against model_encode, so that a mismatch is located. */
static void test_encoding_kernel(void) {
  const size_t n = 4096;
  core_rng rng;
  core_rng_init(&rng, 5, 1);
  float *wi = malloc(sizeof(float) * 3 * n), *wo = malloc(sizeof(float) * 3 * n);
  float *pairs = malloc(sizeof(float) * 6 * n), *ref = malloc(sizeof(float) * 102 * n);
  for (size_t k = 0; k < n; k++) {
    fixture_direction(&rng, wi + 3 * k);
    fixture_direction(&rng, wo + 3 * k);
    memcpy(pairs + 6 * k, wi + 3 * k, 12);
    memcpy(pairs + 6 * k + 3, wo + 3 * k, 12);
  }
  vkh_buffer pb, fb;
  vkh_kernel kern;
  int rc = vkh_buffer_create(vk, 6 * n * 4, &pb);
  if (!rc) rc = vkh_buffer_create(vk, 102 * n * 4, &fb);
  if (!rc) rc = vkh_kernel_create(vk, "encode.spv", 2, 12, 0, NULL, &kern);
  CHECK_MSG(rc == 0, "encode kernel: %s", vkh_error(vk));
  if (rc) return;
  memcpy(pb.map, pairs, 6 * n * 4);
  vkh_buffer *bind[2] = {&pb, &fb};
  vkh_kernel_bind(vk, &kern, bind);
  for (int kind = 0; kind < 2; kind++) {
    model_encoding enc = {(model_encoding_kind)kind, MODEL_ENCODING_MAX_OCTAVES};
    model_encode(&enc, n, wi, wo, ref, 102);
    uint32_t push[3] = {(uint32_t)n, (uint32_t)kind, (uint32_t)enc.octaves};
    CHECK(vkh_run(vk, &kern, push, (uint32_t)((n + 63) / 64), NULL) == 0);
    const float *g = fb.map;
    double worst_base = 0, worst_freq = 0;
    for (size_t k = 0; k < n; k++)
      for (int j = 0; j < 102; j++) {
        double e = fabs(g[102 * k + j] - ref[102 * k + j]);
        if (j < 6 && !(e <= worst_base)) worst_base = e;
        if (j >= 6 && !(e <= worst_freq)) worst_freq = e;
      }
    printf("  encoding %s: max |error| base %.2e, frequencies (octaves < 8) %.2e\n",
           model_encoding_kind_name(enc.kind), worst_base, worst_freq);
    /* Base features: a few ulp. sin(2^7 π x) amplifies the input's float rounding by 2^7 π
     * ≈ 400 (the C side rounds the features from double), hence the looser bound; the
     * rotation of both directions to ωi's azimuth 0 (model_encode_canonical) adds one
     * float rounding before the half vector (measured 2.1e-3 on these queries, 25 % of
     * them within 0.6° of the horizon). */
    CHECK_MSG(worst_base <= 1e-5, "%s: base features differ by %g",
              model_encoding_kind_name(enc.kind), worst_base);
    CHECK_MSG(worst_freq <= 3e-3, "%s: frequency features differ by %g",
              model_encoding_kind_name(enc.kind), worst_freq);
  }
  vkh_kernel_destroy(vk, &kern);
  vkh_buffer_destroy(vk, &pb);
  vkh_buffer_destroy(vk, &fb);
  free(wi), free(wo), free(pairs), free(ref);
}

int main(void) {
  char msg[512];
  if (vkh_open(&vk, msg, sizeof msg) != 0) {
    fprintf(stderr, "Vulkan: %s\n", msg);
    return 1;
  }
  printf("device: %s\n", vkh_device_name(vk));
  RUN(test_encoding_kernel);
  RUN(test_presets);
  RUN(test_encodings_and_outputs);
  RUN(test_skips);
  RUN(test_bundle);
  RUN(test_texture_own_decoder);
  RUN(test_compact_decoder);
  vkh_close(vk);
  return testing_finish();
}
#else
int main(void) {
  puts("shader tests not built: configured with NBRDF_BUILD_SHADERS=OFF");
  return 0;
}
#endif
