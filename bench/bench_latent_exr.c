/* Latent EXR write (and read) cost per compression and storage, on
 * synthetic but latent-like textures: each texel's latents are a smooth
 * non-linear function (tanh of a random linear map, like a network's output)
 * of six parameters that vary over the texture.
 *   painted:  parameters from a few flat regions (few distinct tuples)
 *   distinct: gradients plus fine detail (every texel distinct)
 * Usage: bench_latent_exr [size=1024] [latent_dim=32] [out_dir=/tmp]
 * Writes one file at a time (removed afterwards) and prints a table: file
 * size, write wall time and CPU time (tiles are compressed on all OpenMP
 * threads), and the wall and CPU time to read every level back (one thread). */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/rng.h"
#include "texture/latent_exr.h"

#include "bench_clock.h"

typedef struct {
  int size, dim, painted;
  float A[3 * 999][7]; /* per output channel: 6 weights and a bias */
} generator;

static void params_at(const generator *g, int x, int y, double p[6]) {
  double u = (double)x / g->size, v = (double)y / g->size;
  if (g->painted) {
    /* Eight flat regions: a 4x2 layout of painted patches. */
    int region = (int)(u * 4) + 4 * (int)(v * 2);
    for (int k = 0; k < 6; k++)
      p[k] = 0.1 + 0.8 * fmod(0.37 * (region + 1) * (k + 3), 1.0);
    return;
  }
  p[0] = u;                                         /* roughness gradient */
  p[1] = 0.5 + 0.5 * sin(40.0 * v);                 /* IOR stripes */
  p[2] = 0.5 + 0.3 * sin(7.0 * u + 3.0 * v);        /* smooth variation */
  p[3] = 0.5 + 0.2 * sin(90.0 * u) * sin(85.0 * v); /* fine detail */
  p[4] = v;                                         /* albedo gradient */
  p[5] = 0.5 + 0.5 * cos(11.0 * u * v);
}

static void band(const generator *g, int y0, int rows, int C, float *out) {
  for (int j = 0; j < rows; j++)
    for (int x = 0; x < g->size; x++) {
      double p[6];
      params_at(g, x, y0 + j, p);
      float *t = out + ((size_t)j * g->size + x) * C;
      for (int c = 0; c < C; c++) {
        const float *a = g->A[c];
        double s = a[6];
        for (int k = 0; k < 6; k++)
          s += a[k] * p[k];
        t[c] = (float)(2.0 * tanh(s));
      }
    }
}

int main(int argc, char **argv) {
  int size = argc > 1 ? atoi(argv[1]) : 1024, dim = argc > 2 ? atoi(argv[2]) : 32;
  const char *dir = argc > 3 ? argv[3] : "/tmp";
  if (size < 1 || dim < 1 || dim > 999) return 2;
  generator *g = calloc(1, sizeof *g);
  g->size = size;
  g->dim = dim;
  core_rng rng;
  core_rng_init(&rng, 2022, 0);
  texture_latent_layout layout = {dim, NBRDF_COLOUR_RGB, 0};
  int C = texture_latent_channel_count(&layout);
  for (int c = 0; c < C; c++)
    for (int k = 0; k < 7; k++)
      g->A[c][k] = (float)(2.0 * core_rng_uniform(&rng) - 1.0);
  const int rows = 64;
  float *buf = malloc(sizeof(float) * (size_t)rows * size * C);
  char path[1024];
  snprintf(path, sizeof path, "%s/bench_latent_%d.exr", dir, (int)getpid());
  printf("%dx%d RGB, %d latents/channel (%d channels), 64x64 tiles, full mip chain, "
         "%d compression threads\n",
         size, size, dim, C, omp_get_max_threads());
  printf("%-9s %-5s %-5s %10s %9s %8s %8s %8s %8s\n", "content", "store", "comp", "size MiB",
         "bits/val", "write s", "cpu s", "read s", "cpu s");
  static const texture_latent_compression comps[] = {
      NBRDF_LATENT_NONE, NBRDF_LATENT_RLE, NBRDF_LATENT_ZIPS, NBRDF_LATENT_ZIP, NBRDF_LATENT_PIZ};
  for (int painted = 1; painted >= 0; painted--) {
    g->painted = painted;
    for (int s = 0; s < 2; s++)
      for (int ci = 0; ci < 5; ci++) {
        nbrdf_error err;
        texture_latent_exr_options opts = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
        opts.storage = s ? NBRDF_LATENT_FLOAT : NBRDF_LATENT_HALF;
        opts.compression = comps[ci];
        texture_latent_writer *w = NULL;
        double t0 = bench_wall_seconds(), spent = 0, spent_cpu = 0, c0 = bench_cpu_seconds();
        if (texture_latent_writer_create(&w, path, size, size, &layout, NULL, &opts, NULL, 0,
                                         &err) != NBRDF_OK) {
          fprintf(stderr, "%s\n", err.message);
          return 1;
        }
        spent += bench_wall_seconds() - t0;
        spent_cpu += bench_cpu_seconds() - c0;
        for (int y = 0; y < size; y += rows) {
          int n = size - y < rows ? size - y : rows;
          band(g, y, n, C, buf); /* not timed */
          double t1 = bench_wall_seconds(), c1 = bench_cpu_seconds();
          if (texture_latent_writer_write_rows(w, buf, n, &err) != NBRDF_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
          }
          spent += bench_wall_seconds() - t1;
          spent_cpu += bench_cpu_seconds() - c1;
        }
        double t2 = bench_wall_seconds(), c2 = bench_cpu_seconds();
        if (texture_latent_writer_finish(w, &err) != NBRDF_OK) {
          fprintf(stderr, "%s\n", err.message);
          return 1;
        }
        spent += bench_wall_seconds() - t2;
        spent_cpu += bench_cpu_seconds() - c2;
        /* Read every level back whole. */
        double t3 = bench_wall_seconds(), c3 = bench_cpu_seconds();
        texture_latent_reader *r = NULL;
        long long bytes = 0;
        if (texture_latent_reader_open(&r, path, &err) == NBRDF_OK) {
          const texture_latent_info *in = texture_latent_reader_info(r);
          bytes = in->file_size;
          float *all = malloc(sizeof(float) * (size_t)size * 64 * C);
          for (int l = 0; l < in->levels; l++) {
            int lw, lh;
            texture_latent_reader_level_size(r, l, &lw, &lh, &err);
            for (int y = 0; y < lh; y += 64)
              texture_latent_reader_read(r, l, 0, y, lw, lh - y < 64 ? lh - y : 64, all, &err);
          }
          free(all);
          texture_latent_reader_close(r);
        }
        double read_s = bench_wall_seconds() - t3, read_cpu = bench_cpu_seconds() - c3;
        double values = (double)C * size * size * 4.0 / 3.0;
        printf("%-9s %-5s %-5s %10.1f %9.2f %8.2f %8.2f %8.2f %8.2f\n",
               painted ? "painted" : "distinct", texture_latent_storage_name(opts.storage),
               texture_latent_compression_name(comps[ci]), bytes / 1048576.0, bytes * 8.0 / values,
               spent, spent_cpu, read_s, read_cpu);
        fflush(stdout);
        unlink(path);
      }
  }
  free(buf);
  free(g);
  return 0;
}
