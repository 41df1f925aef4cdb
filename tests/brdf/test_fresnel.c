#include "brdf/fresnel.h"
#include "testing.h"

static void test_dielectric_values(void) {
  /* Normal incidence: ((η − 1) / (η + 1))²; η = 1.5 → 0.04. */
  CHECK_REL(brdf_fresnel_dielectric(1.0, 1.5), 0.04, 1e-12, 0);
  CHECK_REL(brdf_fresnel_dielectric(-1.0, 1.5), 0.04, 1e-12, 0);
  /* 45° from outside, η = 1.5: sin θt = 0.70711 / 1.5 = 0.47140, cos θt = 0.88192;
   * r∥ = (1.5·0.70711 − 0.88192) / (1.5·0.70711 + 0.88192) = 0.17874 / 1.94258 = 0.092013,
   * r⊥ = (0.70711 − 1.5·0.88192) / (0.70711 + 1.5·0.88192) = −0.61577 / 2.02998 = −0.303337,
   * F = (0.0084665 + 0.0920134) / 2 = 0.0502399. */
  CHECK_NEAR(brdf_fresnel_dielectric(sqrt(0.5), 1.5), 0.0502399, 2e-7);
  /* Light arriving from inside at the refracted angle sees the same F. */
  CHECK_NEAR(brdf_fresnel_dielectric(-sqrt(1.0 - 0.5 / 2.25), 1.5), 0.0502399, 2e-7);
  /* Beyond the critical angle asin(1/1.5) = 41.81° inside: total reflection. */
  CHECK(brdf_fresnel_dielectric(-cos(42.0 * M_PI / 180), 1.5) == 1.0);
  CHECK(brdf_fresnel_dielectric(-cos(41.0 * M_PI / 180), 1.5) < 1.0);
  /* Index-matched: nothing reflects (except the degenerate exact grazing). */
  CHECK(brdf_fresnel_dielectric(0.3, 1.0) < 1e-15);
  CHECK(brdf_fresnel_dielectric(-0.3, 1.0) < 1e-15);
  /* Grazing from outside reflects everything. */
  CHECK_NEAR(brdf_fresnel_dielectric(0.0, 1.5), 1.0, 1e-12);
  for (double c = -1.0; c <= 1.0; c += 0.01) {
    double f = brdf_fresnel_dielectric(c, 1.33);
    CHECK(f >= 0.0 && f <= 1.0);
  }
}

static void test_schlick(void) {
  CHECK(brdf_fresnel_schlick(0.3, 1.0) == 0.3);
  CHECK(brdf_fresnel_schlick(0.3, 0.0) == 1.0);
  /* cos θd = 0.5: 0.3 + 0.7 / 32 = 0.321875. */
  CHECK_REL(brdf_fresnel_schlick(0.3, 0.5), 0.321875, 1e-15, 0);
}

static void test_refract(void) {
  vec3 wt, m = v3(0, 0, 1);
  double etap;
  /* Snell: sin θt = sin θi / η, on the other side, and reversible. */
  vec3 w = v3_from_spherical(50 * M_PI / 180, 0.7);
  CHECK(brdf_fresnel_refract(w, m, 1.5, &wt, &etap));
  CHECK(etap == 1.5);
  CHECK_NEAR(v3_length(wt), 1.0, 1e-14);
  CHECK(wt.z < 0.0);
  CHECK_NEAR(sqrt(wt.x * wt.x + wt.y * wt.y), sin(50 * M_PI / 180) / 1.5, 1e-14);
  vec3 back;
  CHECK(brdf_fresnel_refract(wt, m, 1.5, &back, &etap));
  CHECK_NEAR(etap, 1.0 / 1.5, 1e-15);
  CHECK_NEAR(v3_length(v3_sub(back, w)), 0.0, 1e-14);
  /* Total internal reflection from inside beyond 41.81°. */
  CHECK(
      !brdf_fresnel_refract(v3_flip_z(v3_from_spherical(45 * M_PI / 180, 0)), m, 1.5, &wt, &etap));
  /* Through a tilted microfacet normal. */
  vec3 mt = v3_from_spherical(20 * M_PI / 180, 2.0);
  CHECK(brdf_fresnel_refract(w, mt, 1.5, &wt, &etap));
  double ci = v3_dot(w, mt), ct = -v3_dot(wt, mt);
  CHECK_NEAR(sqrt(1 - ci * ci), 1.5 * sqrt(1 - ct * ct), 1e-13);
}

int main(void) {
  RUN(test_dielectric_values);
  RUN(test_schlick);
  RUN(test_refract);
  return testing_finish();
}
