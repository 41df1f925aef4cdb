/* Parameter maps in the formats artists use, read through OpenImageIO:
 * values, channel rules, colour handling, bands, and bad input; parameter
 * sources (constant or map). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testing.h"
#include "texture/param_map.h"
#include "texture/param_source.h"

static double srgb_to_linear(double v) {
  return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

/* A W x H image of C channels whose values are exact in 8 bits. */
static float *pattern(int W, int H, int C) {
  float *p = malloc(sizeof(float) * (size_t)W * H * C);
  for (int i = 0; i < W * H * C; i++)
    p[i] = (float)((i * 37 + 11) % 256) / 255.0f;
  return p;
}

static void path_in_tmp(char *buf, size_t n, const char *name) {
  snprintf(buf, n, "%s/%s", testing_tmpdir(), name);
}

/* Writes `src` as `name` and reads it back whole through a param map. */
static float *round_trip(const char *name, int W, int H, int C, const float *src,
                         texture_pixel_format fmt, const texture_param_map_options *opts,
                         texture_param_map_info *info) {
  nbrdf_error e, *err = &e;
  char path[512];
  path_in_tmp(path, sizeof path, name);
  CHECK_OK(texture_image_write(path, W, H, C, src, fmt, err), err);
  texture_param_map *m = NULL;
  CHECK_OK(texture_param_map_open(path, opts, &m, err), err);
  if (!m) return NULL;
  *info = *texture_param_map_get_info(m);
  float *out = malloc(sizeof(float) * (size_t)W * H * info->channels);
  CHECK_OK(texture_param_map_read_rows(m, 0, H, out, err), err);
  texture_param_map_close(m);
  return out;
}

static double max_diff(const float *a, const float *b, size_t n) {
  double worst = 0;
  for (size_t i = 0; i < n; i++)
    worst = fmax(worst, fabs((double)a[i] - (double)b[i]));
  return worst;
}

static void test_formats_as_data(void) {
  const int W = 19, H = 11;
  texture_param_map_info in;
  float *grey = pattern(W, H, 1), *rgb = pattern(W, H, 3), *out;
  struct {
    const char *name;
    int C;
    texture_pixel_format fmt;
    double tol;
  } cases[] = {
      {"g8.png", 1, NBRDF_PIXEL_U8, 1e-7},     {"rgb16.png", 3, NBRDF_PIXEL_U16, 1e-7},
      {"rgb8.tif", 3, NBRDF_PIXEL_U8, 1e-7},   {"g16.tif", 1, NBRDF_PIXEL_U16, 1e-7},
      {"rgbh.exr", 3, NBRDF_PIXEL_HALF, 1e-3}, {"gf.exr", 1, NBRDF_PIXEL_FLOAT, 0},
      {"rgb.jpg", 3, NBRDF_PIXEL_U8, 1.0}, /* lossy: only the size and format are exact */
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    const float *src = cases[i].C == 1 ? grey : rgb;
    out = round_trip(cases[i].name, W, H, cases[i].C, src, cases[i].fmt, NULL, &in);
    if (!out) continue;
    CHECK_MSG(in.width == W && in.height == H && in.channels == cases[i].C &&
                  in.file_channels == cases[i].C,
              "%s: %dx%d, %d channels", cases[i].name, in.width, in.height, in.channels);
    CHECK_MSG(in.format == cases[i].fmt, "%s: format %s", cases[i].name, in.format_name);
    double d = max_diff(out, src, (size_t)W * H * cases[i].C);
    CHECK_MSG(d <= cases[i].tol, "%s: values differ by %g", cases[i].name, d);
    CHECK(strstr(in.conversion, "non-colour") != NULL);
    free(out);
  }
  out = round_trip("fmt.png", W, H, 1, grey, NBRDF_PIXEL_U8, NULL, &in);
  CHECK(strcmp(in.file_format, "png") == 0 && in.bits_per_sample == 8);
  CHECK(strcmp(in.reported_colour_space, "sRGB") == 0);
  free(out);
  free(grey);
  free(rgb);
}

static void test_alpha_is_ignored(void) {
  const int W = 8, H = 5;
  float *rgba = pattern(W, H, 4), rgb[8 * 5 * 3];
  for (int p = 0; p < W * H; p++)
    for (int c = 0; c < 3; c++)
      rgb[p * 3 + c] = rgba[p * 4 + c];
  for (int p = 0; p < W * H; p++)
    rgba[p * 4 + 3] = 1.0f; /* straight alpha must not scale RGB */
  texture_param_map_info in;
  float *out = round_trip("rgba.png", W, H, 4, rgba, NBRDF_PIXEL_U8, NULL, &in);
  if (out) {
    CHECK(in.channels == 3 && in.file_channels == 4);
    CHECK(max_diff(out, rgb, (size_t)W * H * 3) < 1e-7);
  }
  free(out);
  free(rgba);
}

static void test_colour_data_is_linearised(void) {
  const int W = 16, H = 16;
  float *rgb = pattern(W, H, 3);
  texture_param_map_options colour = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
  colour.kind = NBRDF_PARAM_COLOUR;
  texture_param_map_info in;
  float *out = round_trip("r0.png", W, H, 3, rgb, NBRDF_PIXEL_U8, &colour, &in);
  /* OCIO's curve is continuous at the toe (slope 12.923 where IEC 61966-2-1
   * rounds to 12.92): within 1e-6 absolute everywhere, 1e-6 relative above. */
  double worst = 0, worst_rel = 0;
  for (int i = 0; out && i < W * H * 3; i++) {
    double want = srgb_to_linear(rgb[i]);
    worst = fmax(worst, fabs(out[i] - want));
    if (rgb[i] > 0.05f) worst_rel = fmax(worst_rel, fabs(out[i] - want) / want);
  }
  CHECK_MSG(out && worst < 1e-6 && worst_rel < 1e-6, "8-bit sRGB map: error %g (relative %g)",
            worst, worst_rel);
  CHECK(strstr(in.conversion, "sRGB") != NULL);
  free(out);
  /* Grey colour maps go through OCIO as (v, v, v). */
  out = round_trip("a.tif", W, H, 1, rgb, NBRDF_PIXEL_U16, &colour, &in);
  worst = 0;
  for (int i = 0; out && i < W * H; i++)
    worst = fmax(worst, fabs(out[i] - srgb_to_linear(rgb[i])));
  CHECK_MSG(out && worst < 1e-6, "16-bit grey sRGB map: error %g", worst);
  free(out);
  /* Float images are linear already; an explicit "linear" skips conversion. */
  out = round_trip("r0.exr", W, H, 3, rgb, NBRDF_PIXEL_FLOAT, &colour, &in);
  CHECK(out && max_diff(out, rgb, (size_t)W * H * 3) == 0);
  free(out);
  colour.colour_space = "linear";
  out = round_trip("r0lin.png", W, H, 3, rgb, NBRDF_PIXEL_U8, &colour, &in);
  CHECK(out && max_diff(out, rgb, (size_t)W * H * 3) < 1e-7);
  free(out);
  /* Non-colour data in 8 bits is never converted, only remapped on request. */
  texture_param_map_options eta = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
  eta.remap = 1;
  eta.lo = 1.0f;
  eta.hi = 2.0f;
  out = round_trip("eta.png", W, H, 1, rgb, NBRDF_PIXEL_U8, &eta, &in);
  worst = 0;
  for (int i = 0; out && i < W * H; i++)
    worst = fmax(worst, fabs(out[i] - (1.0 + rgb[i])));
  CHECK_MSG(out && worst < 1e-6, "remapped eta: error %g", worst);
  CHECK(strstr(in.conversion, "[0, 1] -> [1, 2]") != NULL);
  free(out);
  out = round_trip("eta.exr", W, H, 1, rgb, NBRDF_PIXEL_FLOAT, &eta, &in); /* float: as stored */
  CHECK(out && max_diff(out, rgb, (size_t)W * H) == 0);
  free(out);
  free(rgb);
}

static void test_bands_match_whole_reads(void) {
  nbrdf_error e, *err = &e;
  const int W = 23, H = 37;
  float *rgb = pattern(W, H, 3), band[23 * 7 * 3];
  char path[512];
  path_in_tmp(path, sizeof path, "bands.exr");
  CHECK_OK(texture_image_write(path, W, H, 3, rgb, NBRDF_PIXEL_FLOAT, err), err);
  /* A tiled, mip-mapped copy (OIIO reads tiled files differently). */
  char tiled[600], cmd[1400];
  snprintf(tiled, sizeof tiled, "%s/tiled.exr", testing_tmpdir());
  snprintf(cmd, sizeof cmd, "oiiotool '%s' --tile 16 16 -o '%s'", path, tiled);
  CHECK(system(cmd) == 0);
  const char *files[] = {path, tiled};
  for (int f = 0; f < 2; f++) {
    texture_param_map *m = NULL;
    CHECK_OK(texture_param_map_open(files[f], NULL, &m, err), err);
    int same = 1;
    for (int y = 0; m && y < H; y += 7) {
      int rows = H - y < 7 ? H - y : 7;
      CHECK_OK(texture_param_map_read_rows(m, y, rows, band, err), err);
      same &= memcmp(band, rgb + (size_t)y * W * 3, sizeof(float) * (size_t)rows * W * 3) == 0;
    }
    CHECK_MSG(same, "%s: bands differ from the image", files[f]);
    if (m)
      CHECK_FAILS(texture_param_map_read_rows(m, 35, 7, band, err), NBRDF_ERR_ARGUMENT, err,
                  "rows 35..41 of a map 37 rows high");
    texture_param_map_close(m);
  }
  free(rgb);
}

static void test_bad_maps_name_the_file(void) {
  nbrdf_error e, *err = &e;
  char path[512];
  texture_param_map *m = NULL;
  path_in_tmp(path, sizeof path, "missing.png");
  CHECK_FAILS(texture_param_map_open(path, NULL, &m, err), NBRDF_ERR_IO, err, path);
  path_in_tmp(path, sizeof path, "garbage.png");
  FILE *f = fopen(path, "wb");
  if (f) {
    fputs("this is not a PNG", f);
    fclose(f);
  }
  CHECK_FAILS(texture_param_map_open(path, NULL, &m, err), NBRDF_ERR_IO, err, path);
  float px[4 * 3 * 5] = {0};
  path_in_tmp(path, sizeof path, "two.png");
  CHECK_OK(texture_image_write(path, 4, 3, 2, px, NBRDF_PIXEL_U8, err), err);
  /* A 2-channel PNG is grey + alpha: alpha is ignored (test_bad_maps.c). */
  CHECK_OK(texture_param_map_open(path, NULL, &m, err), err);
  CHECK(m && texture_param_map_get_info(m)->channels == 1);
  texture_param_map_close(m);
  m = NULL;
  path_in_tmp(path, sizeof path, "five.tif");
  CHECK_OK(texture_image_write(path, 4, 3, 5, px, NBRDF_PIXEL_U8, err), err);
  CHECK_FAILS(texture_param_map_open(path, NULL, &m, err), NBRDF_ERR_UNSUPPORTED, err,
              "five.tif: 5 channels");
  CHECK(m == NULL);

  /* NaN, infinite and negative texels, named with their coordinates. */
  struct {
    float value;
    int C;
    const char *needle;
  } bad[] = {{NAN, 1, "texel (3, 2) is NaN"},
             {INFINITY, 3, "texel (3, 2) channel B is infinite"},
             {-0.25f, 1, "texel (3, 2) is negative (-0.25)"}};
  for (int i = 0; i < 3; i++) {
    float img[4 * 3 * 3];
    for (int k = 0; k < 4 * 3 * 3; k++)
      img[k] = 0.5f;
    img[(2 * 4 + 3) * bad[i].C + bad[i].C - 1] = bad[i].value;
    path_in_tmp(path, sizeof path, "bad.exr");
    CHECK_OK(texture_image_write(path, 4, 3, bad[i].C, img, NBRDF_PIXEL_FLOAT, err), err);
    CHECK_OK(texture_param_map_open(path, NULL, &m, err), err);
    if (m)
      CHECK_FAILS(texture_param_map_read_rows(m, 0, 3, img, err), NBRDF_ERR_ARGUMENT, err,
                  bad[i].needle);
    if (m) CHECK(strstr(e.message, "bad.exr") != NULL);
    texture_param_map_close(m);
    m = NULL;
  }
  texture_param_map_options colour = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
  colour.kind = NBRDF_PARAM_COLOUR;
  colour.colour_space = "no-such-space";
  path_in_tmp(path, sizeof path, "g8.png");
  CHECK_FAILS(texture_param_map_open(path, &colour, &m, err), NBRDF_ERR_ARGUMENT, err,
              "unknown colour space 'no-such-space'");
}

static void test_sources(void) {
  nbrdf_error e, *err = &e;
  texture_param_source *a = NULL, *b = NULL, *c = NULL, *d = NULL;
  CHECK_OK(texture_param_source_parse("alpha1", "0.3", NULL, &a, err), err);
  CHECK_OK(texture_param_source_parse("r0", "0.9, 0.6,0.3", NULL, &b, err), err);
  if (a && b) {
    CHECK(texture_param_source_is_constant(a) && texture_param_source_channels(a) == 1);
    CHECK(texture_param_source_channels(b) == 3 && texture_param_source_value(b, 1) == 0.6f);
    CHECK(strcmp(texture_param_source_describe(a), "alpha1=0.300000012") == 0);
    texture_param_band band;
    CHECK_OK(texture_param_source_read_band(b, 100, 50, &band, err), err);
    CHECK(band.row_stride == 0 && band.texel_stride == 0);
    CHECK(texture_param_band_at(&band, 7000, 30, 2) == 0.3f);
  }
  CHECK_FAILS(texture_param_source_parse("eta", "-1", NULL, &c, err), NBRDF_ERR_ARGUMENT, err,
              "eta: -1 is not a finite value >= 0");
  CHECK_FAILS(texture_param_source_parse("eta", "1,2", NULL, &c, err), NBRDF_ERR_IO, err,
              "eta: 1,2: cannot open");

  const int W = 6, H = 4;
  float *grey = pattern(W, H, 1), *small = pattern(3, 3, 1);
  char p1[512], p2[512];
  path_in_tmp(p1, sizeof p1, "src_a.exr");
  path_in_tmp(p2, sizeof p2, "src_b.exr");
  CHECK_OK(texture_image_write(p1, W, H, 1, grey, NBRDF_PIXEL_FLOAT, err), err);
  CHECK_OK(texture_image_write(p2, 3, 3, 1, small, NBRDF_PIXEL_FLOAT, err), err);
  CHECK_OK(texture_param_source_parse("sigma_t", p1, NULL, &c, err), err);
  CHECK_OK(texture_param_source_parse("albedo", p2, NULL, &d, err), err);
  if (c) {
    texture_param_band band;
    CHECK_OK(texture_param_source_read_band(c, 1, 2, &band, err), err);
    CHECK(!texture_param_source_is_constant(c));
    CHECK(texture_param_band_at(&band, 5, 1, 0) == grey[2 * W + 5]);
    CHECK(strstr(texture_param_source_describe(c), "sigma_t=") &&
          strstr(texture_param_source_describe(c), "openexr float grey"));
  }
  texture_param_source *all[] = {a, b, c, d};
  int w = 0, h = 0;
  CHECK_OK(texture_param_sources_common_size(all, 3, &w, &h, err), err);
  CHECK(w == W && h == H);
  CHECK_FAILS(texture_param_sources_common_size(all, 4, &w, &h, err), NBRDF_ERR_MISMATCH, err,
              "albedo: ");
  CHECK(strstr(e.message, "is 3x3, but sigma_t: ") && strstr(e.message, "is 6x4"));
  for (int i = 0; i < 4; i++)
    texture_param_source_free(all[i]);
  free(grey);
  free(small);
}

int main(void) {
  RUN(test_formats_as_data);
  RUN(test_alpha_is_ignored);
  RUN(test_colour_data_is_linearised);
  RUN(test_bands_match_whole_reads);
  RUN(test_bad_maps_name_the_file);
  RUN(test_sources);
  return testing_finish();
}
