/* The decoder of each latent texture given, alone: queries per CPU-second
 * through nbrdf_model_decode in batches of 4,096 (a render tile's batch) on
 * the texture's own texels (every colour channel decoded), so that `nbrdf
 * render`'s "queries/s inside the renderer" can be read against the network's
 * own rate (issue 19: compact against universal and specialised textures).
 * Prints a markdown table.
 *
 *   bench_texture_decoder [--bundle DIR] [--seconds S] TEXTURE.exr ...
 *
 * Run with OPENBLAS_NUM_THREADS=1: one thread, as a render with --threads 1. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "nbrdf/model.h"
#include "texture/latent_exr.h"

#include "bench_clock.h"

enum { BATCH = 4096 };

static void die(nbrdf_status st, const nbrdf_error *err) {
  if (st == NBRDF_OK) return;
  fprintf(stderr, "bench_texture_decoder: %s\n", err->message);
  exit(1);
}

static void direction(core_rng *r, float w[3]) {
  double z = 0.02 + 0.98 * core_rng_uniform(r), phi = 2.0 * M_PI * core_rng_uniform(r);
  double s = sqrt(1.0 - z * z);
  w[0] = (float)(s * cos(phi)), w[1] = (float)(s * sin(phi)), w[2] = (float)z;
}

int main(int argc, char **argv) {
  const char *bundle_dir = NULL;
  double seconds = 2.0;
  int first = 1;
  for (; first < argc && argv[first][0] == '-'; first++) {
    if (!strcmp(argv[first], "--bundle") && first + 1 < argc)
      bundle_dir = argv[++first];
    else if (!strcmp(argv[first], "--seconds") && first + 1 < argc)
      seconds = atof(argv[++first]);
    else {
      fprintf(stderr, "usage: bench_texture_decoder [--bundle DIR] [--seconds S] TEXTURE.exr ...\n");
      return 2;
    }
  }
  nbrdf_error e = {0};
  nbrdf_model *bundle = NULL;
  char used[1024];
  if (bundle_dir)
    die(nbrdf_model_load(bundle_dir, &bundle, &e), &e);
  else
    die(nbrdf_model_load_default(&bundle, used, sizeof used, &e), &e);
  printf("| texture | latent channels | decoder MACs | queries/s, all colour channels (one thread) |\n");
  printf("|---|---|---|---|\n");
  for (int t = first; t < argc; t++) {
    nbrdf_model *m = NULL;
    die(nbrdf_model_for_texture(bundle, argv[t], &m, &e), &e);
    texture_latent_reader *r = NULL;
    die(texture_latent_reader_open(&r, argv[t], &e), &e);
    const texture_latent_info *info = texture_latent_reader_info(r);
    const int C = texture_latent_colours(&info->layout), D = info->layout.latent_dim;
    const int per = texture_latent_channel_count(&info->layout);
    float *texels = malloc(sizeof(float) * (size_t)info->width * info->height * per);
    die(texture_latent_reader_read(r, 0, 0, 0, info->width, info->height, texels, &e), &e);
    float *lat = malloc(sizeof(float) * BATCH * C * D), *f = malloc(sizeof(float) * BATCH * C);
    float *wi = malloc(sizeof(float) * BATCH * 3), *wo = malloc(sizeof(float) * BATCH * 3);
    core_rng rng;
    core_rng_init(&rng, 1, (uint64_t)t);
    size_t n_texels = (size_t)info->width * info->height;
    for (int k = 0; k < BATCH; k++) {
      const float *tx = texels + (core_rng_u32(&rng) % n_texels) * per;
      for (int c = 0; c < C; c++)
        for (int d = 0; d < D; d++)
          lat[(k * C + c) * D + d] = tx[texture_latent_index_latent(&info->layout, c, d)];
      direction(&rng, wi + 3 * k), direction(&rng, wo + 3 * k);
    }
    double c0 = bench_cpu_seconds(), done = 0;
    while (bench_cpu_seconds() - c0 < seconds) {
      die(nbrdf_model_decode(m, BATCH, C, lat, wi, wo, f, &e), &e);
      done += BATCH;
    }
    double rate = done / (bench_cpu_seconds() - c0);
    printf("| %s | %d x %d | %lld | %.3g |\n", argv[t], D, C,
           (long long)nbrdf_model_decoder_macs(m), rate);
    free(texels), free(lat), free(f), free(wi), free(wo);
    texture_latent_reader_close(r);
    nbrdf_model_destroy(m);
  }
  printf("\nload average %.1f\n", bench_load_average());
  nbrdf_model_destroy(bundle);
  return 0;
}
