/* The material kernel (fetch + one decode per colour channel + proxy pdf) of a whole
 * 1920 x 1080 frame on a Vulkan device, for three kernels: the per-invocation decoder
 * (shaders/nbrdf_shade.spv), the tiled fp32 one (nbrdf_shade_tiled.spv) and the fp16
 * tensor-core one (nbrdf_shade_coop.spv, where the device has VK_NV_cooperative_matrix),
 * each against the fp32 C decoder. Prints a Markdown table (docs/SHADERS.md). Where the
 * device has no cooperative matrices but fp16 (lavapipe), the fp16 kernel with emulated
 * matrix operations (nbrdf_shade_coopemu.spv) gives that kernel's errors.
 *
 *   bench_shader                  1920x1080, decoders: compact 8x32 (untrained; the cost
 *                                 does not depend on the weights), models/medium,
 *                                 models/default (trained)
 *   bench_shader --quick          fewer repetitions; on a CPU device (lavapipe) 2,048 pixels
 *   bench_shader --pixels N       N pixels (queries) instead
 *   bench_shader --models DIR     where medium/ and default/ are (default: models)
 *   bench_shader --presets        adds the untrained presets small, medium, large
 *   NBRDF_VK_DEVICE=NVIDIA bench_shader   the device (tests/shaders/vk_harness.h)
 *
 * One query per pixel: (u, v, lod) in a random 128 x 128 latent texture with its mip
 * chain, random directions (cos θ in [0.01, 1]). The RGB frame = the texture has 3 colour
 * channels, i.e. 3 decodes per pixel (the same directions, each channel's latents); the
 * per-channel figure is a 1-channel texture of the same size. Times: GPU timestamps
 * around `reps` back-to-back dispatches (barriers between them) after one warm-up
 * dispatch, divided by reps (wall time of submit + wait where the device has no
 * timestamps). TFLOP/s = 2 x MACs x decodes / time (the decoder's GEMMs only).
 * Errors: on a sample of pixels (every k-th), each channel's f against the C reference
 * (texture_latent_fetch + model_decoder_eval in fp32): err f = |f - f_C| / (1 + f_C),
 * rel f = |f - f_C| / f_C where f_C > 0.01, log1p = |log(1 + f) - log(1 + f_C)|. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_clock.h"

#ifdef NBRDF_HAVE_VULKAN
#include "model/decoder.h"
#include "model/gpu_pack.h"
#include "nbrdf/gpu_pack.h"
#include "nbrdf_tiled.h"
#include "texture/latent_fetch.h"
#include "vk_harness.h"

static void die(const char *what, const char *msg) {
  fprintf(stderr, "bench_shader: %s: %s\n", what, msg);
  exit(1);
}

static unsigned lcg(unsigned *s) {
  *s = *s * 1664525u + 1013904223u;
  return *s >> 8;
}
static float uni(unsigned *s) { return (float)lcg(s) / 16777216.0f; }

/* A random latent texture, 128 x 128 with its mip chain: latents in [-1.5, 1.5], sigma in
 * [0.05, 1], w in [0, 1]. */
static texture_latent_image *make_texture(int dim, int colours, unsigned seed) {
  texture_latent_layout layout = {dim, colours == 3 ? NBRDF_COLOUR_RGB : NBRDF_COLOUR_MONO, 1};
  texture_latent_image *img = NULL;
  nbrdf_error err = {0};
  if (texture_latent_image_create(&layout, 128, 128, 8, &img, &err) != NBRDF_OK)
    die("texture", err.message);
  for (int l = 0; l < img->levels; l++)
    for (size_t t = 0; t < (size_t)img->width[l] * img->height[l]; t++)
      for (int c = 0; c < colours; c++) {
        float *texel = img->data[l] + t * img->channels;
        for (int k = 0; k < dim; k++)
          texel[texture_latent_index_latent(&layout, c, k)] = 3.0f * uni(&seed) - 1.5f;
        texel[texture_latent_index_sigma(&layout, c)] = 0.05f + 0.95f * uni(&seed);
        texel[texture_latent_index_w(&layout, c)] = uni(&seed);
      }
  return img;
}

static void pack_texture(vkh *vk, const texture_latent_image *img, int colours, vkh_buffer *b) {
  nbrdf_error err = {0};
  const float *data[TEXTURE_LATENT_MAX_LEVELS];
  for (int l = 0; l < img->levels; l++)
    data[l] = img->data[l];
  size_t n = 0;
  if (nbrdf_gpu_pack_latents(img->levels, img->width, img->height, img->channels,
                             img->layout.latent_dim, colours, 1, data, NULL, 0, &n, &err))
    die("pack", err.message);
  if (vkh_buffer_create(vk, n * 4, b)) die("buffer", vkh_error(vk));
  if (nbrdf_gpu_pack_latents(img->levels, img->width, img->height, img->channels,
                             img->layout.latent_dim, colours, 1, data, b->map, n, NULL, &err))
    die("pack", err.message);
}

typedef struct bench_row {
  char label[256];
  model_decoder *dec;
} bench_row;

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

typedef struct errors {
  double max_f, med_f, max_rel, med_rel, max_l, med_l;
} errors;

static errors compare(const float *g, const float *ref, const size_t *pix, size_t s) {
  double *ef = malloc(sizeof(double) * 3 * s), *el = malloc(sizeof(double) * 3 * s);
  double *er = malloc(sizeof(double) * 3 * s);
  size_t nr = 0;
  errors e = {0, 0, 0, 0, 0, 0};
  for (size_t i = 0; i < s; i++)
    for (int c = 0; c < 3; c++) {
      double a = g[4 * pix[i] + c], b = ref[3 * i + c];
      double d = fabs(a - b);
      ef[3 * i + c] = d != d ? 1e30 : d / (1.0 + fabs(b));
      el[3 * i + c] = fabs(log1p(fmax(a, 0.0)) - log1p(fmax(b, 0.0)));
      if (el[3 * i + c] != el[3 * i + c]) el[3 * i + c] = 1e30;
      if (b > 0.01) er[nr++] = d != d ? 1e30 : d / b;
    }
  qsort(ef, 3 * s, sizeof(double), cmp_double);
  qsort(el, 3 * s, sizeof(double), cmp_double);
  qsort(er, nr, sizeof(double), cmp_double);
  e.max_f = ef[3 * s - 1], e.med_f = ef[3 * s / 2];
  e.max_l = el[3 * s - 1], e.med_l = el[3 * s / 2];
  if (nr) e.max_rel = er[nr - 1], e.med_rel = er[nr / 2];
  free(ef), free(el), free(er);
  return e;
}

int main(int argc, char **argv) {
  int quick = 0, presets = 0;
  long pixels = 0;
  const char *models = "models";
  for (int a = 1; a < argc; a++) {
    if (!strcmp(argv[a], "--quick"))
      quick = 1;
    else if (!strcmp(argv[a], "--presets"))
      presets = 1;
    else if (!strcmp(argv[a], "--pixels") && a + 1 < argc)
      pixels = atol(argv[++a]);
    else if (!strcmp(argv[a], "--models") && a + 1 < argc)
      models = argv[++a];
    else {
      fprintf(stderr, "usage: bench_shader [--quick] [--pixels N] [--models DIR] [--presets]\n");
      return 2;
    }
  }
  char msg[512];
  vkh *vk = NULL;
  if (vkh_open(&vk, msg, sizeof msg)) die("vulkan", msg);
  int cpu = vkh_device_is_cpu(vk);
  if (pixels <= 0) pixels = quick && cpu ? 2048 : 1920 * 1080;
  const size_t P = (size_t)pixels;
  const int reps = quick ? 2 : 5;
  printf("device: %s (%s); shared memory %u B, %u invocations, subgroup %u, "
         "VK_NV_cooperative_matrix fp16 16x16x16: %s\n",
         vkh_device_name(vk), cpu ? "CPU" : "GPU", vkh_max_shared(vk), vkh_max_invocations(vk),
         vkh_subgroup_size(vk), vkh_has_coop(vk) ? "yes" : "no");

  /* Decoders. */
  bench_row rows[8];
  int n_rows = 0;
  nbrdf_error err = {0};
  {
    model_decoder_config cfg;
    if (model_decoder_compact_config(8, 32, &cfg, &err) ||
        model_decoder_create(&cfg, 1, &rows[n_rows].dec, &err))
      die("compact", err.message);
    snprintf(rows[n_rows++].label, sizeof rows[0].label, "compact 8x32 (untrained)");
  }
  const char *trained[2] = {"medium", "default"};
  for (int m = 0; m < 2; m++) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s/decoder.safetensors", models, trained[m]);
    if (model_decoder_load(path, &rows[n_rows].dec, &err) != NBRDF_OK) {
      printf("(%s: %s; row skipped)\n", path, err.message);
      continue;
    }
    snprintf(rows[n_rows++].label, sizeof rows[0].label, "models/%s", trained[m]);
  }
  if (presets) {
    const char *names[3] = {"small", "medium", "large"};
    for (int p = 0; p < 3; p++) {
      model_decoder_config cfg;
      if (model_decoder_preset(names[p], 32, &cfg, &err) ||
          model_decoder_create(&cfg, 1, &rows[n_rows].dec, &err))
        die(names[p], err.message);
      snprintf(rows[n_rows++].label, sizeof rows[0].label, "preset %s (untrained)", names[p]);
    }
  }

  /* Queries, shared by every row: (u, v, lod), ωi, ωo. */
  vkh_buffer qb, rb;
  if (vkh_buffer_create(vk, P * 36, &qb) || vkh_buffer_create(vk, P * 16, &rb))
    die("buffers", vkh_error(vk));
  float *q = qb.map;
  unsigned seed = 12345u;
  for (size_t k = 0; k < P; k++) {
    float *c = q + 9 * k;
    c[0] = uni(&seed), c[1] = uni(&seed), c[2] = 4.0f * uni(&seed);
    for (int d = 0; d < 2; d++) {
      float z = 0.01f + 0.99f * uni(&seed), r = sqrtf(1.0f - z * z), phi = 6.2831853f * uni(&seed);
      c[3 + 3 * d] = r * cosf(phi), c[4 + 3 * d] = r * sinf(phi), c[5 + 3 * d] = z;
    }
  }
  /* The sample the errors are measured on. */
  size_t S = P < (quick ? 2048u : 16384u) ? P : (quick ? 2048u : 16384u);
  size_t *pix = malloc(sizeof(size_t) * S);
  for (size_t i = 0; i < S; i++)
    pix[i] = i * (P / S);

  printf("frame: %zu pixels%s; %d timed dispatches after a warm-up; errors on %zu pixels x 3 "
         "channels\n\n",
         P, P == 1920 * 1080 ? " (1920x1080)" : "", reps, S);
  printf("| decoder | MACs/decode | kernel | tile (rows x threads, shared B) | RGB frame ms | "
         "one channel ms | RGB TFLOP/s | max err f | median err f | max rel f (f>0.01) | "
         "median rel f | max log1p | median log1p |\n");
  printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  fflush(stdout);
  int timestamps = 1;
  for (int p = 0; p < n_rows; p++) {
    model_decoder *dec = rows[p].dec;
    int dim = dec->cfg.latent_dim;
    int64_t macs = model_decoder_macs(dec);
    size_t nw = 0;
    model_gpu_pack_decoder(dec, NULL, 0, &nw, &err);
    vkh_buffer wb, wb16, lrgb, lmono;
    if (vkh_buffer_create(vk, nw * 4, &wb)) die("buffer", vkh_error(vk));
    if (model_gpu_pack_decoder(dec, wb.map, nw, NULL, &err)) die(rows[p].label, err.message);
    const uint32_t *words = wb.map;
    /* the fp16 kernels' buffer: the words and the weights' fp16 copy (nbrdf_tiled.h) */
    if (vkh_buffer_create(vk, nbrdf_tile_f16_words(words, nw) * 4, &wb16))
      die("buffer", vkh_error(vk));
    nbrdf_tile_f16_pack(words, nw, wb16.map);
    texture_latent_image *rgb = make_texture(dim, 3, 777u + (unsigned)p);
    texture_latent_image *mono = make_texture(dim, 1, 999u + (unsigned)p);
    pack_texture(vk, rgb, 3, &lrgb);
    pack_texture(vk, mono, 1, &lmono);

    /* C reference on the sample. */
    float *lat = malloc(sizeof(float) * 3 * dim * S), *wi = malloc(12 * S), *wo = malloc(12 * S);
    float *ref = malloc(12 * S), *texel = malloc(sizeof(float) * rgb->channels);
    for (size_t i = 0; i < S; i++) {
      const float *c = q + 9 * pix[i];
      texture_latent_fetch(rgb, c[0], c[1], c[2], texel);
      for (int ch = 0; ch < 3; ch++)
        for (int k = 0; k < dim; k++)
          lat[(i * 3 + ch) * dim + k] = texel[texture_latent_index_latent(&rgb->layout, ch, k)];
      memcpy(wi + 3 * i, c + 3, 12);
      memcpy(wo + 3 * i, c + 6, 12);
    }
    model_runner runner;
    if (model_runner_create(dec->nn, 4096, NBRDF_NN_INFER, &runner, &err) ||
        model_decoder_eval(dec, &runner, S, 3, lat, wi, wo, ref, &err))
      die("C decoder", err.message);
    model_runner_destroy(&runner);

    const char *names[4] = {"nbrdf_shade.spv", "nbrdf_shade_tiled.spv", "nbrdf_shade_coop.spv",
                            "nbrdf_shade_coopemu.spv"};
    const char *labels[4] = {"per-invocation fp32", "tiled fp32", "tiled fp16 tensor cores",
                             "tiled fp16, matrix ops emulated (error only)"};
    for (int kind = 0; kind < 4; kind++) {
      /* The emulation (tests' kernel) only where the real one cannot run: its errors are
       * the fp16 kernel's, its times mean nothing. */
      if (kind == 3 && (vkh_has_coop(vk) || !vkh_has_f16(vk))) continue;
      char tile[96] = "64 x 1 invocation each";
      uint32_t spec[7] = {words[NBRDF_GPU_W_MAX_WIDTH]}, n_spec = 1, per_group = 64, tiled = 0;
      if (kind == 2 && !vkh_has_coop(vk)) {
        printf("| %s | %lld | %s | not run: no VK_NV_cooperative_matrix | | | | | | | | | |\n",
               rows[p].label, (long long)macs, labels[kind]);
        continue;
      }
      if (kind > 0) {
        nbrdf_tile_config cfg;
        if (nbrdf_tile_config_make(words, vkh_max_shared(vk), vkh_max_invocations(vk), kind >= 2,
                                   &cfg)) {
          printf("| %s | %lld | %s | no tile fits | | | | | | | | | |\n", rows[p].label,
                 (long long)macs, labels[kind]);
          continue;
        }
        memcpy(spec, cfg.spec, sizeof spec);
        n_spec = 7, per_group = cfg.rows, tiled = 1;
        snprintf(tile, sizeof tile, "%u x %u, %u B", cfg.rows, cfg.threads, cfg.shared_bytes);
      }
      vkh_kernel k;
      if (vkh_kernel_create(vk, names[kind], 4, 4, (int)n_spec, spec, &k)) {
        printf("| %s | %lld | %s | pipeline failed: %s | | | | | | | | | |\n", rows[p].label,
               (long long)macs, labels[kind], vkh_error(vk));
        continue;
      }
      double t[2] = {0, 0};
      errors e = {0, 0, 0, 0, 0, 0};
      int failed = 0;
      for (int tex = 0; tex < 2 && !failed; tex++) {
        int colours = tex == 0 ? 3 : 1;
        vkh_buffer *bind[4] = {kind >= 2 ? &wb16 : &wb, tex == 0 ? &lrgb : &lmono, &qb, &rb};
        vkh_kernel_bind(vk, &k, bind);
        uint32_t n = (uint32_t)P;
        uint64_t work = tiled ? (uint64_t)P * colours : P;
        uint32_t groups = (uint32_t)((work + per_group - 1) / per_group);
        memset(rb.map, 0xff, P * 16);
        int ts = 0;
        if (vkh_run(vk, &k, &n, groups, NULL) || /* warm-up; its result is compared */
            (tex == 0 && (e = compare(rb.map, ref, pix, S), 0)) ||
            vkh_time(vk, &k, &n, groups, reps, &t[tex], &ts)) {
          printf("| %s | %lld | %s | dispatch failed: %s | | | | | | | | | |\n", rows[p].label,
                 (long long)macs, labels[kind], vkh_error(vk));
          failed = 1;
        }
        if (!ts) timestamps = 0;
      }
      vkh_kernel_destroy(vk, &k);
      if (failed) continue;
      printf("| %s | %lld | %s | %s | %.3f | %.3f | %.3g | %.1e | %.1e | %.1e | %.1e | %.1e | "
             "%.1e |\n",
             rows[p].label, (long long)macs, labels[kind], tile, t[0] * 1e3, t[1] * 1e3,
             2.0 * (double)macs * 3.0 * (double)P / t[0] * 1e-12, e.max_f, e.med_f, e.max_rel,
             e.med_rel, e.max_l, e.med_l);
      fflush(stdout);
    }
    free(lat), free(wi), free(wo), free(ref), free(texel);
    texture_latent_image_free(rgb), texture_latent_image_free(mono);
    vkh_buffer_destroy(vk, &wb), vkh_buffer_destroy(vk, &wb16);
    vkh_buffer_destroy(vk, &lrgb), vkh_buffer_destroy(vk, &lmono);
    model_decoder_destroy(dec);
  }
  printf("\ntimes from %s\n", timestamps ? "GPU timestamps (vkCmdWriteTimestamp x timestampPeriod)"
                                         : "wall time of submit + wait (no timestamps)");
  free(pix);
  vkh_buffer_destroy(vk, &qb), vkh_buffer_destroy(vk, &rb);
  vkh_close(vk);
  return 0;
}
#else
int main(void) {
  puts("bench_shader: built without the shaders (NBRDF_BUILD_SHADERS=OFF)");
  return 0;
}
#endif
