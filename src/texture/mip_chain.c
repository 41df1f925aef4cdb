#include "texture/mip_chain.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

int texture_mip_level_count(int width, int height) {
  int m = width > height ? width : height, n = 1;
  while (m > 1) {
    m >>= 1;
    n++;
  }
  return n;
}

int texture_mip_level_dim(int dim0, int level) {
  int d = level >= 31 ? 0 : dim0 >> level;
  return d < 1 ? 1 : d;
}

void texture_mip_footprint(int dim0, int level, int i, int *begin, int *end) {
  int n = texture_mip_level_dim(dim0, level);
  *begin = i << level;
  *end = i == n - 1 ? dim0 : (i + 1) << level;
}

struct texture_mip_builder {
  int channels, levels;
  int w[NBRDF_MIP_MAX_LEVELS], h[NBRDF_MIP_MAX_LEVELS];
  /* sum[l]: running sums of the level-0 texels of the current row of
   * level l (l >= 1), w[l] * channels doubles. */
  double *sum[NBRDF_MIP_MAX_LEVELS];
  float *mean; /* scratch row handed to `emit` for levels >= 1 */
  float *copy; /* scratch copy of a level-0 row handed to `emit` */
  int rows;
  texture_mip_row_fn emit;
  void *user;
};

nbrdf_status texture_mip_builder_create(int width, int height, int channels, int levels,
                                        texture_mip_row_fn emit, void *user,
                                        texture_mip_builder **out, nbrdf_error *err) {
  *out = NULL;
  if (width < 1 || height < 1 || channels < 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "mip chain of %dx%d texels of %d channels", width,
                     height, channels);
  int full = texture_mip_level_count(width, height);
  if (levels < 1 || levels > full)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%d mip levels requested; a %dx%d texture has 1 to %d", levels, width, height,
                     full);
  texture_mip_builder *b = calloc(1, sizeof *b);
  if (!b) return core_fail(err, NBRDF_ERR_MEMORY, "out of memory for a mip builder");
  b->channels = channels;
  b->levels = levels;
  b->emit = emit;
  b->user = user;
  for (int l = 0; l < levels; l++) {
    b->w[l] = texture_mip_level_dim(width, l);
    b->h[l] = texture_mip_level_dim(height, l);
  }
  int ok = 1;
  for (int l = 1; l < levels; l++) {
    b->sum[l] = calloc((size_t)b->w[l] * (size_t)channels, sizeof(double));
    ok = ok && b->sum[l];
  }
  b->mean = malloc((size_t)b->w[levels > 1 ? 1 : 0] * (size_t)channels * sizeof(float));
  b->copy = malloc((size_t)width * (size_t)channels * sizeof(float));
  if (!ok || !b->mean || !b->copy) {
    texture_mip_builder_free(b);
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory for a mip chain %d texels wide", width);
  }
  *out = b;
  return NBRDF_OK;
}

/* The last row of level l-1 that feeds row y of level l. */
static int last_child(const texture_mip_builder *b, int l, int y) {
  return y == b->h[l] - 1 ? b->h[l - 1] - 1 : 2 * y + 1;
}

/* Adds a row of level l-1 (as sums, or level-0 values) into level l. */
static void accumulate_float(texture_mip_builder *b, int l, const float *row) {
  int C = b->channels, wp = b->w[l - 1], wl = b->w[l];
  double *sum = b->sum[l];
  for (int x = 0; x < wp; x++) {
    int xl = x >> 1 < wl ? x >> 1 : wl - 1;
    const float *src = row + (size_t)x * C;
    double *dst = sum + (size_t)xl * C;
    for (int c = 0; c < C; c++)
      dst[c] += src[c];
  }
}

static void accumulate_double(texture_mip_builder *b, int l, const double *row) {
  int C = b->channels, wp = b->w[l - 1], wl = b->w[l];
  double *sum = b->sum[l];
  for (int x = 0; x < wp; x++) {
    int xl = x >> 1 < wl ? x >> 1 : wl - 1;
    const double *src = row + (size_t)x * C;
    double *dst = sum + (size_t)xl * C;
    for (int c = 0; c < C; c++)
      dst[c] += src[c];
  }
}

/* Row y of level l (l >= 1) is complete: emit its means, pass its sums on
 * to level l+1, and clear it. Going through sums keeps every level-0 texel's
 * weight equal, whatever the nesting of odd footprints. */
static nbrdf_status finish_row(texture_mip_builder *b, int l, int y, nbrdf_error *err) {
  int C = b->channels, W0 = b->w[0], H0 = b->h[0];
  int y0, y1;
  texture_mip_footprint(H0, l, y, &y0, &y1);
  const double *sum = b->sum[l];
  for (int x = 0; x < b->w[l]; x++) {
    int x0, x1;
    texture_mip_footprint(W0, l, x, &x0, &x1);
    double inv = 1.0 / ((double)(x1 - x0) * (double)(y1 - y0));
    for (int c = 0; c < C; c++)
      b->mean[(size_t)x * C + c] = (float)(sum[(size_t)x * C + c] * inv);
  }
  nbrdf_status st = b->emit(b->user, l, y, b->mean, err);
  if (st != NBRDF_OK) return st;
  if (l + 1 < b->levels) {
    accumulate_double(b, l + 1, sum);
    int yn = y >> 1 < b->h[l + 1] ? y >> 1 : b->h[l + 1] - 1;
    if (y == last_child(b, l + 1, yn)) {
      st = finish_row(b, l + 1, yn, err);
      if (st != NBRDF_OK) return st;
    }
  }
  memset(b->sum[l], 0, (size_t)b->w[l] * (size_t)C * sizeof(double));
  return NBRDF_OK;
}

nbrdf_status texture_mip_builder_push_row(texture_mip_builder *b, const float *row,
                                          nbrdf_error *err) {
  int y = b->rows;
  if (y >= b->h[0])
    return core_fail(err, NBRDF_ERR_ARGUMENT, "row %d pushed into a mip chain %d rows high", y,
                     b->h[0]);
  size_t n = (size_t)b->w[0] * (size_t)b->channels;
  memcpy(b->copy, row, n * sizeof(float));
  nbrdf_status st = b->emit(b->user, 0, y, b->copy, err);
  if (st != NBRDF_OK) return st;
  b->rows++;
  if (b->levels > 1) {
    accumulate_float(b, 1, row);
    int y1 = y >> 1 < b->h[1] ? y >> 1 : b->h[1] - 1;
    if (y == last_child(b, 1, y1)) return finish_row(b, 1, y1, err);
  }
  return NBRDF_OK;
}

int texture_mip_builder_rows(const texture_mip_builder *b) { return b->rows; }

void texture_mip_builder_free(texture_mip_builder *b) {
  if (!b) return;
  for (int l = 0; l < NBRDF_MIP_MAX_LEVELS; l++)
    free(b->sum[l]);
  free(b->mean);
  free(b->copy);
  free(b);
}
