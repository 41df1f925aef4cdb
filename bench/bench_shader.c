/* Decoder throughput of the GLSL shader (shaders/nbrdf_decode.comp) on a Vulkan device,
 * beside the C decoder (nbrdf_model_decode's path, model_decoder_eval) and the machine's
 * cblas_sgemm rate, all in the same run. Prints a markdown table (docs/SHADERS.md).
 *
 *   bench_shader            presets small, medium, large, paper; a 1920x1080 frame of one
 *                           query per pixel measured for small, extrapolated from
 *                           queries/s for the others
 *   bench_shader --quick    fewer queries, no frame
 *   bench_shader --frames   measure a whole frame for every decoder (on a GPU)
 *   bench_shader --decoder models/default/decoder.safetensors   adds a trained decoder
 * Rows: the compact decoders of `nbrdf bake --compact 4` and `--compact 8` (width 32), then
 * the presets, all untrained (the cost does not depend on the weights).
 *   NBRDF_VK_DEVICE=NVIDIA bench_shader    the same on a GPU (tests/shaders/vk_harness.h)
 *
 * Device times are the wall time of submit + wait of one dispatch (buffers already
 * filled, pipeline compiled by a warm-up dispatch), the fastest of 3. */
#include <cblas.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_clock.h"

#ifdef NBRDF_HAVE_VULKAN
#include "model/decoder.h"
#include "model/gpu_pack.h"
#include "vk_harness.h"

#define FRAME_QUERIES (1920u * 1080u)

static void die(const char *what, const char *msg) {
  fprintf(stderr, "bench_shader: %s: %s\n", what, msg);
  exit(1);
}

/* GFLOP/s of cblas_sgemm at 4096 x w x w (the decoder's hidden shape), best of 3. */
static double sgemm_gflops(int w) {
  int m = 4096;
  float *a = calloc((size_t)m * w, 4), *b = calloc((size_t)w * w, 4), *c = calloc((size_t)m * w, 4);
  double best = 1e30;
  for (int r = 0; r < 3; r++) {
    double t0 = bench_wall_seconds();
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasTrans, m, w, w, 1.0f, a, w, b, w, 0.0f, c, w);
    double t = bench_wall_seconds() - t0;
    if (t < best) best = t;
  }
  free(a), free(b), free(c);
  return 2.0 * m * w * (double)w / best * 1e-9;
}

typedef struct gpu_run {
  vkh_buffer wb, qb, ob;
  vkh_kernel k;
  uint32_t n;
} gpu_run;

static void gpu_setup(vkh *vk, const uint32_t *words, size_t nw, const float *q, size_t n, int dim,
                      gpu_run *g) {
  uint32_t spec[1] = {words[NBRDF_GPU_W_MAX_WIDTH]};
  if (vkh_buffer_create(vk, nw * 4, &g->wb) || vkh_buffer_create(vk, n * (6 + dim) * 4, &g->qb) ||
      vkh_buffer_create(vk, n * 8, &g->ob) ||
      vkh_kernel_create(vk, "nbrdf_decode.spv", 3, 4, 1, spec, &g->k))
    die("vulkan", vkh_error(vk));
  memcpy(g->wb.map, words, nw * 4);
  memcpy(g->qb.map, q, n * (6 + dim) * 4);
  vkh_buffer *bind[3] = {&g->wb, &g->qb, &g->ob};
  vkh_kernel_bind(vk, &g->k, bind);
  g->n = (uint32_t)n;
}

/* Fastest wall time of `rounds` dispatches; *cpu gets the process CPU seconds of that
 * dispatch (lavapipe's worker threads are in this process). */
static double gpu_time(vkh *vk, gpu_run *g, int rounds, double *cpu) {
  double best = 1e30;
  for (int r = 0; r < rounds; r++) {
    double t, c0 = bench_cpu_seconds();
    if (vkh_run(vk, &g->k, &g->n, (g->n + 63) / 64, &t)) die("dispatch", vkh_error(vk));
    if (t < best) best = t, *cpu = bench_cpu_seconds() - c0;
  }
  return best;
}

static void gpu_free(vkh *vk, gpu_run *g) {
  vkh_kernel_destroy(vk, &g->k);
  vkh_buffer_destroy(vk, &g->wb);
  vkh_buffer_destroy(vk, &g->qb);
  vkh_buffer_destroy(vk, &g->ob);
}

/* Random queries: directions on the hemisphere, latents in [-1.5, 1.5]. */
static float *make_queries(size_t n, int dim, float **wi, float **wo, float **lat) {
  float *q = malloc(n * (6 + dim) * 4);
  *wi = malloc(n * 12), *wo = malloc(n * 12), *lat = malloc(n * dim * 4);
  unsigned s = 12345u;
  for (size_t k = 0; k < n; k++) {
    float *row = q + k * (6 + dim);
    for (int d = 0; d < 2; d++) {
      s = s * 1664525u + 1013904223u;
      float z = 0.01f + 0.99f * (float)(s >> 8) / 16777216.0f, r = sqrtf(1.0f - z * z);
      s = s * 1664525u + 1013904223u;
      float phi = 6.2831853f * (float)(s >> 8) / 16777216.0f;
      float v[3] = {r * cosf(phi), r * sinf(phi), z};
      memcpy(row + 3 * d, v, 12);
      memcpy((d ? *wo : *wi) + 3 * k, v, 12);
    }
    for (int i = 0; i < dim; i++) {
      s = s * 1664525u + 1013904223u;
      row[6 + i] = 3.0f * (float)(s >> 8) / 16777216.0f - 1.5f;
      (*lat)[k * dim + i] = row[6 + i];
    }
  }
  return q;
}

/* One row of the table: a preset (untrained), a compact decoder (`nbrdf bake --compact K`'s
 * architecture, untrained) or a trained decoder file. */
typedef struct bench_row {
  const char *label, *preset, *file;
  int compact_dim, compact_width;
  size_t queries;
} bench_row;

static model_decoder *row_decoder(const bench_row *r) {
  nbrdf_error err = {0};
  model_decoder_config cfg;
  model_decoder *dec = NULL;
  nbrdf_status st;
  if (r->file)
    st = model_decoder_load(r->file, &dec, &err);
  else {
    st = r->preset ? model_decoder_preset(r->preset, 32, &cfg, &err)
                   : model_decoder_compact_config(r->compact_dim, r->compact_width, &cfg, &err);
    if (st == NBRDF_OK) st = model_decoder_create(&cfg, 1, &dec, &err);
  }
  if (st != NBRDF_OK) die(r->label, err.message);
  return dec;
}

int main(int argc, char **argv) {
  int quick = 0, all_frames = 0;
  const char *file = NULL;
  for (int a = 1; a < argc; a++) {
    if (!strcmp(argv[a], "--quick"))
      quick = 1;
    else if (!strcmp(argv[a], "--frames"))
      all_frames = 1;
    else if (!strcmp(argv[a], "--decoder") && a + 1 < argc)
      file = argv[++a];
    else {
      fprintf(stderr, "usage: bench_shader [--quick] [--frames] [--decoder FILE.safetensors]\n");
      return 2;
    }
  }
  char msg[512];
  vkh *vk = NULL;
  if (vkh_open(&vk, msg, sizeof msg)) die("vulkan", msg);
  bench_row rows[] = {
      {"compact 4x32", NULL, NULL, 4, 32, 262144},
      {"compact 8x32", NULL, NULL, 8, 32, 262144},
      {"small", "small", NULL, 0, 0, 262144},
      {"medium", "medium", NULL, 0, 0, 65536},
      {"large", "large", NULL, 0, 0, 16384},
      {"paper", "paper", NULL, 0, 0, 2048},
      {file, NULL, file, 0, 0, 65536},
  };
  int n_rows = file ? 7 : 6;
  printf("device: %s (%s)\n", vkh_device_name(vk), vkh_device_is_cpu(vk) ? "CPU" : "GPU");
  double cpu0 = bench_cpu_seconds(), w0 = bench_wall_seconds();
  double gf = sgemm_gflops(256);
  printf("cblas_sgemm 4096x256x256: %.1f GFLOP/s (same run; CPU/wall %.2f)\n\n", gf,
         (bench_cpu_seconds() - cpu0) / (bench_wall_seconds() - w0));
  /* CPU seconds beside wall seconds: on a shared machine only the former are stable. */
  printf("| decoder | MACs/query | queries | shader q/s | shader q/CPU-s | shader GFLOP/s | "
         "C q/s | C q/CPU-s | shader/C (CPU-s) | 1920x1080 frame (shader) | max log1p diff |\n");
  printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int p = 0; p < n_rows; p++) {
    nbrdf_error err = {0};
    model_decoder *dec = row_decoder(&rows[p]);
    const int dim = dec->cfg.latent_dim;
    size_t nw = 0;
    model_gpu_pack_decoder(dec, NULL, 0, &nw, &err);
    uint32_t *words = malloc(nw * 4);
    if (model_gpu_pack_decoder(dec, words, nw, NULL, &err) != NBRDF_OK) die(rows[p].label, err.message);
    size_t n = quick ? rows[p].queries / 8 : rows[p].queries;
    float *wi, *wo, *lat;
    float *q = make_queries(n, dim, &wi, &wo, &lat);
    int64_t macs = model_decoder_macs(dec);

    model_runner runner;
    float *f = malloc(n * 4);
    if (model_runner_create(dec->nn, 4096, NBRDF_NN_INFER, &runner, &err) != NBRDF_OK)
      die("runner", err.message);
    double cg = 0, cc = 0, cf = 0, tc = 1e30;
    for (int r = 0; r < 3; r++) {
      double t0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
      model_decoder_eval(dec, &runner, n, 1, lat, wi, wo, f, &err);
      double t = bench_wall_seconds() - t0;
      if (t < tc) tc = t, cc = bench_cpu_seconds() - c0;
    }
    model_runner_destroy(&runner);

    gpu_run g;
    gpu_setup(vk, words, nw, q, n, dim, &g);
    gpu_time(vk, &g, 1, &cg); /* warm-up: first dispatch after pipeline creation */
    double tg = gpu_time(vk, &g, 3, &cg);
    /* The timing is only worth printing if the device computed the same function: the
     * largest |log(1 + f_shader) - log(1 + f_C)| over the queries (tests/shaders holds the
     * tolerances; this is the bench's own guard on a device the tests did not run on). */
    double agree = 0;
    const float *fg = g.ob.map;
    for (size_t k = 0; k < n; k++) {
      double d = fabs(log1p(fmax(fg[2 * k], 0.0)) - log1p(fmax(f[k], 0.0f)));
      if (!(d <= agree)) agree = d; /* NaN propagates */
    }
    gpu_free(vk, &g);

    double qs = (double)n / tg, qc = (double)n / tc;
    char frame[64];
    /* A whole frame is measured for `small` and, with --frames (meant for a GPU), every row;
     * on lavapipe the big presets' frames would take an hour. */
    if (!quick && (all_frames || (rows[p].preset && !strcmp(rows[p].preset, "small")))) {
      float *wf, *of, *lf;
      float *qf = make_queries(FRAME_QUERIES, dim, &wf, &of, &lf);
      gpu_setup(vk, words, nw, qf, FRAME_QUERIES, dim, &g);
      gpu_time(vk, &g, 1, &cf);
      double tf = gpu_time(vk, &g, all_frames ? 3 : 1, &cf);
      gpu_free(vk, &g);
      snprintf(frame, sizeof frame, "%.1f ms (measured; %.1f CPU-s)", tf * 1e3, cf);
      free(qf), free(wf), free(of), free(lf);
    } else {
      snprintf(frame, sizeof frame, "%.0f ms (from queries/s)", FRAME_QUERIES / qs * 1e3);
    }
    printf("| %s | %lld | %zu | %.3g | %.3g | %.2f | %.3g | %.3g | %.2f | %s | %.1e |\n",
           rows[p].label, (long long)macs, n, qs, n / cg, 2.0 * (double)macs * qs * 1e-9, qc,
           n / cc, (n / cg) / (n / cc), frame, agree);
    fflush(stdout);
    free(q), free(wi), free(wo), free(lat), free(f), free(words);
    model_decoder_destroy(dec);
  }
  vkh_close(vk);
  return 0;
}
#else
int main(void) {
  puts("bench_shader: built without the shaders (NBRDF_BUILD_SHADERS=OFF)");
  return 0;
}
#endif
