#include "brdf/conductor.h"
#include "bsdf_check.h"

static brdf_bsdf conductor(double alpha, double r0) {
  return (brdf_bsdf){.kind = BSDF_CONDUCTOR, .conductor = {alpha, r0}};
}

static void test_closed_forms(void) {
  brdf_bsdf_conductor c = {0.5, 0.04};
  /* Normal incidence, wo = wi = z: h = z, D = 1/(π α²) = 1/(0.25 π), G2 = 1,
   * F = R0 = 0.04: f = 0.04 / (4 · 0.25 π) = 0.04 / π = 0.0127324. */
  CHECK_REL(brdf_bsdf_conductor_eval(&c, v3(0, 0, 1), v3(0, 0, 1)), 0.04 / M_PI, 1e-12, 0);
  /* wo at θ = 60°, φ = 0 and wi at θ = 60°, φ = 180°: h = z, cos θd = 0.5,
   * D = 1/(0.25 π); Λ(60°) = (√(1 + 0.25·3) − 1)/2 = 0.161438, G2 = 1/(1 + 2Λ)
   * = 0.755929; F = 0.04 + 0.96·0.5⁵ = 0.07; f = D G2 F / (4·0.5·0.5)
   * = 1.273240 · 0.755929 · 0.07 / 1 = 0.0673735. */
  vec3 wo = v3_from_spherical(M_PI / 3, 0), wi = v3_from_spherical(M_PI / 3, M_PI);
  double lambda = (sqrt(1.75) - 1.0) / 2.0;
  CHECK_REL(brdf_bsdf_conductor_eval(&c, wo, wi), 1.0 / (0.25 * M_PI) / (1 + 2 * lambda) * 0.07,
            1e-12, 0);
  CHECK_NEAR(brdf_bsdf_conductor_eval(&c, wo, wi), 0.0673735, 1e-7);
  /* Below the surface: nothing. */
  CHECK(brdf_bsdf_conductor_eval(&c, v3_flip_z(wo), wi) == 0.0);
}

static void test_reciprocity(void) {
  core_rng rng;
  core_rng_init(&rng, 4, 0);
  brdf_bsdf_conductor c = {0.2, 0.6};
  for (int k = 0; k < 1000; k++) {
    vec3 a = v3_from_spherical(acos(core_rng_uniform(&rng)), 2 * M_PI * core_rng_uniform(&rng));
    vec3 b = v3_from_spherical(acos(core_rng_uniform(&rng)), 2 * M_PI * core_rng_uniform(&rng));
    double fab = brdf_bsdf_conductor_eval(&c, a, b), fba = brdf_bsdf_conductor_eval(&c, b, a);
    if (fabs(fab - fba) > 1e-12 * fab) {
      CHECK_MSG(0, "f(a, b) = %.15g, f(b, a) = %.15g", fab, fba);
      return;
    }
  }
}

static void test_sampler(void) {
  brdf_bsdf b = conductor(0.3, 0.5);
  check_sampler("conductor a=0.3 50deg", &b, v3_from_spherical(50 * M_PI / 180, 0.2), BSDF_RADIANCE,
                BSDF_ALL, 200000, 1);
  b = conductor(1.0, 0.9);
  check_sampler("conductor a=1 80deg", &b, v3_from_spherical(80 * M_PI / 180, 1.0), BSDF_RADIANCE,
                BSDF_ALL, 200000, 2);
  b = conductor(0.6, 0.1);
  check_sampler("conductor a=0.6 0deg", &b, v3(0, 0, 1), BSDF_RADIANCE, BSDF_ALL, 200000, 3);
}

/* R0 = 1, α = 0.01: a nearly perfect mirror; its albedo (mean sample weight)
 * is G2/G1 ≈ 1 at normal incidence, and below 1 everywhere. */
static void test_albedo(void) {
  core_rng rng;
  core_rng_init(&rng, 5, 0);
  brdf_bsdf mirror = conductor(0.01, 1.0), rough = conductor(1.0, 1.0);
  const double thetas[] = {0.0, 45.0, 80.0, 89.9};
  for (int t = 0; t < 4; t++) {
    vec3 wo = v3_from_spherical(thetas[t] * M_PI / 180, 0);
    double sm = 0.0, sr = 0.0;
    const int n = 20000;
    for (int s = 0; s < n; s++) {
      brdf_bsdf_sample bs;
      if (brdf_bsdf_sample_dir(&mirror, wo, BSDF_RADIANCE, BSDF_ALL, &rng, &bs)) sm += bs.weight;
      if (brdf_bsdf_sample_dir(&rough, wo, BSDF_RADIANCE, BSDF_ALL, &rng, &bs)) sr += bs.weight;
    }
    CHECK(sm / n <= 1.0 && sr / n <= 1.0);
    if (thetas[t] < 50) CHECK_NEAR(sm / n, 1.0, 1e-3);
    /* A white GGX conductor with α = 1 loses most of its energy without
     * multiple scattering: at normal incidence half of the (cosine-
     * distributed) visible normals reflect below the horizon, and G2 < 1
     * takes more: ≈ 0.30. */
    CHECK_MSG(sr / n > (thetas[t] < 50 ? 0.25 : 0.05), "theta %g: rough white albedo %g", thetas[t],
              sr / n);
  }
}

static void test_extremes_finite(void) {
  core_rng rng;
  core_rng_init(&rng, 6, 0);
  const double alphas[] = {1e-3, 0.01, 1.0};
  for (int a = 0; a < 3; a++) {
    brdf_bsdf b = conductor(alphas[a], 0.0);
    vec3 wo = v3_from_spherical(89.9 * M_PI / 180, 0.0);
    for (int s = 0; s < 5000; s++) {
      brdf_bsdf_sample bs;
      if (!brdf_bsdf_sample_dir(&b, wo, BSDF_RADIANCE, BSDF_ALL, &rng, &bs)) continue;
      double f = brdf_bsdf_eval(&b, wo, bs.wi, BSDF_RADIANCE, NULL);
      double p = brdf_bsdf_pdf(&b, wo, bs.wi, BSDF_RADIANCE, BSDF_ALL);
      if (!(isfinite(f) && isfinite(p) && isfinite(bs.weight) && bs.weight <= 1.0 + 1e-12)) {
        CHECK_MSG(0, "alpha %g: f %g pdf %g weight %g", alphas[a], f, p, bs.weight);
        break;
      }
    }
  }
}

int main(void) {
  RUN(test_closed_forms);
  RUN(test_reciprocity);
  RUN(test_sampler);
  RUN(test_albedo);
  RUN(test_extremes_finite);
  return testing_finish();
}
