/* Cost of nbrdf render: decoder queries per second inside the renderer
 * against the machine's cblas_sgemm rate (measured in the same run), and the
 * time of a 512 x 512 preview at 16 spp; the reference mode at a smaller
 * size for comparison. Prints a markdown table (docs/RENDER.md).
 *
 *   bench_render [--bundle DIR] [--decoder PRESET] [--size N] [--spp N] [--rgb]
 *
 * Without --bundle it makes an untrained bundle (decoder preset, default
 * medium): random networks cost exactly what trained ones of the same
 * shapes cost. The texture is a constant bake (mono, or RGB with --rgb). */
#include <cblas.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "model/bundle.h"
#include "nbrdf/bake.h"
#include "nbrdf/render.h"

#include "bench_clock.h"

static void die(nbrdf_status st, const nbrdf_error *err) {
  if (st == NBRDF_OK) return;
  fprintf(stderr, "bench_render: %s\n", err->message);
  exit(1);
}

/* GFLOP/s of cblas_sgemm for an m x k times k x n product (best of a few). */
static double sgemm_gflops(int m, int n, int k) {
  float *a = calloc((size_t)m * k, 4), *b = calloc((size_t)k * n, 4), *c = calloc((size_t)m * n, 4);
  for (size_t i = 0; i < (size_t)m * k; i++)
    a[i] = (float)(i % 7) * 0.1f;
  for (size_t i = 0; i < (size_t)k * n; i++)
    b[i] = (float)(i % 5) * 0.1f;
  double best = 0.0;
  for (int rep = 0; rep < 5; rep++) {
    int calls = 0;
    double t0 = bench_wall_seconds();
    do {
      cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, m, n, k, 1.0f, a, k, b, n, 0.0f, c, n);
      calls++;
    } while (bench_wall_seconds() - t0 < 0.2);
    double g = 2.0 * m * n * k * calls / (bench_wall_seconds() - t0) * 1e-9;
    if (g > best) best = g;
  }
  free(a), free(b), free(c);
  return best;
}

int main(int argc, char **argv) {
  const char *bundle = NULL, *preset = "medium";
  int size = 512, spp = 16, rgb = 0;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--bundle") && i + 1 < argc)
      bundle = argv[++i];
    else if (!strcmp(argv[i], "--decoder") && i + 1 < argc)
      preset = argv[++i];
    else if (!strcmp(argv[i], "--size") && i + 1 < argc)
      size = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--spp") && i + 1 < argc)
      spp = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--rgb"))
      rgb = 1;
    else {
      fprintf(stderr, "usage: bench_render [--bundle DIR] [--decoder PRESET] [--size N] [--spp N] "
                      "[--rgb]\n");
      return 2;
    }
  }
  nbrdf_error err;
  char dir[256], tex[300];
  snprintf(dir, sizeof dir, "/tmp/bench_render.%d", (int)getpid());
  if (!bundle) {
    die(model_bundle_init_random(dir, "bench", 1, preset, &err), &err);
    bundle = dir;
  }
  nbrdf_model *model = NULL;
  die(nbrdf_model_load(bundle, &model, &err), &err);
  snprintf(tex, sizeof tex, "/tmp/bench_render.%d.exr", (int)getpid());
  nbrdf_bake_inputs in = NBRDF_BAKE_INPUTS_DEFAULT;
  const float v[6] = {0.1f, 1.5f, 0.3f, 0.9f, 0.8f, 1.0f};
  for (int k = 0; k < NBRDF_BAKE_PARAM_COUNT; k++)
    nbrdf_bake_param_constant(&in.param[k], v[k]);
  if (rgb) {
    in.param[NBRDF_BAKE_R0].channels = 3;
    in.param[NBRDF_BAKE_R0].value[1] = 0.6f, in.param[NBRDF_BAKE_R0].value[2] = 0.3f;
  }
  die(nbrdf_bake(model, &in, NULL, tex, NULL, &err), &err);

  double g128 = sgemm_gflops(4096, 128, 128), g256 = sgemm_gflops(4096, 256, 256);
  double gemm = g128 > g256 ? g128 : g256;
  int64_t macs = nbrdf_model_decoder_macs(model);
  printf("bundle %s (%s, decoder %lld MACs/query), texture %s\n", bundle,
         nbrdf_model_is_trained(model) ? "trained" : "UNTRAINED", (long long)macs,
         rgb ? "RGB" : "mono");
  printf("cblas_sgemm: %.1f GFLOP/s (4096x128x128), %.1f GFLOP/s (4096x256x256)\n\n", g128, g256);
  printf("| mode | image | spp | tile threads | wall s | CPU s | decoder queries/s | GFLOP/s | "
         "of sgemm |\n|---|---|---|---|---|---|---|---|---|\n");
  float *img = malloc(sizeof(float) * 3 * (size_t)size * size);
  for (int threads = 1; threads <= 2; threads++) {
    nbrdf_render_options o = NBRDF_RENDER_OPTIONS_DEFAULT;
    o.width = o.height = size, o.spp = spp, o.threads = threads, o.light_intensity = 30.0;
    nbrdf_render_stats st;
    double t0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
    die(nbrdf_render(model, tex, &o, img, &st, &err), &err);
    double wall = bench_wall_seconds() - t0, cpu = bench_cpu_seconds() - c0;
    double qps = st.decoded / wall, gf = qps * (double)macs * 2e-9;
    printf("| neural | %dx%d | %d | %d | %.2f | %.2f | %.3g | %.1f | %.0f%% |\n", size, size, spp,
           threads, wall, cpu, qps, gf, 100.0 * gf / gemm);
    fflush(stdout);
  }
  /* The ground truth is orders slower: a quarter of the width, then scaled. */
  nbrdf_brdf *bottom = NULL, *layered = NULL;
  die(nbrdf_brdf_create_conductor(0.3, 0.9, &bottom, &err), &err);
  die(nbrdf_brdf_create_layered(0.1, 1.5, 0.8, 1.0, bottom, &layered, &err), &err);
  const nbrdf_brdf *ref[3] = {layered, layered, layered};
  nbrdf_render_options o = NBRDF_RENDER_OPTIONS_DEFAULT;
  o.mode = NBRDF_RENDER_REFERENCE, o.reference = ref, o.reference_channels = rgb ? 3 : 1;
  o.width = o.height = size / 4, o.spp = spp, o.light_intensity = 30.0;
  nbrdf_render_stats st;
  double t0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  die(nbrdf_render(model, tex, &o, img, &st, &err), &err);
  double wall = bench_wall_seconds() - t0, cpu = bench_cpu_seconds() - c0;
  printf("| reference | %dx%d | %d | all | %.2f | %.2f | (%.3g ground-truth evals/s) | | |\n",
         size / 4, size / 4, spp, wall, cpu, st.brdf_evals / wall);
  free(img);
  nbrdf_brdf_destroy(layered), nbrdf_brdf_destroy(bottom);
  nbrdf_model_destroy(model);
  remove(tex);
  return 0;
}
