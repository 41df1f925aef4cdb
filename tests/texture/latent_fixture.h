/* Shared by the latent texture tests: synthetic level-0 texels, a writer
 * loop that feeds them in bands, and expected mip levels computed by brute
 * force (independently of src/texture/mip_chain.c). */
#ifndef NBRDF_TESTS_LATENT_FIXTURE_H
#define NBRDF_TESTS_LATENT_FIXTURE_H

#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "testing.h"
#include "texture/latent_exr.h"
#include "texture/mip_chain.h"

/* Smooth in space plus noise, in [-3, 3]; proxy sigma/w in (0, 1). */
static inline float *fixture_texels(int W, int H, const texture_latent_layout *layout,
                                    uint64_t seed) {
  int C = texture_latent_channel_count(layout);
  float *t = malloc(sizeof(float) * (size_t)W * H * C);
  core_rng rng;
  core_rng_init(&rng, seed, 0);
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++)
      for (int i = 0; i < C; i++) {
        double u = core_rng_uniform(&rng);
        double smooth = sin(0.1 * x + 0.7 * i) * cos(0.13 * y - 0.3 * i);
        t[((size_t)y * W + x) * C + i] = (float)(2.0 * smooth + (u - 0.5));
      }
  if (layout->proxy)
    for (size_t p = 0; p < (size_t)W * H; p++)
      for (int c = 0; c < texture_latent_colours(layout); c++) {
        t[p * C + texture_latent_index_sigma(layout, c)] =
            (float)(0.05 + 0.9 * core_rng_uniform(&rng));
        t[p * C + texture_latent_index_w(layout, c)] = (float)core_rng_uniform(&rng);
      }
  return t;
}

/* Writes `texels` in bands of `band` rows (the last band shorter). */
static inline nbrdf_status fixture_write(const char *path, int W, int H,
                                         const texture_latent_layout *layout,
                                         const texture_latent_meta *meta,
                                         const texture_latent_exr_options *opts,
                                         const float *texels, int band, nbrdf_error *err) {
  texture_latent_writer *w = NULL;
  nbrdf_status st = texture_latent_writer_create(&w, path, W, H, layout, meta, opts, NULL, 0, err);
  if (st != NBRDF_OK) return st;
  size_t row = (size_t)W * texture_latent_channel_count(layout);
  for (int y = 0; y < H; y += band) {
    int n = H - y < band ? H - y : band;
    st = texture_latent_writer_write_rows(w, texels + (size_t)y * row, n, err);
    if (st != NBRDF_OK) {
      texture_latent_writer_abort(w);
      return st;
    }
  }
  return texture_latent_writer_finish(w, err);
}

/* Level l by brute force: each texel the mean of level-0 texels over
 * [x<<l, x==last ? W : (x+1)<<l) x (the same in y). */
static inline float *fixture_level(const float *l0, int W, int H, int C, int l, int *lw, int *lh) {
  int wl = W >> l < 1 ? 1 : W >> l, hl = H >> l < 1 ? 1 : H >> l;
  float *out = malloc(sizeof(float) * (size_t)wl * hl * C);
  double *acc = malloc(sizeof(double) * (size_t)C);
  for (int y = 0; y < hl; y++)
    for (int x = 0; x < wl; x++) {
      int x0 = x << l, x1 = x == wl - 1 ? W : (x + 1) << l;
      int y0 = y << l, y1 = y == hl - 1 ? H : (y + 1) << l;
      memset(acc, 0, sizeof(double) * (size_t)C);
      for (int yy = y0; yy < y1; yy++)
        for (int xx = x0; xx < x1; xx++)
          for (int c = 0; c < C; c++)
            acc[c] += l0[((size_t)yy * W + xx) * C + c];
      for (int c = 0; c < C; c++)
        out[((size_t)y * wl + x) * C + c] = (float)(acc[c] / ((double)(x1 - x0) * (y1 - y0)));
    }
  free(acc);
  *lw = wl;
  *lh = hl;
  return out;
}

/* Largest |got - want| relative to the storage's precision: <= 1 passes. */
static inline double fixture_error(const float *got, const float *want, size_t n,
                                   texture_latent_storage storage) {
  /* Half keeps 11 significant bits: round-to-nearest errs by <= 2^-11
   * relative (plus subnormal spacing near zero). Float storage may differ
   * from the test's own double-precision mean by one rounding (2^-23). */
  double rel = storage == NBRDF_LATENT_HALF ? 1.0 / 2000 : 1.0 / (1 << 23);
  double abs_tol = storage == NBRDF_LATENT_HALF ? 6e-8 : 1e-30;
  double worst = 0;
  for (size_t i = 0; i < n; i++) {
    double d = fabs((double)got[i] - (double)want[i]);
    double tol = rel * fabs((double)want[i]) + abs_tol;
    double r = d == 0 ? 0 : tol == 0 ? INFINITY : d / tol;
    if (!(r <= worst)) worst = r;
  }
  return worst;
}

#endif
