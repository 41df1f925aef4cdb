/* Which texels verify compares. A stratified sample rather than a uniform
 * one, so that a painted region of a large texture is not missed by chance;
 * jittered within its cell, so that a periodic pattern is not aliased. */
#include <math.h>
#include <stdlib.h>

#include "core/rng.h"
#include "verify/verify_internal.h"

/* Cells along x and y with gx·gy <= n, gx <= w, gy <= h, cells about square. */
static void grid(int w, int h, int n, int *gx, int *gy) {
  double s = sqrt((double)w * h / n); /* cell edge */
  int a = (int)ceil(w / s), b = (int)ceil(h / s);
  if (a > w) a = w;
  if (b > h) b = h;
  while ((long)a * b > n) {
    if ((double)w / a < (double)h / b && b > 1) /* cells narrower than tall: fewer rows */
      b--;
    else if (a > 1)
      a--;
    else
      b--;
  }
  *gx = a < 1 ? 1 : a;
  *gy = b < 1 ? 1 : b;
}

size_t verify_select(int w, int h, int n, uint64_t seed, int level, verify_point **out) {
  *out = NULL;
  if (w < 1 || h < 1 || n < 1) return 0;
  if ((long)w * h <= n) {
    verify_point *p = malloc(sizeof *p * (size_t)w * (size_t)h);
    if (!p) return 0;
    size_t k = 0;
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w; x++)
        p[k++] = (verify_point){x, y};
    *out = p;
    return k;
  }
  int gx, gy;
  grid(w, h, n, &gx, &gy);
  verify_point *p = malloc(sizeof *p * (size_t)gx * (size_t)gy);
  if (!p) return 0;
  core_rng rng;
  core_rng_init(&rng, seed, 1000u + (uint64_t)level);
  size_t k = 0;
  for (int j = 0; j < gy; j++) /* row-major, so rows of maps are read in order */
    for (int i = 0; i < gx; i++) {
      int x0 = (int)((long)w * i / gx), x1 = (int)((long)w * (i + 1) / gx);
      int y0 = (int)((long)h * j / gy), y1 = (int)((long)h * (j + 1) / gy);
      int x = x0 + (int)(core_rng_uniform(&rng) * (x1 - x0));
      int y = y0 + (int)(core_rng_uniform(&rng) * (y1 - y0));
      p[k++] = (verify_point){x < x1 ? x : x1 - 1, y < y1 ? y : y1 - 1};
    }
  *out = p;
  return k;
}

int verify_footprint(int x0, int x1, int y0, int y1, int max, verify_point *out) {
  int w = x1 - x0, h = y1 - y0;
  if (max < 1) max = 1;
  int gx = w, gy = h;
  if ((long)w * h > max) grid(w, h, max, &gx, &gy);
  int k = 0;
  for (int j = 0; j < gy; j++)
    for (int i = 0; i < gx; i++) /* the centre of cell (i, j) */
      out[k++] = (verify_point){x0 + (int)(((2L * i + 1) * w) / (2L * gx)),
                                y0 + (int)(((2L * j + 1) * h) / (2L * gy))};
  return k;
}
