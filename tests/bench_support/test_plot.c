/* Line plots (src/bench/support/plot.c) and the PNG writer behind them (png_write_shim.cpp). */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support/plot.h"
#include "lobe/png_write.h"
#include "testing.h"

static int count_tmp_files(const char *dir) {
  int n = 0;
  DIR *d = opendir(dir);
  for (struct dirent *e; d && (e = readdir(d));)
    n += strstr(e->d_name, ".tmp") != NULL;
  if (d) closedir(d);
  return n;
}

/* Pixels of colour (r, g, b) in the square of half-size `rad` around (x, y). */
static int colour_near(const unsigned char *rgb, int w, int x, int y, int rad, int r, int g,
                       int b) {
  int n = 0;
  for (int yy = y - rad; yy <= y + rad; yy++)
    for (int xx = x - rad; xx <= x + rad; xx++) {
      const unsigned char *p = rgb + ((size_t)yy * w + xx) * 3;
      n += p[0] == r && p[1] == g && p[2] == b;
    }
  return n;
}

static const double XS[3] = {1, 10, 100}, YS[3] = {1, 10, 100};

static void test_points_land_where_the_axes_say(void) {
  bench_plot_options o = NBRDF_PLOT_OPTIONS_DEFAULT;
  o.log_x = o.log_y = 1;
  o.title = "lobe error vs spp";
  /* A dashed floor at y = 1 in the colour of palette entry 2 (orange). */
  static const double ones[3] = {1, 1, 1};
  bench_plot_series s[2] = {{"coat", 3, XS, YS, 0, 0}, {"floor", 3, XS, ones, 1, 2}};
  unsigned char *rgb = NULL;
  int w = 0, h = 0;
  nbrdf_error err = {0}, *e = &err;
  CHECK_OK(bench_plot_render(&o, 2, s, &rgb, &w, &h, &err), e);
  if (!rgb) return;
  CHECK(w == 800 && h == 520);
  /* Data from 1 to 100 on both log axes: (1, 1) is the lower-left corner of the
   * plot area, (10, 10) its centre, (100, 100) the upper-right corner. */
  const int left = 90, right = w - 20, top = 56, bottom = h - 64;
  CHECK(colour_near(rgb, w, left, bottom, 2, 31, 119, 180) > 5);
  CHECK(colour_near(rgb, w, (left + right) / 2, (top + bottom) / 2, 2, 31, 119, 180) > 5);
  CHECK(colour_near(rgb, w, right, top, 2, 31, 119, 180) > 5);
  /* ... and nowhere near the other two corners, where there is no data. */
  CHECK(colour_near(rgb, w, left + 20, top + 20, 10, 31, 119, 180) == 0);
  CHECK(colour_near(rgb, w, right - 20, bottom - 20, 10, 31, 119, 180) == 0);
  CHECK(colour_near(rgb, w, right - 100, bottom, 10, 255, 127, 14) > 10);
  /* The title is drawn in black above the plot area. */
  int black = 0;
  for (int y = 0; y < top - 24; y++)
    black +=
        colour_near(rgb, w, w / 2, y, 0, 0, 0, 0) + colour_near(rgb, w, w / 2 - 30, y, 0, 0, 0, 0);
  CHECK(black > 0);
  free(rgb);
}

static void test_write_and_failures(void) {
  char path[512];
  snprintf(path, sizeof path, "%s/plot.png", testing_tmpdir());
  bench_plot_options o = NBRDF_PLOT_OPTIONS_DEFAULT;
  o.log_y = 1;
  o.width = 640;
  o.height = 400;
  const double nan_y[3] = {1, NAN, -1}; /* skipped points must not break the plot */
  bench_plot_series s[2] = {{"a", 3, XS, YS, 0, 0}, {"floor", 3, XS, nan_y, 1, 0}};
  nbrdf_error err = {0}, *e = &err;
  CHECK_OK(bench_plot_write_png(path, &o, 2, s, &err), e);
  int w = 0, h = 0;
  CHECK(testing_png_size(path, &w, &h) && w == 640 && h == 400);
  CHECK(count_tmp_files(testing_tmpdir()) == 0);
  o.width = 10;
  CHECK_FAILS(bench_plot_write_png(path, &o, 2, s, &err), NBRDF_ERR_ARGUMENT, &err, "plot.png");
  o.width = 0;
  snprintf(path, sizeof path, "%s/no/such/dir/plot.png", testing_tmpdir());
  CHECK_FAILS(bench_plot_write_png(path, &o, 2, s, &err), NBRDF_ERR_IO, &err, "plot.png");
  static const unsigned char px[3] = {1, 2, 3};
  CHECK_FAILS(lobe_png_write_rgb8(path, 0, 1, px, &err), NBRDF_ERR_ARGUMENT, &err, "size");
}

int main(void) {
  RUN(test_points_land_where_the_axes_say);
  RUN(test_write_and_failures);
  return testing_finish();
}
