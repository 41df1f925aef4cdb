/* Trilinear latent fetch (src/texture/latent_fetch.c) against hand-computed
 * mixes, texel centres, wrapping, lod clamping, and the loader against the
 * writer. */
#include <stdlib.h>
#include <string.h>

#include "texture/latent_fetch.h"
#include "testing.h"
#include "texture/latent_fixture.h"

static const texture_latent_layout layout = {2, NBRDF_COLOUR_MONO, 1}; /* 4 floats per texel */

/* Texel (i, j) of level l, channel c: a value that names its position. */
static float val(int l, int i, int j, int c) { return (float)(100 * l + 10 * j + i + 0.25 * c); }

static texture_latent_image *make(void) {
  nbrdf_error err;
  texture_latent_image *img = NULL;
  CHECK_OK(texture_latent_image_create(&layout, 4, 2, 3, &img, &err), &err);
  if (!img) return NULL;
  for (int l = 0; l < img->levels; l++)
    for (int j = 0; j < img->height[l]; j++)
      for (int i = 0; i < img->width[l]; i++)
        for (int c = 0; c < img->channels; c++)
          img->data[l][((size_t)j * img->width[l] + i) * img->channels + c] = val(l, i, j, c);
  return img;
}

static void test_levels(void) {
  texture_latent_image *img = make();
  if (!img) return;
  /* OpenEXR round-down chain of 4 x 2: 4x2, 2x1, 1x1. */
  CHECK(img->levels == 3 && img->channels == 4);
  CHECK(img->width[1] == 2 && img->height[1] == 1 && img->width[2] == 1 && img->height[2] == 1);
  texture_latent_image_free(img);
}

static void test_texel_centres(void) {
  texture_latent_image *img = make();
  if (!img) return;
  float out[4];
  for (int l = 0; l < img->levels; l++)
    for (int j = 0; j < img->height[l]; j++)
      for (int i = 0; i < img->width[l]; i++) {
        float u = (i + 0.5f) / img->width[l], v = (j + 0.5f) / img->height[l];
        texture_latent_fetch(img, u, v, (float)l, out);
        for (int c = 0; c < 4; c++)
          CHECK_MSG(out[c] == val(l, i, j, c), "level %d texel (%d, %d) channel %d: %g vs %g", l, i,
                    j, c, out[c], val(l, i, j, c));
      }
  texture_latent_image_free(img);
}

static void test_hand_mix(void) {
  texture_latent_image *img = make();
  if (!img) return;
  float out[4];
  /* u = 0.3, v = 0.8, lod = 0.4. Level 0 (4 x 2): x = 0.7 -> i 0|1, fx 0.7;
   * y = 1.1 -> j 1|0 (wrapped), fy 0.1. Level 1 (2 x 1): x = 0.1 -> i 0|1,
   * fx 0.1; y = 0.3 -> j 0|0. Blend 0.6 level 0 + 0.4 level 1. */
  texture_latent_fetch(img, 0.3f, 0.8f, 0.4f, out);
  for (int c = 0; c < 4; c++) {
    double l0 = 0.3 * 0.9 * val(0, 0, 1, c) + 0.7 * 0.9 * val(0, 1, 1, c) +
                0.3 * 0.1 * val(0, 0, 0, c) + 0.7 * 0.1 * val(0, 1, 0, c);
    double l1 = 0.9 * val(1, 0, 0, c) + 0.1 * val(1, 1, 0, c);
    CHECK_NEAR(out[c], 0.6 * l0 + 0.4 * l1, 1e-4);
  }
  /* Wrapping: u and u ± 1 fetch the same; u = 0 mixes the first and last column. */
  float a[4], b[4], e[4];
  texture_latent_fetch(img, 0.1f, 0.25f, 0.0f, a);
  texture_latent_fetch(img, 1.1f, 0.25f, 0.0f, b);
  texture_latent_fetch(img, -0.9f, 0.25f, 0.0f, e);
  for (int c = 0; c < 4; c++) {
    CHECK_NEAR(a[c], b[c], 1e-4);
    CHECK_NEAR(a[c], e[c], 1e-4);
  }
  texture_latent_fetch(img, 0.0f, 0.25f, 0.0f, a);
  CHECK_NEAR(a[0], 0.5 * val(0, 3, 0, 0) + 0.5 * val(0, 0, 0, 0), 1e-4);
  /* lod beyond the chain is the last level; negative (and NaN) is level 0. */
  texture_latent_fetch(img, 0.37f, 0.61f, 10.0f, a);
  CHECK(a[1] == val(2, 0, 0, 1));
  texture_latent_fetch(img, 0.125f, 0.25f, -3.0f, a);
  CHECK(a[2] == val(0, 0, 0, 2));
  texture_latent_fetch(img, 0.125f, 0.25f, NAN, a);
  CHECK(a[2] == val(0, 0, 0, 2));
  texture_latent_image_free(img);
}

static void test_load(void) {
  nbrdf_error err;
  const texture_latent_layout lay = {3, NBRDF_COLOUR_RGB, 1};
  int W = 9, H = 6, C = texture_latent_channel_count(&lay);
  float *texels = fixture_texels(W, H, &lay, 5);
  char path[512];
  snprintf(path, sizeof path, "%s/fetch.exr", testing_tmpdir());
  texture_latent_meta meta = {"m", "0123456789abcdef", "", "", NULL, 0, NULL, NULL};
  texture_latent_exr_options o = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  o.storage = NBRDF_LATENT_FLOAT, o.tile_size = 8;
  CHECK_OK(fixture_write(path, W, H, &lay, &meta, &o, texels, 4, &err), &err);
  texture_latent_image *img = NULL;
  char sum[64];
  CHECK_OK(texture_latent_image_load(path, &img, sum, sizeof sum, &err), &err);
  if (img) {
    CHECK(img->levels == 4 && img->width[3] == 1 && img->height[3] == 1);
    CHECK(!strcmp(sum, "0123456789abcdef"));
    CHECK(!memcmp(img->data[0], texels, sizeof(float) * (size_t)W * H * C));
    /* A level-1 texel centre is the stored 2x2 mean. */
    int lw, lh;
    float *l1 = fixture_level(texels, W, H, C, 1, &lw, &lh);
    float out[64];
    texture_latent_fetch(img, 2.5f / lw, 1.5f / lh, 1.0f, out);
    CHECK(fixture_error(out, l1 + ((size_t)1 * lw + 2) * C, (size_t)C, NBRDF_LATENT_FLOAT) <= 1.0);
    free(l1);
  }
  texture_latent_image_free(img);
  CHECK_FAILS(texture_latent_image_load("/nonexistent/x.exr", &img, NULL, 0, &err), NBRDF_ERR_IO,
              &err, "x.exr");
  free(texels);
}

int main(void) {
  RUN(test_levels);
  RUN(test_texel_centres);
  RUN(test_hand_mix);
  RUN(test_load);
  return testing_finish();
}
