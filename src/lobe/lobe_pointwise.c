/* The point-wise lobe error of lobe.h (contract there). */
#include <math.h>
#include <stdlib.h>

#include "core/sort.h"
#include "lobe/lobe.h"

double lobe_median_finite(size_t n, const double *x) {
  double *v = malloc((n ? n : 1) * sizeof *v);
  if (!v) return NAN;
  size_t m = 0;
  for (size_t k = 0; k < n; k++)
    if (isfinite(x[k])) v[m++] = x[k];
  double med = NAN;
  if (m > 0) {
    core_sort_doubles(v, m);
    med = m % 2 ? v[m / 2] : 0.5 * (v[m / 2 - 1] + v[m / 2]);
  }
  free(v);
  return med;
}

double lobe_pointwise_error(int res, const double *ref, const double *approx,
                            double floor_fraction) {
  size_t npix = (size_t)res * (size_t)res;
  double *e = malloc(npix * sizeof *e);
  if (!e) return NAN;
  double peak = 0.0, wo[3];
  for (int row = 0; row < res; row++)
    for (int col = 0; col < res; col++)
      if (lobe_pixel_wo(res, row, col, wo)) {
        double f = ref[(size_t)row * res + col] / wo[2];
        if (f > peak) peak = f;
      }
  size_t m = 0;
  for (int row = 0; row < res; row++)
    for (int col = 0; col < res; col++) {
      size_t k = (size_t)row * res + col;
      if (!lobe_pixel_wo(res, row, col, wo)) continue;
      double f = ref[k] / wo[2];
      if (peak > 0.0 && f > floor_fraction * peak) e[m++] = fabs(approx[k] / ref[k] - 1.0);
    }
  double med = lobe_median_finite(m, e);
  free(e);
  return med;
}
