/* Lobe images as PNG (src/lobe/lobe_png.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "lobe/lobe.h"
#include "lobe/lobe_png.h"
#include "testing.h"

static nbrdf_status lambert(void *user, size_t n, const nbrdf_query *q, double *f,
                            nbrdf_error *err) {
  for (size_t k = 0; k < n; k++)
    f[k] = 1.0 / M_PI;
  return NBRDF_OK;
}

static void test_grid_sizes(void) {
  enum { RES = 32, NT = 4 };
  static double ref[NT * RES * RES], approx[NT * RES * RES];
  const double thetas[NT] = {0, 30, 60, 80};
  nbrdf_error err = {0}, *e = &err;
  CHECK_OK(lobe_images(lambert, NULL, RES, NT, thetas, ref, &err), e);
  for (int p = 0; p < NT * RES * RES; p++)
    approx[p] = ref[p] * (p % 3 ? 1.2 : 0.7);
  char path[512];
  int w = 0, h = 0;
  snprintf(path, sizeof path, "%s/cmp.png", testing_tmpdir());
  CHECK_OK(lobe_write_png(path, RES, NT, ref, approx, 2, &err), e);
  /* Three columns of 64-pixel panels, four rows, 4-pixel gaps around each. */
  CHECK_MSG(testing_png_size(path, &w, &h) && w == 3 * 64 + 4 * 4 && h == 4 * 64 + 5 * 4, "%d x %d",
            w, h);
  snprintf(path, sizeof path, "%s/one.png", testing_tmpdir());
  CHECK_OK(lobe_write_png(path, RES, 1, ref, NULL, 1, &err), e);
  CHECK_MSG(testing_png_size(path, &w, &h) && w == 32 + 8 && h == 32 + 8, "%d x %d", w, h);
  CHECK_FAILS(lobe_write_png(path, RES, 1, ref, NULL, 0, &err), NBRDF_ERR_ARGUMENT, &err, "zoom");
}

int main(void) {
  RUN(test_grid_sizes);
  return testing_finish();
}
