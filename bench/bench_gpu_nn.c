/* The networks' forward pass on a GPU (src/gpu, Vulkan compute) vs the CPU (issue 34):
 * rows/s and achieved TFLOP/s (2 x MACs x rows/s) of the bundle's layering network, decoder
 * and sampler over N rows (host memory to host memory, chunks streamed), fp32 and, where the
 * device has VK_NV_cooperative_matrix, the fp16 tensor-core path; the largest and median
 * difference from the CPU (nn_forward on OpenBLAS) on a sample of rows; the CPU's own rate on
 * that sample and its cblas_sgemm rate in the same run (METRICS.md). Markdown output.
 *
 *   NBRDF_VK_DEVICE=NVIDIA ./bench/bench_gpu_nn [--rows 1048576] [--sample 4096] [--reps 3]
 *                                               [--bundle DIR]
 * Links OpenBLAS, cJSON and libnbrdf's network/model objects only (no OpenImageIO): with
 * Debian's libvulkan1 it runs on a bare GPU machine (docs/GPU.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_args.h"
#include "bench_clock.h"
#include "bench_sgemm.h"
#include "core/rng.h"
#include "gpu/gpu.h"
#include "model/bundle.h"
#include "nbrdf/model.h"

static void usage(FILE *f) {
  fprintf(f, "usage: bench_gpu_nn [--rows N] [--sample S] [--reps R] [--bundle DIR] [--gemm-tile 128x128]\n"
             "  NBRDF_VK_DEVICE=<substring of the device name> picks the device (llvmpipe:\n"
             "  lavapipe); without it the first GPU.\n");
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

typedef struct result {
  double rows_per_s, tflops, max_err, median_rel;
  double kernel_tflops; /* from GPU timestamps around the layers; < 0: none */
} result;

/* Max |g - c| / max(|c|, 1) and the median |g - c| / |c| over the sample. */
static void differences(const float *g, const float *c, size_t n, double *max_err,
                        double *median) {
  double *rel = malloc(sizeof *rel * n), worst = 0.0;
  for (size_t k = 0; k < n; k++) {
    double d = fabs((double)g[k] - c[k]);
    if (!(d / fmax(fabs((double)c[k]), 1.0) <= worst)) worst = d / fmax(fabs((double)c[k]), 1.0);
    rel[k] = d / fmax(fabs((double)c[k]), 1e-12);
  }
  qsort(rel, n, sizeof *rel, cmp_double);
  *max_err = worst;
  *median = rel[n / 2];
  free(rel);
}

static int run_gpu(gpu_context *ctx, const nn_network *nn, gpu_precision prec, const float *x,
                   size_t rows, int reps, const float *ref, size_t sample, result *r) {
  nbrdf_error err;
  gpu_network *g = NULL;
  if (gpu_network_create(ctx, nn, prec, 0, &g, &err) != NBRDF_OK) {
    fprintf(stderr, "bench_gpu_nn: %s\n", err.message);
    return -1;
  }
  const size_t out = (size_t)nn_outputs(nn);
  float *y = malloc(sizeof(float) * rows * out);
  size_t warm = rows < (size_t)gpu_network_chunk_rows(g) ? rows : (size_t)gpu_network_chunk_rows(g);
  int ok = y && gpu_network_forward(g, x, warm, y, &err) == NBRDF_OK;
  double best = 1e30, best_device = -1.0;
  for (int k = 0; ok && k < reps; k++) {
    double t0 = bench_wall_seconds();
    ok = gpu_network_forward(g, x, rows, y, &err) == NBRDF_OK;
    double t = bench_wall_seconds() - t0;
    if (t < best) best = t;
    double d = gpu_network_device_seconds(g);
    if (d > 0.0 && (best_device < 0.0 || d < best_device)) best_device = d;
  }
  if (!ok) fprintf(stderr, "bench_gpu_nn: %s\n", err.message);
  if (ok) {
    r->rows_per_s = (double)rows / best;
    r->tflops = 2.0 * (double)nn_spec_macs(nn_get_spec(nn)) * r->rows_per_s * 1e-12;
    r->kernel_tflops = best_device > 0.0 ? 2.0 * (double)nn_spec_macs(nn_get_spec(nn)) *
                                               (double)rows / best_device * 1e-12
                                         : -1.0;
    differences(y, ref, sample * out, &r->max_err, &r->median_rel);
  }
  free(y);
  gpu_network_destroy(g);
  return ok ? 0 : -1;
}

static void bench_network(gpu_context *ctx, const char *name, const nn_network *nn, size_t rows,
                          size_t sample, int reps) {
  const size_t in = (size_t)nn_inputs(nn), out = (size_t)nn_outputs(nn);
  float *x = malloc(sizeof(float) * rows * in), *ref = malloc(sizeof(float) * sample * out);
  if (!x || !ref) {
    fprintf(stderr, "bench_gpu_nn: out of memory for %zu rows\n", rows);
    exit(1);
  }
  core_rng rng;
  core_rng_init(&rng, 34, in);
  for (size_t k = 0; k < rows * in; k++)
    x[k] = (float)(2.0 * core_rng_uniform(&rng) - 1.0);
  nn_workspace *ws = NULL;
  nbrdf_error err;
  if (nn_workspace_create(nn, 4096, NBRDF_NN_INFER, &ws, &err) != NBRDF_OK) exit(1);
  double t0 = bench_wall_seconds();
  nn_forward(nn, ws, x, (int)sample, ref, &err);
  double cpu_rate = (double)sample / (bench_wall_seconds() - t0);
  nn_workspace_destroy(ws);
  const long long macs = (long long)nn_spec_macs(nn_get_spec(nn));
  printf("| %s | %lld | CPU (OpenBLAS) | %zu | %.3g | %.3g | | 0 | 0 |\n", name, macs, sample,
         cpu_rate, 2.0 * (double)macs * cpu_rate * 1e-12);
  result r;
  if (run_gpu(ctx, nn, GPU_FP32, x, rows, reps, ref, sample, &r) == 0)
    printf("| %s | %lld | GPU fp32 | %zu | %.3g | %.3g | %.3g | %.2e | %.2e |\n", name, macs,
           rows, r.rows_per_s, r.tflops, r.kernel_tflops, r.max_err, r.median_rel);
  if (gpu_context_limits(ctx)->coop_matrix &&
      run_gpu(ctx, nn, GPU_FP16_COOP, x, rows, reps, ref, sample, &r) == 0)
    printf("| %s | %lld | GPU fp16 tensor cores | %zu | %.3g | %.3g | %.3g | %.2e | %.2e |\n",
           name, macs, rows, r.rows_per_s, r.tflops, r.kernel_tflops, r.max_err, r.median_rel);
  fflush(stdout);
  free(x);
  free(ref);
}

int main(int argc, char **argv) {
  long rows = 1048576, sample = 4096, reps = 3;
  const char *bundle = NULL;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = bench_option_value(argc, argv, &i, "bench_gpu_nn", usage);
    if (!v) return 2;
    if (!strcmp(a, "--rows")) rows = strtol(v, NULL, 10);
    else if (!strcmp(a, "--sample")) sample = strtol(v, NULL, 10);
    else if (!strcmp(a, "--reps")) reps = strtol(v, NULL, 10);
    else if (!strcmp(a, "--bundle")) bundle = v;
    else if (!strcmp(a, "--gemm-tile")) setenv("NBRDF_GPU_GEMM_TILE", v, 1);
    else {
      usage(stderr);
      return 2;
    }
  }
  if (rows < 1 || sample < 1 || reps < 1) {
    usage(stderr);
    return 2;
  }
  if (sample > rows) sample = rows;
  nbrdf_error err;
  nbrdf_model *m = NULL;
  char used[4096];
  if ((bundle ? nbrdf_model_load(bundle, &m, &err)
              : nbrdf_model_load_default(&m, used, sizeof used, &err)) != NBRDF_OK) {
    fprintf(stderr, "bench_gpu_nn: %s\n", err.message);
    return 1;
  }
  gpu_context *ctx = NULL;
  if (gpu_context_open(GPU_CHOICE_GPU, &ctx, &err) != NBRDF_OK) {
    fprintf(stderr, "bench_gpu_nn: %s\n", err.message);
    return 1;
  }
  const gpu_limits *l = gpu_context_limits(ctx);
  printf("device: %s%s; shared memory %u bytes, device memory %.1f GiB; cooperative matrix "
         "(fp16 16x16x16, tensor cores): %s\n",
         gpu_context_name(ctx), gpu_context_is_cpu(ctx) ? " (CPU)" : "", l->shared_bytes,
         (double)l->device_bytes / (1 << 30), l->coop_note);
  printf("cblas_sgemm 4096x256x256: %.1f GFLOP/s (same run, CPU)\n\n",
         bench_sgemm_gflops(4096, 256, 256, 1.0, 0));
  printf("| network | MACs/row | path | rows | rows/s | TFLOP/s | kernels TFLOP/s | max err vs CPU "
         "| median rel err |\n|---|---|---|---|---|---|---|---|---|\n");
  bench_network(ctx, "layering", m->layering->nn, (size_t)rows, (size_t)sample, (int)reps);
  bench_network(ctx, "decoder", m->decoder->nn, (size_t)rows, (size_t)sample, (int)reps);
  bench_network(ctx, "sampler", m->sampler->nn, (size_t)rows, (size_t)sample, (int)reps);
  printf("\nmax err = max |gpu - cpu| / max(|cpu|, 1) over the first %ld rows' outputs; rows/s "
         "and TFLOP/s host to host (uploads and readback included), best of %ld; kernels "
         "TFLOP/s from GPU timestamps around the layers (-1: no timestamps).\n",
         sample, reps);
  gpu_context_close(ctx);
  nbrdf_model_destroy(m);
  return 0;
}
