/* Peak memory of the streaming latent EXR writer: it should grow with the
 * texture's width, not its height.
 * Usage: bench_latent_exr_memory WIDTH HEIGHT [latent_dim=32] [out_dir=/tmp]
 * Writes an RGB texture with the proxy (3 * (dim + 2) half channels, PIZ,
 * full mip chain) of cheap, smoothly varying values, then prints the peak
 * resident set size and the time. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "texture/latent_exr.h"

int main(int argc, char **argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: %s WIDTH HEIGHT [latent_dim] [out_dir]\n", argv[0]);
    return 2;
  }
  int W = atoi(argv[1]), H = atoi(argv[2]), dim = argc > 3 ? atoi(argv[3]) : 32;
  const char *dir = argc > 4 ? argv[4] : "/tmp";
  texture_latent_layout layout = {dim, NBRDF_COLOUR_RGB, 1};
  int C = texture_latent_channel_count(&layout), rows = 16;
  char path[1024];
  snprintf(path, sizeof path, "%s/bench_latent_mem_%d.exr", dir, (int)getpid());
  float *band = malloc(sizeof(float) * (size_t)rows * W * C);
  struct timespec t0, t1;
  clock_gettime(CLOCK_MONOTONIC, &t0);
  nbrdf_error err;
  texture_latent_writer *w = NULL;
  if (texture_latent_writer_create(&w, path, W, H, &layout, NULL, NULL, NULL, 0, &err) !=
      NBRDF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  for (int y = 0; y < H; y += rows) {
    int n = H - y < rows ? H - y : rows;
    for (int j = 0; j < n; j++)
      for (int x = 0; x < W; x++)
        for (int c = 0; c < C; c++)
          band[((size_t)j * W + x) * C + c] =
              (float)(0.5 + 0.25 * sin(0.001 * x * (c + 1) + 0.002 * (y + j)));
    if (texture_latent_writer_write_rows(w, band, n, &err) != NBRDF_OK) {
      fprintf(stderr, "%s\n", err.message);
      return 1;
    }
  }
  if (texture_latent_writer_finish(w, &err) != NBRDF_OK) {
    fprintf(stderr, "%s\n", err.message);
    return 1;
  }
  clock_gettime(CLOCK_MONOTONIC, &t1);
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  FILE *f = fopen(path, "rb");
  long size = 0;
  if (f) {
    fseek(f, 0, SEEK_END);
    size = ftell(f);
    fclose(f);
  }
  unlink(path);
  printf(
      "%dx%d, %d half channels: peak RSS %.0f MiB (input band %.0f MiB), file %.0f MiB, %.1f s\n",
      W, H, C, ru.ru_maxrss / 1024.0, sizeof(float) * (double)rows * W * C / 1048576.0,
      size / 1048576.0, (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec));
  free(band);
  return 0;
}
