/* The ground truth as a lobe callback (src/lobe/lobe_brdf.c): integrating the
 * lobe image of a rough conductor over the disk gives the albedo that its
 * sampler gives, and stochastic lobes do not depend on the thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lobe/lobe.h"
#include "testing.h"

enum { RES = NBRDF_LOBE_RES, PIX = RES * RES };

static void test_conductor_lobe_albedo_matches_sampler(void) {
  nbrdf_brdf *b = NULL;
  nbrdf_error err = {0}, *e = &err;
  CHECK_OK(nbrdf_brdf_create_conductor(0.5, 1.0, &b, &err), e);
  if (!b) return;
  static double img[3 * PIX];
  const double thetas[3] = {0.0, 30.0, 60.0};
  lobe_brdf lb = {b, NBRDF_EVAL_OPTIONS_DEFAULT};
  CHECK_OK(lobe_images(lobe_brdf_fn, &lb, RES, 3, thetas, img, &err), e);
  for (int t = 0; t < 3; t++) {
    double rho = 0, se = 0;
    CHECK_OK(nbrdf_brdf_albedo(b, thetas[t] * M_PI / 180, 1 << 16, 3, &rho, &se, &err), e);
    /* The 64² midpoint rule resolves this wide lobe to within 1 %. */
    double lobe = lobe_albedo(RES, img + t * PIX);
    CHECK_MSG(fabs(lobe - rho) < 0.01 * rho + 4 * se,
              "theta_i %g: lobe %.5f vs sampler %.5f +- %.5f", thetas[t], lobe, rho, se);
    /* At normal incidence: 0.68785 by quadrature of D G2 / (4 cos_i cos_o) cos_o (800 × 64
     * midpoint rule in θo, φo; α = 0.5 GGX loses ~31 % to single scattering). */
    if (t == 0) CHECK_NEAR(rho, 0.68785, 4 * se + 1e-4);
  }
  nbrdf_brdf_destroy(b);
}

static void test_layered_lobe_is_deterministic(void) {
  nbrdf_brdf *bottom = NULL, *b = NULL;
  nbrdf_error err = {0}, *e = &err;
  CHECK_OK(nbrdf_brdf_create_conductor(0.3, 0.9, &bottom, &err), e);
  CHECK_OK(nbrdf_brdf_create_layered(0.1, 1.5, 0.8, 1.0, bottom, &b, &err), e);
  nbrdf_brdf_destroy(bottom);
  if (!b) return;
  enum { R = 16 };
  static double a[R * R], c[R * R], d[R * R];
  const double theta = 30.0;
  lobe_brdf one = {b, {42, 8, 1}}, two = {b, {42, 8, 2}}, other = {b, {43, 8, 2}};
  CHECK_OK(lobe_images(lobe_brdf_fn, &one, R, 1, &theta, a, &err), e);
  CHECK_OK(lobe_images(lobe_brdf_fn, &two, R, 1, &theta, c, &err), e);
  CHECK_OK(lobe_images(lobe_brdf_fn, &other, R, 1, &theta, d, &err), e);
  CHECK(memcmp(a, c, sizeof a) == 0);
  CHECK(lobe_l1_error(R * R, a, d) > 0.0);
  nbrdf_brdf_destroy(b);
}

int main(void) {
  RUN(test_conductor_lobe_albedo_matches_sampler);
  RUN(test_layered_lobe_is_deterministic);
  return testing_finish();
}
