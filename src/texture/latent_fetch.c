/* Trilinear latent fetch (the convention is in latent_fetch.h). */
#include "texture/latent_fetch.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "texture/latent_exr.h"

void texture_latent_image_free(texture_latent_image *img) {
  if (!img) return;
  for (int l = 0; l < img->levels; l++)
    free(img->data[l]);
  free(img);
}

nbrdf_status texture_latent_image_create(const texture_latent_layout *layout, int width, int height,
                                         int levels, texture_latent_image **out, nbrdf_error *err) {
  *out = NULL;
  nbrdf_status st = texture_latent_layout_check(layout, err);
  if (st != NBRDF_OK) return st;
  if (width < 1 || height < 1 || levels < 1 || levels > TEXTURE_LATENT_MAX_LEVELS)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "latent image %d x %d with %d levels", width, height,
                     levels);
  texture_latent_image *img = calloc(1, sizeof *img);
  if (!img) return core_fail(err, NBRDF_ERR_MEMORY, "latent image: out of memory");
  img->layout = *layout;
  img->channels = texture_latent_channel_count(layout);
  for (int l = 0; l < levels; l++) {
    int w = width >> l, h = height >> l;
    img->width[l] = w > 1 ? w : 1;
    img->height[l] = h > 1 ? h : 1;
    img->data[l] = calloc((size_t)img->width[l] * img->height[l] * img->channels, sizeof(float));
    img->levels = l + 1;
    if (!img->data[l]) {
      texture_latent_image_free(img);
      return core_fail(err, NBRDF_ERR_MEMORY, "latent image level %d: out of memory", l);
    }
  }
  *out = img;
  return NBRDF_OK;
}

/* Every level of the open texture (closes it). */
static nbrdf_status load_levels(texture_latent_reader *r, const char *path,
                                texture_latent_image **out, nbrdf_error *err) {
  const texture_latent_info *info = texture_latent_reader_info(r);
  if (info->levels > TEXTURE_LATENT_MAX_LEVELS) {
    texture_latent_reader_close(r);
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: %d mip levels", path, info->levels);
  }
  texture_latent_image *img = NULL;
  nbrdf_status st = texture_latent_image_create(&info->layout, info->width, info->height,
                                                info->levels, &img, err);
  for (int l = 0; st == NBRDF_OK && l < img->levels; l++) {
    int w, h;
    st = texture_latent_reader_level_size(r, l, &w, &h, err);
    if (st == NBRDF_OK && (w != img->width[l] || h != img->height[l]))
      st = core_fail(err, NBRDF_ERR_FORMAT, "%s: level %d is %d x %d, expected %d x %d", path, l, w,
                     h, img->width[l], img->height[l]);
    if (st == NBRDF_OK) st = texture_latent_reader_read(r, l, 0, 0, w, h, img->data[l], err);
  }
  texture_latent_reader_close(r);
  if (st != NBRDF_OK) {
    texture_latent_image_free(img);
    return st;
  }
  *out = img;
  return NBRDF_OK;
}

nbrdf_status texture_latent_image_load(const char *path, texture_latent_image **out,
                                       char *model_checksum, size_t checksum_size,
                                       nbrdf_error *err) {
  *out = NULL;
  texture_latent_reader *r = NULL;
  nbrdf_status st = texture_latent_reader_open(&r, path, err);
  if (st != NBRDF_OK) return st;
  const texture_latent_info *info = texture_latent_reader_info(r);
  if (model_checksum && checksum_size)
    snprintf(model_checksum, checksum_size, "%s", info->model_checksum);
  return load_levels(r, path, out, err);
}

nbrdf_status texture_latent_image_load_model(const char *path, const nbrdf_model *bundle,
                                             texture_latent_image **out, nbrdf_model **model,
                                             nbrdf_error *err) {
  *out = NULL;
  *model = NULL;
  texture_latent_reader *r = NULL;
  nbrdf_status st = texture_latent_reader_open(&r, path, err);
  if (st == NBRDF_OK) st = texture_latent_reader_model(r, bundle, model, err);
  if (st != NBRDF_OK) {
    texture_latent_reader_close(r);
    return st;
  }
  st = load_levels(r, path, out, err);
  if (st != NBRDF_OK) {
    nbrdf_model_destroy(*model);
    *model = NULL;
  }
  return st;
}

/* Positive modulo: repeat wrapping for negative coordinates as well. */
static int wrap(int i, int n) {
  int m = i % n;
  return m < 0 ? m + n : m;
}

void texture_latent_fetch_level(const texture_latent_image *img, int level, float u, float v,
                                float *out) {
  int w = img->width[level], h = img->height[level], C = img->channels;
  float x = u * (float)w - 0.5f, y = v * (float)h - 0.5f;
  float xf = floorf(x), yf = floorf(y);
  float fx = x - xf, fy = y - yf;
  /* The period is reduced in float first so that huge u (a plane's far
   * horizon) cannot overflow the int conversion. */
  int i0 = wrap((int)fmodf(xf, (float)w), w), j0 = wrap((int)fmodf(yf, (float)h), h);
  int i1 = i0 + 1 == w ? 0 : i0 + 1, j1 = j0 + 1 == h ? 0 : j0 + 1;
  const float *d = img->data[level];
  const float *t00 = d + ((size_t)j0 * w + i0) * C, *t10 = d + ((size_t)j0 * w + i1) * C;
  const float *t01 = d + ((size_t)j1 * w + i0) * C, *t11 = d + ((size_t)j1 * w + i1) * C;
  float w00 = (1.0f - fx) * (1.0f - fy), w10 = fx * (1.0f - fy);
  float w01 = (1.0f - fx) * fy, w11 = fx * fy;
  for (int c = 0; c < C; c++)
    out[c] = w00 * t00[c] + w10 * t10[c] + w01 * t01[c] + w11 * t11[c];
}

void texture_latent_fetch(const texture_latent_image *img, float u, float v, float lod,
                          float *out) {
  float last = (float)(img->levels - 1);
  if (!(lod > 0.0f)) lod = 0.0f; /* NaN too */
  if (lod > last) lod = last;
  int l0 = (int)floorf(lod);
  float t = lod - (float)l0;
  texture_latent_fetch_level(img, l0, u, v, out);
  if (l0 + 1 >= img->levels || t == 0.0f) return;
  int C = img->channels;
  float tmp[4 * NBRDF_LATENT_MAX_DIM + 8];
  float *b = C <= (int)(sizeof tmp / sizeof tmp[0]) ? tmp : malloc(sizeof(float) * (size_t)C);
  if (!b) return; /* out of memory: level l0 alone, still a valid texel */
  texture_latent_fetch_level(img, l0 + 1, u, v, b);
  for (int c = 0; c < C; c++)
    out[c] = (1.0f - t) * out[c] + t * b[c];
  if (b != tmp) free(b);
}
