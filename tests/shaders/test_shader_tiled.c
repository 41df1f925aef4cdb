/* The tiled decoder kernels (shaders/nbrdf_tiled.glsl) against the C decoder: the fp32
 * kernel nbrdf_decode_tiled.spv on lavapipe (every preset, both encodings, frequency
 * octaves, both output transforms, skip connections, a compact decoder, the shipped
 * models/medium and models/default), and the fp16 tensor-core kernel nbrdf_decode_coop.spv
 * where the device has VK_NV_cooperative_matrix (skipped with a message elsewhere: lavapipe
 * cannot load its SPIR-V), and that kernel with its three matrix operations emulated in
 * plain arithmetic (nbrdf_decode_coopemu.spv: the tensor-core kernel's tiles, strides,
 * padding, fp16 rounding and passes, on lavapipe).
 *
 * Tolerance of the fp32 kernel: raw output o within tol (1 + |o|) and f within tol (1 + f),
 * tol = max(base, 2 G K u): u = 2^-24 the float unit roundoff, K the widest fan-in of a
 * GEMM of the network, G the GEMMs on the path (a residual block's two, a projected skip's).
 * K u bounds (to first order) the rounding error of a K-term dot product relative to
 * sum |w x|, in ANY summation order, with or without fused multiply-adds: the C side sums
 * in sgemm's blocked order, the shader in input order on lavapipe, and a GPU driver may
 * reorder and contract mul + add into FMA (NVIDIA does: preset medium, raw 1.34e-5 on an
 * H200); the two computations give 2 K u per GEMM, and the LayerNorm after each keeps the
 * activations O(1), so the layers' errors add up (G), they do not multiply. This is the
 * float rounding of the computation, not a measured margin (printed per case: preset medium
 * 8.4e-5, models/default 1.3e-4, compact 1.5e-5; lavapipe measures at most 2.4e-5, with
 * 6 octaves, and 6.6e-6 without).
 * base = 1e-5 (a floor for tiny networks), 5e-5 with 4 or 6 frequency octaves, where both
 * shaders inherit the encoding's float error: sin(2^k pi x) amplifies the rounding of x by
 * 2^k pi (test_shader_decoder.c; measured 1.1e-5 and 2.3e-5 here). No shipped decoder uses
 * more than 1 octave.
 * fp16 kernels (tensor cores, emulated): median |log(1 + f) - log(1 + f_C)| <= 0.02 and every query
 * within 0.25: a guard against a wrong kernel (which is off by O(1)), not a precision claim
 * (bench_shader measures its error). */
#include "testing.h"

#ifdef NBRDF_HAVE_VULKAN
#include <stdlib.h>
#include <string.h>

#include "bake/bake_compact.h"
#include "model/decoder.h"
#include "model/gpu_pack.h"
#include "shader_fixture.h"

static vkh *vk;

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

/* 2 G K u (the header's tolerance note) from the packed layer records. */
static double rounding_bound(const uint32_t *words) {
  uint32_t K = words[NBRDF_GPU_W_INPUTS], G = 0;
  for (uint32_t l = 0; l < words[NBRDF_GPU_W_LAYERS]; l++) {
    const uint32_t *r = words + 16 + 16 * l;
    uint32_t kind = r[0], in = r[1], hidden = r[3];
    if (kind != 1u && kind != 4u && kind != 5u) continue; /* LayerNorm, ReLU: no GEMM */
    G += kind == 5u ? 2u : 1u;
    if (in > K) K = in;
    if (kind == 5u && hidden > K) K = hidden;
    if (r[4] != NBRDF_GPU_NONE && r[14] != NBRDF_GPU_NONE) G++, K = r[5] > K ? r[5] : K;
  }
  return 2.0 * G * K * 0x1p-24;
}

/* Random queries (a quarter grazing) and the C reference of `dec` on them, then the tiled
 * kernel(s); prints the errors. */
static void check_decoder(const char *label, const model_decoder *dec, size_t n, uint64_t seed,
                          double tol) {
  nbrdf_error err = {0};
  size_t nw = 0;
  CHECK_OK(model_gpu_pack_decoder(dec, NULL, 0, &nw, &err), &err);
  uint32_t *words = malloc(nw * 4);
  CHECK_OK(model_gpu_pack_decoder(dec, words, nw, NULL, &err), &err);
  tol = fmax(tol, rounding_bound(words));
  int dim = dec->cfg.latent_dim, in = model_decoder_inputs(dec);
  core_rng rng;
  core_rng_init(&rng, seed, 9);
  float *q = malloc(sizeof(float) * n * (6 + dim)), *wi = malloc(12 * n), *wo = malloc(12 * n);
  float *lat = malloc(sizeof(float) * n * dim), *x = malloc(sizeof(float) * n * in);
  float *raw = malloc(4 * n), *gpu = malloc(8 * n);
  for (size_t k = 0; k < n; k++) {
    fixture_direction(&rng, wi + 3 * k);
    fixture_direction(&rng, wo + 3 * k);
    for (int i = 0; i < dim; i++)
      lat[k * dim + i] = (float)(3.0 * core_rng_uniform(&rng) - 1.5);
    float *row = q + k * (6 + dim);
    memcpy(row, wi + 3 * k, 12);
    memcpy(row + 3, wo + 3 * k, 12);
    memcpy(row + 6, lat + k * dim, 4 * dim);
  }
  model_decoder_fill_inputs(dec, n, 1, lat, wi, wo, x);
  nn_workspace *ws = NULL;
  CHECK_OK(nn_workspace_create(dec->nn, 1024, NBRDF_NN_INFER, &ws, &err), &err);
  CHECK_OK(nn_forward(dec->nn, ws, x, (int)n, raw, &err), &err);
  for (int coop = 0; coop < 3; coop++) {
    if (coop == 1 && !vkh_has_coop(vk)) {
      printf("  %-34s nbrdf_decode_coop.spv skipped (no VK_NV_cooperative_matrix)\n", label);
      continue;
    }
    if (coop == 2 && !vkh_has_f16(vk)) {
      printf("  %-34s nbrdf_decode_coopemu.spv skipped (no shaderFloat16 / quad operations)\n",
             label);
      continue;
    }
    nbrdf_tile_config cfg = {{0}, 0, 0, 0};
    int rc = fixture_run_tiled(vk, words, nw, q, n, gpu, coop, &cfg);
    if (rc == -2) {
      printf("  %-34s %s: no tile fits %u B of shared memory (skipped)\n", label,
             coop == 2 ? "emu  "
             : coop    ? "coop "
                       : "tiled",
             vkh_max_shared(vk));
      CHECK_MSG(coop != 0, "%s: the fp32 tile must fit every device", label);
      continue;
    }
    CHECK_MSG(rc == 0, "%s (%s): %s", label,
              coop == 2 ? "emu"
              : coop    ? "coop"
                        : "tiled",
              vkh_error(vk));
    if (rc) continue;
    double worst_f = 0, worst_o = 0, worst_l = 0, *logs = malloc(sizeof(double) * n);
    size_t bad = 0, positive = 0;
    for (size_t k = 0; k < n; k++) {
      double f = model_output_to_f(dec->cfg.output, raw[k]);
      double ef = fabs(gpu[2 * k] - f) / (1.0 + fabs(f));
      double eo = fabs(gpu[2 * k + 1] - raw[k]) / (1.0 + fabs(raw[k]));
      double el = fabs(log1p(fmax(gpu[2 * k], 0.0)) - log1p(fmax(f, 0.0)));
      int ok = coop ? el <= 0.25 : ef <= tol && eo <= tol;
      if (coop) logs[k] = el != el ? 1e30 : el;
      if (!ok && bad++ < 3)
        printf("    query %zu: f %.9g vs %.9g, o %.9g vs %.9g\n", k, gpu[2 * k], f, gpu[2 * k + 1],
               raw[k]);
      if (!(ef <= worst_f)) worst_f = ef;
      if (!(eo <= worst_o)) worst_o = eo;
      if (!(el <= worst_l)) worst_l = el;
      positive += fabsf(raw[k]) > 1e-3f;
    }
    double median = 0;
    if (coop) {
      qsort(logs, n, sizeof(double), cmp_double);
      median = logs[n / 2];
    }
    free(logs);
    printf("  %-34s %s %3u rows x %3u threads, %5u B shared: %zu queries, max error f %.2e, raw "
           "%.2e, log1p f %.2e",
           label,
           coop == 2 ? "emu  "
           : coop    ? "coop "
                     : "tiled",
           cfg.rows, cfg.threads, cfg.shared_bytes, n, worst_f, worst_o, worst_l);
    if (coop)
      printf(" (median %.2e)", median);
    else
      printf(" (tolerance %.1e)", tol);
    printf("\n");
    if (coop) CHECK_MSG(median <= 0.02, "%s (coop): median log1p error %.3g > 0.02", label, median);
    CHECK_MSG(bad == 0, "%s (%s): %zu of %zu queries beyond the tolerance", label,
              coop ? "coop" : "tiled", bad, n);
    CHECK_MSG(positive > n / 10, "%s: only %zu of %zu raw outputs away from 0", label, positive, n);
  }
  nn_workspace_destroy(ws);
  free(words), free(q), free(wi), free(wo), free(lat), free(x), free(raw), free(gpu);
}

static void check_config(const char *label, const model_decoder_config *cfg, size_t n,
                         uint64_t seed, double tol) {
  nbrdf_error err = {0};
  model_decoder *dec = NULL;
  CHECK_OK(model_decoder_create(cfg, seed, &dec, &err), &err);
  if (dec) check_decoder(label, dec, n, seed, tol);
  model_decoder_destroy(dec);
}

static void test_presets(void) {
  const char *presets[] = {"small", "medium", "large", "paper"};
  const size_t counts[] = {4096, 4096, 2048, 512};
  for (int p = 0; p < 4; p++) {
    model_decoder_config cfg;
    nbrdf_error err = {0};
    CHECK_OK(model_decoder_preset(presets[p], 32, &cfg, &err), &err);
    char label[64];
    snprintf(label, sizeof label, "preset %s", presets[p]);
    check_config(label, &cfg, counts[p], 11 + (uint64_t)p, 1e-5);
  }
}

static void test_encodings_and_outputs(void) {
  struct {
    model_encoding_kind kind;
    int octaves;
    model_output output;
    const char *label;
    double tol;
  } cases[] = {
      {MODEL_ENCODING_HALFDIFF, 4, MODEL_OUTPUT_LOG1P, "halfdiff, 4 octaves, log1p", 5e-5},
      {MODEL_ENCODING_HALFDIFF, 6, MODEL_OUTPUT_F, "halfdiff, 6 octaves, f", 5e-5},
      {MODEL_ENCODING_CARTESIAN, 2, MODEL_OUTPUT_LOG1P, "cartesian, 2 octaves, log1p", 1e-5},
      {MODEL_ENCODING_CARTESIAN, 0, MODEL_OUTPUT_F, "cartesian, f", 1e-5}};
  for (int c = 0; c < 4; c++) {
    model_decoder_config cfg;
    nbrdf_error err = {0};
    model_encoding enc = {cases[c].kind, cases[c].octaves};
    /* width 50: neither a multiple of 4 nor of 16 (ragged blocks and tiles) */
    CHECK_OK(model_decoder_config_make(16, enc, cases[c].output, 50, 2, 1, &cfg, &err), &err);
    check_config(cases[c].label, &cfg, 4096, 100 + (uint64_t)c, cases[c].tol);
  }
}

/* Skips from the network input: identity (equal widths) and projected. */
static void test_skips(void) {
  nbrdf_error err = {0};
  model_decoder_config cfg;
  model_encoding hd = {MODEL_ENCODING_HALFDIFF, 0};
  CHECK_OK(model_decoder_config_make(26, hd, MODEL_OUTPUT_LOG1P, 32, 2, 1, &cfg, &err), &err);
  nn_spec_skip(&cfg.spec, 2, 0);
  nn_spec_skip(&cfg.spec, 5, 0);
  CHECK_OK(nn_spec_validate(&cfg.spec, &err), &err);
  check_config("skips from the input", &cfg, 2048, 31, 1e-5);
}

static void test_compact(void) {
  model_decoder_config cfg;
  nbrdf_error err = {0};
  CHECK_OK(model_decoder_compact_config(BAKE_COMPACT_DEFAULT_DIM, BAKE_COMPACT_DEFAULT_WIDTH, &cfg,
                                        &err),
           &err);
  check_config("compact 8x32", &cfg, 4096, 29, 1e-5);
}

/* The shipped decoders (trained weights: realistic activations). */
static void test_models(void) {
  const char *names[] = {"medium", "default"};
  for (int m = 0; m < 2; m++) {
    char path[1200];
    snprintf(path, sizeof path, "%s/models/%s/decoder.safetensors", testing_source_dir(), names[m]);
    nbrdf_error err = {0};
    model_decoder *dec = NULL;
    CHECK_OK(model_decoder_load(path, &dec, &err), &err);
    char label[64];
    snprintf(label, sizeof label, "models/%s", names[m]);
    if (dec) check_decoder(label, dec, 4096, 40 + (uint64_t)m, 1e-5);
    model_decoder_destroy(dec);
  }
}

int main(void) {
  char msg[512];
  if (vkh_open(&vk, msg, sizeof msg) != 0) {
    fprintf(stderr, "Vulkan: %s\n", msg);
    return 1;
  }
  printf("device: %s (shared memory %u B, %u invocations, subgroup %u, cooperative matrix %s)\n",
         vkh_device_name(vk), vkh_max_shared(vk), vkh_max_invocations(vk), vkh_subgroup_size(vk),
         vkh_has_coop(vk) ? "yes" : "no");
  RUN(test_presets);
  RUN(test_encodings_and_outputs);
  RUN(test_skips);
  RUN(test_compact);
  RUN(test_models);
  vkh_close(vk);
  return testing_finish();
}
#else
int main(void) {
  puts("shader tests not built: configured with NBRDF_BUILD_SHADERS=OFF");
  return 0;
}
#endif
