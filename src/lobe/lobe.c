#include "lobe/lobe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/vec3.h"

const double lobe_theta_deg[NBRDF_LOBE_N_THETA] = {0.0, 30.0, 60.0, 80.0};

int lobe_pixel_wo(int res, int row, int col, double wo[3]) {
  double x = -1.0 + (col + 0.5) * 2.0 / res;
  double y = 1.0 - (row + 0.5) * 2.0 / res;
  double r2 = x * x + y * y;
  if (!(r2 < 1.0)) return 0;
  wo[0] = x;
  wo[1] = y;
  wo[2] = sqrt(1.0 - r2);
  return 1;
}

size_t lobe_pixels_inside(int res) {
  size_t n = 0;
  double wo[3];
  for (int row = 0; row < res; row++)
    for (int col = 0; col < res; col++)
      n += (size_t)lobe_pixel_wo(res, row, col, wo);
  return n;
}

nbrdf_status lobe_images(lobe_fn fn, void *user, int res, int n_theta, const double *theta_deg,
                         double *images, nbrdf_error *err) {
  if (res < 1 || res > 4096)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "lobe resolution %d is outside [1, 4096]", res);
  if (n_theta < 0)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "lobe image count %d is negative", n_theta);
  for (int t = 0; t < n_theta; t++) {
    nbrdf_status st = core_check_range(err, "lobe theta_i (degrees)", theta_deg[t], 0.0, 90.0);
    if (st != NBRDF_OK) return st;
    if (theta_deg[t] == 90.0)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "lobe theta_i = 90 degrees is grazing");
  }
  const size_t per_image = (size_t)res * (size_t)res, inside = lobe_pixels_inside(res);
  const size_t n = inside * (size_t)n_theta;
  memset(images, 0, per_image * (size_t)n_theta * sizeof *images);
  if (n == 0) return NBRDF_OK;
  nbrdf_query *q = malloc(n * sizeof *q);
  double *f = malloc(n * sizeof *f);
  if (!q || !f) {
    free(q), free(f);
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory for %zu lobe queries", n);
  }
  size_t k = 0;
  for (int t = 0; t < n_theta; t++) {
    vec3 wi = v3_from_spherical(theta_deg[t] * (M_PI / 180.0), 0.0);
    for (int row = 0; row < res; row++)
      for (int col = 0; col < res; col++) {
        if (!lobe_pixel_wo(res, row, col, q[k].wo)) continue;
        q[k].wi[0] = wi.x, q[k].wi[1] = wi.y, q[k].wi[2] = wi.z;
        k++;
      }
  }
  nbrdf_status st = fn(user, n, q, f, err);
  for (k = 0; st == NBRDF_OK && k < n; k++)
    if (!isfinite(f[k]))
      st = core_fail(err, NBRDF_ERR_INTERNAL, "lobe query %zu: the BRDF returned %g", k, f[k]);
  if (st == NBRDF_OK) {
    k = 0;
    for (int t = 0; t < n_theta; t++)
      for (size_t p = 0; p < per_image; p++) {
        double wo[3];
        if (!lobe_pixel_wo(res, (int)(p / (size_t)res), (int)(p % (size_t)res), wo)) continue;
        images[(size_t)t * per_image + p] = f[k++] * wo[2];
      }
  }
  free(q);
  free(f);
  return st;
}

double lobe_l1_error(size_t n_pixels, const double *ref, const double *approx) {
  double num = 0.0, den = 0.0;
  for (size_t p = 0; p < n_pixels; p++) {
    num += fabs(approx[p] - ref[p]);
    den += fabs(ref[p]);
  }
  if (den > 0.0) return num / den;
  return num > 0.0 ? INFINITY : 0.0;
}

double lobe_albedo(int res, const double *image) {
  const double area = (2.0 / res) * (2.0 / res);
  double rho = 0.0;
  for (int row = 0; row < res; row++)
    for (int col = 0; col < res; col++) {
      double wo[3];
      if (lobe_pixel_wo(res, row, col, wo))
        rho += image[(size_t)row * (size_t)res + (size_t)col] / wo[2];
    }
  return rho * area;
}

double lobe_albedo_error(int res, int n_images, const double *ref, const double *approx,
                         double *per_image) {
  const size_t stride = (size_t)res * (size_t)res;
  double sum = 0.0;
  for (int t = 0; t < n_images; t++) {
    double e = fabs(lobe_albedo(res, approx + (size_t)t * stride) -
                    lobe_albedo(res, ref + (size_t)t * stride));
    if (per_image) per_image[t] = e;
    sum += e;
  }
  return n_images > 0 ? sum / n_images : 0.0;
}
