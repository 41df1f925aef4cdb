/* The whole-lobe estimator agrees with per-pixel evaluation within the
 * standard errors, is deterministic for any thread count and follows the
 * METRICS.md lobe-image convention. */
#include "brdf/brdf_handle.h"
#include "brdf/layered_lobe.h"
#include "layered_util.h"

enum { RES = 12 };

static void compare(const char *label, const nbrdf_brdf *b, double theta_deg, int walks, int spp) {
  const brdf_bsdf_layered *l = &brdf_handle_bsdf(b)->layered;
  double img[RES * RES], img_se[RES * RES];
  CHECK(brdf_layered_lobe_image(l, theta_deg * M_PI / 180, RES, walks, 21, 0, img, img_se));
  nbrdf_query q[RES * RES];
  int pix[RES * RES], n = 0;
  for (int row = 0; row < RES; row++)
    for (int col = 0; col < RES; col++) {
      double x = -1.0 + (col + 0.5) * 2.0 / RES, y = 1.0 - (row + 0.5) * 2.0 / RES;
      if (x * x + y * y >= 1.0) {
        CHECK(img[row * RES + col] == 0.0);
        continue;
      }
      set_dir(q[n].wi, theta_deg, 0);
      q[n].wo[0] = x, q[n].wo[1] = y, q[n].wo[2] = sqrt(1 - x * x - y * y);
      pix[n++] = row * RES + col;
    }
  double f[RES * RES], se[RES * RES];
  nbrdf_eval_options o = NBRDF_EVAL_OPTIONS_DEFAULT;
  o.spp = spp;
  o.seed = 22;
  nbrdf_error err_ = {0}, *err = &err_;
  CHECK_OK(nbrdf_brdf_eval(b, (size_t)n, q, &o, f, se, err), err);
  double sum_z2 = 0.0, worst = 0.0;
  for (int k = 0; k < n; k++) {
    double c = q[k].wo[2];
    double a = img[pix[k]], sa = img_se[pix[k]], e = f[k] * c, sb = se[k] * c;
    double s = sqrt(sa * sa + sb * sb);
    double z = s > 0.0 ? (a - e) / s : (a == e ? 0.0 : INFINITY);
    sum_z2 += z * z;
    if (fabs(z) > fabs(worst)) worst = z;
  }
  double rms = sqrt(sum_z2 / n);
  printf("  %s: %d pixels, RMS z %.3f, worst %.2f\n", label, n, rms, worst);
  CHECK_MSG(fabs(worst) < 5.0 && rms < 1.5, "%s: RMS z %.3f, worst z %.2f", label, rms, worst);
}

static void test_agrees_with_per_pixel_eval(void) {
  nbrdf_brdf *b = layered2(0.02, 1.5, 0.5, 0.9, 0.0, 0.0);
  compare("smooth coat over rough metal", b, 30, 2000, 2000);
  nbrdf_brdf_destroy(b);
  b = layered2(0.6, 1.5, 0.02, 0.9, 0.0, 0.0);
  compare("rough coat over smooth metal", b, 60, 2000, 2000);
  nbrdf_brdf_destroy(b);
  b = layered2(0.1, 1.5, 0.3, 0.9, 0.95, 5.0);
  compare("thick scattering medium", b, 0, 1000, 1000);
  nbrdf_brdf_destroy(b);
  b = layered2(0.3, 1.0, 0.3, 0.5, 0.5, 1.0);
  compare("index-matched top", b, 45, 2000, 2000);
  nbrdf_brdf_destroy(b);
  nbrdf_brdf *inner = layered2(0.2, 1.8, 0.4, 0.9, 0.0, 0.0);
  b = layered_or_die(0.3, 1.3, 0.5, 1.0, inner);
  compare("three layers", b, 20, 300, 1000);
  nbrdf_brdf_destroy(b);
  nbrdf_brdf_destroy(inner);
}

static void test_deterministic_and_oriented(void) {
  nbrdf_brdf *b = layered2(0.05, 1.5, 0.3, 0.9, 0.5, 1.0);
  const brdf_bsdf_layered *l = &brdf_handle_bsdf(b)->layered;
  double a[RES * RES], sa[RES * RES], c[RES * RES], sc[RES * RES];
  CHECK(brdf_layered_lobe_image(l, 0.7, RES, 100, 5, 1, a, sa));
  CHECK(brdf_layered_lobe_image(l, 0.7, RES, 100, 5, 2, c, sc));
  CHECK(memcmp(a, c, sizeof a) == 0 && memcmp(sa, sc, sizeof sa) == 0);
  /* The coat's mirror lobe is at ωo = (−sin θi, 0, cos θi): the brightest
   * pixel is left of the centre, on the middle rows. */
  int best = 0;
  for (int k = 1; k < RES * RES; k++)
    if (a[k] > a[best]) best = k;
  int row = best / RES, col = best % RES;
  CHECK_MSG(col < RES / 2 && (row == RES / 2 - 1 || row == RES / 2), "brightest pixel (%d, %d)",
            row, col);
  nbrdf_brdf_destroy(b);
}

int main(void) {
  RUN(test_agrees_with_per_pixel_eval);
  RUN(test_deterministic_and_oriented);
  return testing_finish();
}
