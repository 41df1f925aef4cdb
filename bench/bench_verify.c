/* Cost of `nbrdf verify` (docs/VERIFY.md): decoder queries per second on
 * verify's own path (src/verify/verify_decode.c: 12,912 lobe queries per
 * distinct latent), against the machine's cblas_sgemm rate on the decoder's
 * width measured in the same run; and the ground truth's cost per reference
 * (2 runs x 4 images x walks). CPU seconds are the figures to quote on a
 * shared machine; wall seconds are printed beside them.
 *
 *   bench_verify [--bundle DIR] [--latents N] [--walks W] [--threads T] */
#include <cblas.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_clock.h"
#include "bench_sgemm.h"
#include "core/rng.h"
#include "verify/verify_internal.h"
#include "model/bundle.h"

int main(int argc, char **argv) {
  const char *bundle = NULL;
  int latents = 32, walks = 256, threads = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--bundle"))
      bundle = argv[i + 1];
    else if (!strcmp(argv[i], "--latents"))
      latents = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--walks"))
      walks = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--threads"))
      threads = atoi(argv[i + 1]);
  }
  nbrdf_error err = {0};
  char dir[] = "/tmp/bench_verify_XXXXXX";
  if (!bundle) {
    if (!mkdtemp(dir) || model_bundle_init_random(dir, "bench", 1, "small", &err) != NBRDF_OK) {
      fprintf(stderr, "bench_verify: %s\n", err.message);
      return 1;
    }
    bundle = dir;
  }
  nbrdf_model *model = NULL;
  if (nbrdf_model_load(bundle, &model, &err) != NBRDF_OK) {
    fprintf(stderr, "bench_verify: %s\n", err.message);
    return 1;
  }
  const int D = nbrdf_model_latent_dim(model);
  verify_decoder *dec = verify_decoder_create(model);
  float *lat = malloc(sizeof(float) * D);
  double *img = malloc(sizeof(double) * VERIFY_SET);
  core_rng rng;
  core_rng_init(&rng, 7, 0);
  double w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  for (int n = 0; n < latents; n++) {
    for (int k = 0; k < D; k++)
      lat[k] = (float)core_rng_normal(&rng);
    int finite;
    if (verify_decode(dec, lat, img, &finite, &err) != NBRDF_OK) {
      fprintf(stderr, "bench_verify: %s\n", err.message);
      return 1;
    }
  }
  double dw = bench_wall_seconds() - w0, dc = bench_cpu_seconds() - c0;
  size_t q = verify_decoder_queries(dec);
  double macs = (double)q * (double)nbrdf_model_decoder_macs(model);
  double sg = bench_sgemm_gflops(16384, 32, 32, 1.0, 1);

  verify_refs *refs = verify_refs_create(walks, 1, threads);
  verify_tuple t = {{0.3f, 1.5f, 0.2f, 0.7f, 0.8f, 1.0f}};
  const double *a, *b;
  size_t clamped = 0;
  w0 = bench_wall_seconds(), c0 = bench_cpu_seconds();
  if (verify_refs_get(refs, &t, &a, &b, &clamped, &err) != NBRDF_OK) {
    fprintf(stderr, "bench_verify: %s\n", err.message);
    return 1;
  }
  double rw = bench_wall_seconds() - w0, rc = bench_cpu_seconds() - c0;
  printf("| quantity | value |\n|---|---|\n");
  printf("| decoder (bundle %s) | %lld MACs per query |\n", nbrdf_model_name(model),
         (long long)nbrdf_model_decoder_macs(model));
  printf("| distinct latents decoded | %d (%zu queries) |\n", latents, q);
  printf("| decode: queries per CPU-second | %.3g (%.3g per wall-second) |\n", q / dc, q / dw);
  printf("| decode: GFLOP/s (2 x MACs) | %.2f |\n", 2 * macs / dc * 1e-9);
  printf("| cblas_sgemm 16384x32x32 GFLOP/s (CPU time) | %.2f |\n", sg);
  printf("| decode as a fraction of sgemm | %.1f %% |\n", 100 * 2 * macs / dc * 1e-9 / sg);
  printf("| ground truth: one reference (2 runs x 4 images x %d walks, %d thread(s)) | %.2f "
         "CPU-s (%.2f s wall) |\n",
         walks, threads, rc, rw);
  printf("| reference noise of that reference | %.2f %% |\n",
         100 * lobe_l1_error(VERIFY_SET, a, b));
  verify_refs_free(refs);
  verify_decoder_free(dec);
  nbrdf_model_destroy(model);
  free(lat), free(img);
  return 0;
}
