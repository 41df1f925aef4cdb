/* Lobe images and the metrics of METRICS.md (src/lobe/lobe.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "lobe/lobe.h"
#include "testing.h"

enum { RES = NBRDF_LOBE_RES, NT = NBRDF_LOBE_N_THETA, PIX = RES * RES };

typedef struct counter {
  int calls;
  size_t n;
  int bad_direction;
} counter;

/* Lambertian f = 1/π; also records how it was called and checks the directions. */
static nbrdf_status lambert(void *user, size_t n, const nbrdf_query *q, double *f,
                            nbrdf_error *err) {
  counter *c = user;
  c->calls++;
  c->n = n;
  for (size_t k = 0; k < n; k++) {
    double li = q[k].wi[0] * q[k].wi[0] + q[k].wi[1] * q[k].wi[1] + q[k].wi[2] * q[k].wi[2];
    double lo = q[k].wo[0] * q[k].wo[0] + q[k].wo[1] * q[k].wo[1] + q[k].wo[2] * q[k].wo[2];
    if (fabs(li - 1) > 1e-12 || fabs(lo - 1) > 1e-12 || q[k].wo[2] <= 0 || q[k].wi[1] != 0)
      c->bad_direction++;
    f[k] = 1.0 / M_PI;
  }
  return NBRDF_OK;
}

/* Pixel centres inside the disk, counted here independently of lobe.c. */
static size_t count_inside(int res) {
  size_t n = 0;
  for (int i = 0; i < res; i++)
    for (int j = 0; j < res; j++) {
      double x = -1 + (j + 0.5) * 2.0 / res, y = -1 + (i + 0.5) * 2.0 / res;
      n += x * x + y * y < 1;
    }
  return n;
}

static void test_lambertian_albedo(void) {
  static double img[NT * PIX];
  counter c = {0};
  nbrdf_error err = {0}, *e = &err; /* a pointer: CHECK_OK(x, &err) trips -Waddress */
  CHECK_OK(lobe_images(lambert, &c, RES, NT, lobe_theta_deg, img, &err), e);
  const size_t inside = count_inside(RES);
  CHECK(lobe_pixels_inside(RES) == inside);
  CHECK_MSG(c.calls == 1 && c.n == NT * inside, "one batched call of %zu queries, got %d of %zu",
            NT * inside, c.calls, c.n);
  CHECK(c.bad_direction == 0);
  /* Midpoint rule: every inside pixel contributes (1/π)·(2/64)². */
  const double expected = (double)inside * (2.0 / RES) * (2.0 / RES) / M_PI;
  for (int t = 0; t < NT; t++) {
    double rho = lobe_albedo(RES, img + t * PIX);
    CHECK_NEAR(rho, expected, 1e-12);
    CHECK_NEAR(rho, 1.0, 0.01); /* the pixelised disk has area π within 1 % */
  }
  /* Pixel values: f·cos θo inside, 0 outside (the corner). */
  double wo[3];
  CHECK(lobe_pixel_wo(RES, 20, 40, wo));
  CHECK_NEAR(img[PIX + 20 * RES + 40], wo[2] / M_PI, 1e-15);
  CHECK(!lobe_pixel_wo(RES, 0, 0, wo));
  CHECK(img[0] == 0.0 && img[3 * PIX + PIX - 1] == 0.0);
  CHECK(lobe_pixels_inside(1) == 1 && lobe_pixels_inside(2) == 4);
}

static void test_error_of_identical_and_scaled(void) {
  static double ref[NT * PIX], approx[NT * PIX];
  counter c = {0};
  nbrdf_error err = {0}, *e = &err; /* a pointer: CHECK_OK(x, &err) trips -Waddress */
  CHECK_OK(lobe_images(lambert, &c, RES, NT, lobe_theta_deg, ref, &err), e);
  CHECK(lobe_l1_error(NT * PIX, ref, ref) == 0.0);
  for (int p = 0; p < NT * PIX; p++)
    approx[p] = 1.1 * ref[p];
  CHECK_NEAR(lobe_l1_error(NT * PIX, ref, approx), 0.1, 1e-12);
  double per[NT];
  double mean = lobe_albedo_error(RES, NT, ref, approx, per);
  for (int t = 0; t < NT; t++)
    CHECK_NEAR(per[t], 0.1 * lobe_albedo(RES, ref + t * PIX), 1e-12);
  CHECK_NEAR(mean, per[0], 1e-12);
  /* The error pools all images: doubling one of four equal-sum images gives 25 %. */
  memcpy(approx, ref, sizeof approx);
  for (int p = 0; p < PIX; p++)
    approx[2 * PIX + p] *= 2.0;
  double s[NT] = {0};
  for (int t = 0; t < NT; t++)
    for (int p = 0; p < PIX; p++)
      s[t] += ref[t * PIX + p];
  CHECK_NEAR(lobe_l1_error(NT * PIX, ref, approx), s[2] / (s[0] + s[1] + s[2] + s[3]), 1e-12);
  static const double zero[4] = {0}, one[4] = {0, 1, 0, 0};
  CHECK(lobe_l1_error(4, zero, zero) == 0.0);
  CHECK(isinf(lobe_l1_error(4, zero, one)));
}

/* A narrow lobe around the mirror direction of ωi. */
static nbrdf_status mirror_peak(void *user, size_t n, const nbrdf_query *q, double *f,
                                nbrdf_error *err) {
  for (size_t k = 0; k < n; k++) {
    double dx = q[k].wo[0] + q[k].wi[0], dy = q[k].wo[1] + q[k].wi[1];
    f[k] = exp(-(dx * dx + dy * dy) / 0.01);
  }
  return NBRDF_OK;
}

static void test_mirror_is_left_of_centre(void) {
  static double img[PIX];
  const double theta = 30.0;
  nbrdf_error err = {0}, *e = &err; /* a pointer: CHECK_OK(x, &err) trips -Waddress */
  CHECK_OK(lobe_images(mirror_peak, NULL, RES, 1, &theta, img, &err), e);
  int best = 0;
  for (int p = 1; p < PIX; p++)
    if (img[p] > img[best]) best = p;
  double wo[3];
  CHECK(lobe_pixel_wo(RES, best / RES, best % RES, wo));
  CHECK_MSG(fabs(wo[0] + 0.5) < 2.0 / RES && fabs(wo[1]) < 2.0 / RES,
            "peak at (%g, %g), expected (-sin 30°, 0)", wo[0], wo[1]);
}

static nbrdf_status failing(void *user, size_t n, const nbrdf_query *q, double *f,
                            nbrdf_error *err) {
  return core_fail(err, NBRDF_ERR_IO, "decoder weights gone");
}

static nbrdf_status nan_at_7(void *user, size_t n, const nbrdf_query *q, double *f,
                             nbrdf_error *err) {
  for (size_t k = 0; k < n; k++)
    f[k] = k == 7 ? NAN : 1.0;
  return NBRDF_OK;
}

static void test_failures(void) {
  static double img[2 * PIX];
  nbrdf_error err = {0};
  const double thetas[2] = {0.0, 90.0}, bad_nan[1] = {NAN};
  CHECK_FAILS(lobe_images(failing, NULL, RES, 1, thetas, img, &err), NBRDF_ERR_IO, &err,
              "decoder weights gone");
  CHECK_FAILS(lobe_images(nan_at_7, NULL, RES, 1, thetas, img, &err), NBRDF_ERR_INTERNAL, &err,
              "lobe query 7");
  CHECK_FAILS(lobe_images(nan_at_7, NULL, RES, 2, thetas, img, &err), NBRDF_ERR_ARGUMENT, &err,
              "90");
  CHECK_FAILS(lobe_images(nan_at_7, NULL, RES, 1, bad_nan, img, &err), NBRDF_ERR_ARGUMENT, &err,
              "NaN");
  CHECK_FAILS(lobe_images(nan_at_7, NULL, 0, 1, thetas, img, &err), NBRDF_ERR_ARGUMENT, &err,
              "resolution");
}

/* The point-wise error: a uniform 10 % excess reads 0.1; anything below 1 %
 * of the peak is ignored however wrong; a wrong peak pixel is one of many. */
static void test_pointwise(void) {
  double *ref = calloc(PIX, sizeof *ref), *a = calloc(PIX, sizeof *a), wo[3];
  for (int row = 0; row < RES; row++)
    for (int col = 0; col < RES; col++)
      if (lobe_pixel_wo(RES, row, col, wo)) {
        double f = 1.0 + 0.5 * wo[0]; /* f >= 0.5 everywhere: every pixel counts */
        ref[row * RES + col] = f * wo[2];
      }
  lobe_pixel_wo(RES, 5, 32, wo);
  ref[5 * RES + 32] = 1e3 * wo[2]; /* one pixel peak: all others below 1 % */
  for (int k = 0; k < PIX; k++)
    a[k] = 1.1 * ref[k];
  CHECK_NEAR(lobe_pointwise_error(RES, ref, a, 0.01), 0.1, 1e-9); /* only the peak */
  CHECK_NEAR(lobe_pointwise_error(RES, ref, a, 1e-4), 0.1, 1e-9); /* all of them */
  for (int k = 0; k < PIX; k++)
    if (k != 5 * RES + 32) a[k] = 10.0 * ref[k];
  CHECK_NEAR(lobe_pointwise_error(RES, ref, a, 0.01), 0.1, 1e-9);
  CHECK_NEAR(lobe_pointwise_error(RES, ref, a, 1e-4), 9.0, 1e-9);
  double z[PIX] = {0};
  CHECK(isnan(lobe_pointwise_error(RES, z, a, 0.01)));
  double v[5] = {3, NAN, 1, 2, INFINITY};
  CHECK(lobe_median_finite(5, v) == 2.0);
  CHECK(isnan(lobe_median_finite(1, v + 1)));
  free(ref), free(a);
}

int main(void) {
  RUN(test_pointwise);
  RUN(test_lambertian_albedo);
  RUN(test_error_of_identical_and_scaled);
  RUN(test_mirror_is_left_of_centre);
  RUN(test_failures);
  return testing_finish();
}
