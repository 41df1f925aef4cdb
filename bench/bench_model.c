/* Cost of the model layer on top of the networks: the public calls of
 * include/nbrdf/model.h (argument checks, direction encoding, scratch
 * buffers allocated per call) against the bare network forward on prepared
 * inputs, and against the machine's cblas_sgemm rate on the decoder's own
 * largest GEMM shape, all measured in the same run. Prints markdown tables.
 *
 *   bench_model            decoder presets x batches 1, 64, 4096, 65536; layering; sampler;
 *                          projection of 64 BRDFs
 *   bench_model --quick    batches 64 and 4096 only, fewer projection steps */
#include <cblas.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/rng.h"
#include "model/bundle.h"

#include "bench_clock.h"
#include "bench_sgemm.h"

static void die(nbrdf_status st, const nbrdf_error *err) {
  if (st == NBRDF_OK) return;
  fprintf(stderr, "bench_model: %s\n", err->message);
  exit(1);
}

typedef struct job {
  const nbrdf_model *m;
  size_t n;
  int channels;
  float *lat, *wi, *wo, *f, *x;
  model_runner *runner;
} job;

static void decode_public(job *j) {
  nbrdf_error err;
  die(nbrdf_model_decode(j->m, j->n, j->channels, j->lat, j->wi, j->wo, j->f, &err), &err);
}

static void decode_bare(job *j) {
  nbrdf_error err;
  size_t rows = j->n * (size_t)j->channels, in = (size_t)model_decoder_inputs(j->m->decoder);
  for (size_t r0 = 0; r0 < rows; r0 += (size_t)j->runner->max_batch) {
    size_t m = rows - r0 < (size_t)j->runner->max_batch ? rows - r0 : (size_t)j->runner->max_batch;
    die(nn_forward(j->m->decoder->nn, j->runner->ws, j->x + r0 * in, (int)m, j->f + r0, &err),
        &err);
  }
}

/* Seconds per call, repeated for at least min_s. */
static double seconds(void (*fn)(job *), job *j, double min_s) {
  fn(j);
  int n = 0;
  double t0 = bench_wall_seconds();
  do {
    fn(j);
    n++;
  } while (bench_wall_seconds() - t0 < min_s);
  return (bench_wall_seconds() - t0) / n;
}

static void bench_decoders(const char *tmp, int quick) {
  static const size_t all[] = {1, 64, 4096, 65536}, few[] = {64, 4096};
  const size_t *batches = quick ? few : all;
  int nb = quick ? 2 : 4;
  printf("## Decoder: public nbrdf_model_decode vs bare network forward\n\n"
         "| preset | MACs/query | batch | public queries/s | bare rows/s | public/bare | GFLOP/s | "
         "sgemm GFLOP/s |\n|---|---|---|---|---|---|---|---|\n");
  for (int p = 0; model_decoder_presets[p]; p++) {
    char dir[1024];
    nbrdf_error err;
    snprintf(dir, sizeof dir, "%s/%s", tmp, model_decoder_presets[p]);
    die(model_bundle_init_random(dir, model_decoder_presets[p], 1, model_decoder_presets[p], &err),
        &err);
    nbrdf_model *m = NULL;
    die(nbrdf_model_load(dir, &m, &err), &err);
    const nn_spec *spec = nn_get_spec(m->decoder->nn);
    int width = spec->layers[0].width;
    double peak = bench_sgemm_gflops(4096, width, width, 0.5, 0);
    int64_t macs = nbrdf_model_decoder_macs(m);
    for (int b = 0; b < nb; b++) {
      size_t n = batches[b], in = (size_t)model_decoder_inputs(m->decoder);
      job j = {m, n, 1, NULL, NULL, NULL, NULL, NULL, NULL};
      j.lat = malloc(n * 32 * sizeof(float));
      j.wi = malloc(n * 3 * sizeof(float)), j.wo = malloc(n * 3 * sizeof(float));
      j.f = malloc(n * sizeof(float)), j.x = malloc(n * in * sizeof(float));
      core_rng rng;
      core_rng_init(&rng, 1, 0);
      for (size_t i = 0; i < n * 32; i++)
        j.lat[i] = (float)core_rng_normal(&rng);
      for (size_t k = 0; k < 2 * n; k++) {
        double z = 0.1 + 0.9 * core_rng_uniform(&rng), r = sqrt(1 - z * z),
               phi = 6.283 * core_rng_uniform(&rng);
        float *w = k < n ? j.wi + 3 * k : j.wo + 3 * (k - n);
        w[0] = (float)(r * cos(phi)), w[1] = (float)(r * sin(phi)), w[2] = (float)z;
      }
      model_decoder_fill_inputs(m->decoder, n, 1, j.lat, j.wi, j.wo, j.x);
      model_runner runner;
      die(model_runner_create(m->decoder->nn, n < 4096 ? (int)n : 4096, NBRDF_NN_INFER, &runner,
                              &err),
          &err);
      j.runner = &runner;
      double tp = seconds(decode_public, &j, 0.3), tb = seconds(decode_bare, &j, 0.3);
      printf("| %s | %lld | %zu | %.3g | %.3g | %.2f | %.1f | %.1f |\n", model_decoder_presets[p],
             (long long)macs, n, n / tp, n / tb, tb / tp, 2.0 * macs * n / tp * 1e-9, peak);
      model_runner_destroy(&runner);
      free(j.lat), free(j.wi), free(j.wo), free(j.f), free(j.x);
    }
    nbrdf_model_destroy(m);
  }
  printf("\n");
}

static void bench_layering_sampler_projection(const char *tmp, int quick) {
  char dir[1024];
  nbrdf_error err;
  snprintf(dir, sizeof dir, "%s/medium", tmp);
  nbrdf_model *m = NULL;
  die(nbrdf_model_load(dir, &m, &err), &err);
  enum { N = 4096 };
  static float top[N * 32], bottom[N * 32], out[N * 32], a[N], s[N], sg[N], w[N];
  core_rng rng;
  core_rng_init(&rng, 2, 0);
  for (int i = 0; i < N * 32; i++)
    top[i] = (float)core_rng_normal(&rng), bottom[i] = (float)core_rng_normal(&rng);
  for (int k = 0; k < N; k++)
    a[k] = 0.5f, s[k] = 2.0f;
  die(nbrdf_model_layer(m, N, top, bottom, a, s, out, &err), &err);
  double t0 = bench_wall_seconds();
  int reps = 0;
  do {
    die(nbrdf_model_layer(m, N, top, bottom, a, s, out, &err), &err);
    reps++;
  } while (bench_wall_seconds() - t0 < 0.5);
  double tl = (bench_wall_seconds() - t0) / reps;
  t0 = bench_wall_seconds(), reps = 0;
  do {
    die(nbrdf_model_proxy_params(m, N, out, sg, w, &err), &err);
    reps++;
  } while (bench_wall_seconds() - t0 < 0.3);
  double ts = (bench_wall_seconds() - t0) / reps;
  int64_t lmacs = nbrdf_model_layering_macs(m);
  printf("## Layering and sampling networks (batch %d)\n\n| network | MACs | evaluations/s | "
         "GFLOP/s | "
         "sgemm GFLOP/s (4096x512x512) |\n|---|---|---|---|---|\n",
         N);
  printf("| layering | %lld | %.3g | %.1f | %.1f |\n", (long long)lmacs, N / tl,
         2.0 * lmacs * N / tl * 1e-9, bench_sgemm_gflops(4096, 512, 512, 0.5, 0));
  printf("| sampler | %lld | %.3g | %.1f | |\n\n",
         (long long)nn_spec_macs(nn_get_spec(m->sampler->nn)), N / ts,
         2.0 * nn_spec_macs(nn_get_spec(m->sampler->nn)) * N / ts * 1e-9);

  /* Projection: 64 BRDFs x 1024 samples, decoder "medium". */
  enum { NB = 64, PER = 1024 };
  float *wi = malloc(sizeof(float) * NB * PER * 3), *wo = malloc(sizeof(float) * NB * PER * 3);
  float *f = malloc(sizeof(float) * NB * PER), z[NB * 32];
  size_t offsets[NB + 1];
  for (int b = 0; b <= NB; b++)
    offsets[b] = (size_t)b * PER;
  for (size_t k = 0; k < 2 * (size_t)NB * PER; k++) {
    double zz = 0.1 + 0.9 * core_rng_uniform(&rng), r = sqrt(1 - zz * zz),
           phi = 6.283 * core_rng_uniform(&rng);
    float *v = k < (size_t)NB * PER ? wi + 3 * k : wo + 3 * (k - (size_t)NB * PER);
    v[0] = (float)(r * cos(phi)), v[1] = (float)(r * sin(phi)), v[2] = (float)zz;
  }
  for (size_t k = 0; k < (size_t)NB * PER; k++)
    f[k] = (float)(0.5 + core_rng_uniform(&rng));
  nbrdf_project_options po = NBRDF_PROJECT_OPTIONS_DEFAULT;
  po.steps = quick ? 100 : 500;
  t0 = bench_wall_seconds();
  die(nbrdf_model_project(m, NB, offsets, wi, wo, f, &po, z, NULL, &err), &err);
  double tp = bench_wall_seconds() - t0;
  printf("## Projection (decoder medium, %d BRDFs x %d samples, %d steps x %d rows per BRDF)\n\n"
         "%.2f s in all, %.1f ms per BRDF, %.3g rows/s forward+backward\n\n",
         NB, PER, po.steps, po.rows_per_brdf, tp, 1e3 * tp / NB,
         (double)NB * po.rows_per_brdf * po.steps / tp);
  free(wi), free(wo), free(f);
  nbrdf_model_destroy(m);
}

int main(int argc, char **argv) {
  int quick = argc > 1 && !strcmp(argv[1], "--quick");
  char tmp[] = "/tmp/bench-model-XXXXXX";
  if (!mkdtemp(tmp)) return 1;
  bench_decoders(tmp, quick);
  bench_layering_sampler_projection(tmp, quick);
  char cmd[256];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
  return system(cmd) == 0 ? 0 : 1;
}
