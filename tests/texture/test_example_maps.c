/* examples/make_maps.sh makes the maps the README's bake uses; they read as
 * parameter sources of the expected kinds, sizes and values. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testing.h"
#include "texture/param_source.h"

typedef struct {
  const char *name, *file;
  texture_param_kind kind;
  int channels;
  float lo, hi; /* every value within [lo, hi] (after linearisation) */
} expected_map;

static void test_example_maps(void) {
  nbrdf_error e, *err = &e;
  char dir[512], cmd[1400];
  snprintf(dir, sizeof dir, "%s/maps", testing_tmpdir());
  snprintf(cmd, sizeof cmd, "bash '%s/examples/make_maps.sh' '%s' > /dev/null",
           testing_source_dir(), dir);
  CHECK(system(cmd) == 0);
  static const expected_map maps[] = {
      {"alpha1", "alpha1.png", NBRDF_PARAM_DATA, 1, 0.05f, 0.9f},
      {"eta", "eta.exr", NBRDF_PARAM_DATA, 1, 1.3f, 1.7f},
      {"alpha2", "alpha2.png", NBRDF_PARAM_DATA, 1, 0.1f, 0.6f},
      {"r0", "r0.png", NBRDF_PARAM_COLOUR, 3, 0.25f, 0.9f},
      {"albedo", "albedo.png", NBRDF_PARAM_COLOUR, 3, 0.03f, 0.9f},
      {"sigma_t", "sigma_t.exr", NBRDF_PARAM_DATA, 1, 0.0f, 5.0f},
  };
  texture_param_source *src[6] = {0};
  for (int i = 0; i < 6; i++) {
    char path[700];
    snprintf(path, sizeof path, "%s/%s", dir, maps[i].file);
    texture_param_map_options opts = NBRDF_PARAM_MAP_OPTIONS_DEFAULT;
    opts.kind = maps[i].kind;
    CHECK_OK(texture_param_source_map(maps[i].name, path, &opts, &src[i], err), err);
    if (!src[i]) continue;
    CHECK(texture_param_source_channels(src[i]) == maps[i].channels);
    texture_param_band band;
    CHECK_OK(texture_param_source_read_band(src[i], 0, 256, &band, err), err);
    float lo = INFINITY, hi = -INFINITY;
    for (int y = 0; y < 256; y++)
      for (int x = 0; x < 256; x++)
        for (int c = 0; c < maps[i].channels; c++) {
          float v = texture_param_band_at(&band, x, y, c);
          lo = fminf(lo, v);
          hi = fmaxf(hi, v);
        }
    CHECK_MSG(lo >= maps[i].lo - 0.01f && hi <= maps[i].hi + 0.01f && hi > lo,
              "%s: values in [%g, %g], expected within [%g, %g]", maps[i].file, (double)lo,
              (double)hi, (double)maps[i].lo, (double)maps[i].hi);
  }
  /* sigma_t's four steps; eta's two stripes. */
  if (src[5]) {
    texture_param_band band;
    CHECK_OK(texture_param_source_read_band(src[5], 10, 1, &band, err), err);
    CHECK(texture_param_band_at(&band, 0, 0, 0) == 0.0f &&
          texture_param_band_at(&band, 70, 0, 0) == 1.0f);
    CHECK(texture_param_band_at(&band, 130, 0, 0) == 2.0f &&
          texture_param_band_at(&band, 255, 0, 0) == 5.0f);
  }
  if (src[1]) {
    texture_param_band band;
    CHECK_OK(texture_param_source_read_band(src[1], 100, 1, &band, err), err);
    CHECK(texture_param_band_at(&band, 5, 0, 0) == 1.3f &&
          texture_param_band_at(&band, 40, 0, 0) == 1.7f);
  }
  int w = 0, h = 0;
  CHECK_OK(texture_param_sources_common_size(src, 6, &w, &h, err), err);
  CHECK(w == 256 && h == 256);
  for (int i = 0; i < 6; i++)
    texture_param_source_free(src[i]);
}

int main(void) {
  RUN(test_example_maps);
  return testing_finish();
}
