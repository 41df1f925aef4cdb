#include "brdf/dielectric.h"
#include "bsdf_check.h"

static brdf_bsdf dielectric(double alpha, double eta) {
  return (brdf_bsdf){.kind = BSDF_DIELECTRIC, .dielectric = {alpha, eta}};
}

static void test_closed_forms(void) {
  brdf_bsdf_dielectric d = {0.5, 1.5};
  const double D = 1.0 / (M_PI * 0.25); /* D(z) for α = 0.5: 1.2732395 */
  vec3 up = v3(0, 0, 1), down = v3(0, 0, -1);
  /* Reflection at normal incidence: F = (0.5/2.5)² = 0.04, G2 = 1,
   * f = D · 0.04 / 4 = 0.0127324. */
  CHECK_REL(brdf_bsdf_dielectric_eval(&d, up, up, BSDF_RADIANCE), D * 0.04 / 4.0, 1e-12, 0);
  /* Transmission at normal incidence, wo = z outside, wi = −z inside:
   * η' = η_wi/η_wo = 1.5, m = z, (wi·m + wo·m/η')² = (−1 + 1/1.5)² = 1/9,
   * f = D (1 − 0.04) · 1 · 1 / (1/9) = 8.64 D = 11.0008 (importance mode),
   * and 8.64 D / η'² = 3.84 D = 4.88924 in radiance mode. */
  CHECK_REL(brdf_bsdf_dielectric_eval(&d, up, down, BSDF_IMPORTANCE), 8.64 * D, 1e-12, 0);
  CHECK_REL(brdf_bsdf_dielectric_eval(&d, up, down, BSDF_RADIANCE), 3.84 * D, 1e-12, 0);
  /* From inside, wo = −z, wi = z: η' = 1/1.5, (1 + (−1)·1.5)² = 1/4,
   * f = 0.96 D · 4 = 3.84 D (importance), 3.84 D · 2.25 = 8.64 D (radiance). */
  CHECK_REL(brdf_bsdf_dielectric_eval(&d, down, up, BSDF_IMPORTANCE), 3.84 * D, 1e-12, 0);
  CHECK_REL(brdf_bsdf_dielectric_eval(&d, down, up, BSDF_RADIANCE), 8.64 * D, 1e-12, 0);

  /* Oblique transmission: wo at 45° outside (φ = 0), wi its refraction
   * through the macro normal, so m = z. sin θt = 0.7071068/1.5 = 0.4714045,
   * cos θt = 0.8819171, wi = (−0.4714045, 0, −0.8819171).
   * F(45°) = 0.0502399 (test_fresnel). Λ(wo) = (√(1 + 0.25·1) − 1)/2 = 0.0590170,
   * Λ(wi) = (√(1 + 0.25·0.2857143) − 1)/2 = 0.0175492, G2 = 1/1.0765662 = 0.9288793.
   * (wi·m + wo·m/1.5)² = (−0.8819171 + 0.4714045)² = 0.1685206;
   * f = D (1 − F) G2 |wi·m||wo·m| / ((…)² |cos θo cos θi|)
   *   = 1.2732395 · 0.9497601 · 0.9288793 / 0.1685206 = 6.665464 (importance),
   * ÷ 2.25 = 2.962428 (radiance). */
  double st = sqrt(0.5) / 1.5, ct = sqrt(1.0 - st * st);
  vec3 wo = v3(sqrt(0.5), 0, sqrt(0.5)), wi = v3(-st, 0, -ct);
  CHECK_NEAR(brdf_bsdf_dielectric_eval(&d, wo, wi, BSDF_IMPORTANCE), 6.665464, 2e-6);
  CHECK_NEAR(brdf_bsdf_dielectric_eval(&d, wo, wi, BSDF_RADIANCE), 2.962428, 1e-6);
  /* Index-matched: no lobe to evaluate. */
  brdf_bsdf_dielectric matched = {0.5, 1.0};
  CHECK(brdf_bsdf_dielectric_eval(&matched, up, down, BSDF_RADIANCE) == 0.0);
  CHECK(brdf_bsdf_dielectric_pdf(&matched, up, down, BSDF_ALL) == 0.0);
}

/* Generalised reciprocity f(a, b) / η_a² = f(b, a) / η_b² (radiance mode),
 * and the adjoint relation f_importance(a, b) = f_radiance(b, a). */
static void test_reciprocity(void) {
  core_rng rng;
  core_rng_init(&rng, 11, 0);
  brdf_bsdf_dielectric d = {0.4, 1.7};
  int bad = 0, transmissions = 0;
  for (int k = 0; k < 4000; k++) {
    vec3 a = core_warp_uniform_sphere(core_rng_uniform(&rng), core_rng_uniform(&rng));
    vec3 b = core_warp_uniform_sphere(core_rng_uniform(&rng), core_rng_uniform(&rng));
    double eta_a = a.z > 0 ? 1.0 : d.eta, eta_b = b.z > 0 ? 1.0 : d.eta;
    double fab = brdf_bsdf_dielectric_eval(&d, a, b, BSDF_RADIANCE);
    double fba = brdf_bsdf_dielectric_eval(&d, b, a, BSDF_RADIANCE);
    double adj = brdf_bsdf_dielectric_eval(&d, b, a, BSDF_IMPORTANCE);
    transmissions += a.z * b.z < 0 && fab > 0;
    if (fabs(fab / (eta_a * eta_a) - fba / (eta_b * eta_b)) > 1e-10 * fab ||
        fabs(adj - fab) > 1e-10 * fab)
      if (bad++ < 3) fprintf(stderr, "f(a,b) %.15g f(b,a) %.15g adj %.15g\n", fab, fba, adj);
  }
  CHECK(bad == 0);
  CHECK(transmissions > 500);
}

static void test_sampler(void) {
  vec3 above = v3_from_spherical(50 * M_PI / 180, 0.3);
  vec3 below = v3_flip_z(v3_from_spherical(30 * M_PI / 180, 1.3));
  vec3 below_tir = v3_flip_z(v3_from_spherical(60 * M_PI / 180, -2.0));
  brdf_bsdf b = dielectric(0.3, 1.5);
  check_sampler("diel above all", &b, above, BSDF_RADIANCE, BSDF_ALL, 200000, 1);
  check_sampler("diel above T", &b, above, BSDF_IMPORTANCE, BSDF_TRANSMISSION, 100000, 2);
  check_sampler("diel above R", &b, above, BSDF_RADIANCE, BSDF_REFLECTION, 100000, 3);
  check_sampler("diel below all", &b, below, BSDF_RADIANCE, BSDF_ALL, 200000, 4);
  check_sampler("diel below TIR all", &b, below_tir, BSDF_IMPORTANCE, BSDF_ALL, 100000, 5);
  check_sampler("diel below T", &b, below, BSDF_RADIANCE, BSDF_TRANSMISSION, 100000, 6);
  b = dielectric(0.8, 2.5);
  check_sampler("diel rough 80deg", &b, v3_from_spherical(80 * M_PI / 180, 0), BSDF_RADIANCE,
                BSDF_ALL, 200000, 7);
  check_sampler("diel rough below", &b, below, BSDF_IMPORTANCE, BSDF_ALL, 200000, 8);
}

/* Energy: with importance transport (flux) the interface's R + T albedo is
 * ≤ 1 — exactly 1 minus the single-scattering masking loss, which is tiny for
 * α = 0.1 at normal incidence and large for α = 1. In radiance mode light
 * entering the coat is divided by η². */
static double mean_weight(const brdf_bsdf *b, vec3 wo, brdf_bsdf_mode mode, int n, uint64_t seed,
                          double *se) {
  core_rng rng;
  core_rng_init(&rng, seed, 0);
  double s1 = 0, s2 = 0;
  for (int k = 0; k < n; k++) {
    brdf_bsdf_sample bs;
    if (!brdf_bsdf_sample_dir(b, wo, mode, BSDF_ALL, &rng, &bs)) continue;
    s1 += bs.weight;
    s2 += bs.weight * bs.weight;
  }
  double m = s1 / n;
  *se = sqrt(fmax(0.0, s2 / n - m * m) / n);
  return m;
}

static void test_energy(void) {
  double se;
  brdf_bsdf smooth = dielectric(0.1, 1.5), rough = dielectric(1.0, 1.5);
  double e = mean_weight(&smooth, v3(0, 0, 1), BSDF_IMPORTANCE, 100000, 1, &se);
  CHECK_MSG(e <= 1.0 + 1e-12 && e > 0.995, "smooth R+T albedo %g", e);
  /* From inside, GGX's long tail matters: at α = 0.1, 1.2 % of the visible
   * normals are tilted beyond the critical angle (P(tan θm > t) =
   * 1/(1 + t²/α²), t = tan 41.8°), reflect totally, and being tilted by more
   * than 45° send the ray back through the surface: lost without multiple
   * scattering. */
  e = mean_weight(&smooth, v3(0, 0, -1), BSDF_IMPORTANCE, 100000, 2, &se);
  CHECK_MSG(e <= 1.0 + 1e-12 && e > 0.985, "smooth R+T albedo from inside %g", e);
  /* Radiance mode at normal incidence: R + T/η² = 0.04 + 0.96/2.25. */
  e = mean_weight(&smooth, v3(0, 0, 1), BSDF_RADIANCE, 100000, 3, &se);
  CHECK_NEAR(e, 0.04 + 0.96 / 2.25, 0.005);
  const double thetas[] = {0, 30, 60, 80, 89.9};
  for (int t = 0; t < 5; t++) {
    vec3 w = v3_from_spherical(thetas[t] * M_PI / 180, 0.5);
    for (int side = 0; side < 2; side++) {
      vec3 wo = side ? v3_flip_z(w) : w;
      double er = mean_weight(&rough, wo, BSDF_IMPORTANCE, 20000, 4 + t, &se);
      double es = mean_weight(&smooth, wo, BSDF_IMPORTANCE, 20000, 4 + t, &se);
      CHECK_MSG(er <= 1.0 && es <= 1.0 && er > 0.0, "theta %g side %d: albedo rough %g smooth %g",
                thetas[t], side, er, es);
    }
  }
}

static void test_index_matched(void) {
  brdf_bsdf b = dielectric(0.3, 1.0);
  core_rng rng;
  core_rng_init(&rng, 1, 0);
  brdf_bsdf_sample s;
  vec3 wo = v3_from_spherical(0.7, 0.2);
  CHECK(brdf_bsdf_sample_dir(&b, wo, BSDF_RADIANCE, BSDF_ALL, &rng, &s));
  CHECK((s.flags & BSDF_DELTA) && (s.flags & BSDF_TRANSMISSION));
  CHECK(s.weight == 1.0 && v3_length(v3_add(s.wi, wo)) == 0.0);
  CHECK(!brdf_bsdf_sample_dir(&b, wo, BSDF_RADIANCE, BSDF_REFLECTION, &rng, &s));
  CHECK(brdf_bsdf_sample_dir(&b, v3_flip_z(wo), BSDF_IMPORTANCE, BSDF_TRANSMISSION, &rng, &s));
  CHECK(s.weight == 1.0 && s.wi.z > 0.0);
}

/* Very small α, η near 1 and up to 4, grazing 89.9° from both sides, both
 * modes: nothing is NaN or infinite. */
static void test_extremes_finite(void) {
  core_rng rng;
  core_rng_init(&rng, 12, 0);
  const double alphas[] = {1e-3, 0.01, 1.0}, etas[] = {1.0 + 1e-9, 1.0001, 1.05, 2.0, 4.0};
  int bad = 0;
  for (int a = 0; a < 3; a++)
    for (int e = 0; e < 5; e++) {
      brdf_bsdf b = dielectric(alphas[a], etas[e]);
      for (int side = 0; side < 2; side++)
        for (int s = 0; s < 2000; s++) {
          vec3 wo = v3_from_spherical((s % 2 ? 89.9 : 60.0) * M_PI / 180, 0.1 * s);
          if (side) wo = v3_flip_z(wo);
          brdf_bsdf_mode mode = s % 3 ? BSDF_RADIANCE : BSDF_IMPORTANCE;
          brdf_bsdf_sample bs;
          if (!brdf_bsdf_sample_dir(&b, wo, mode, BSDF_ALL, &rng, &bs)) continue;
          double f = brdf_bsdf_eval(&b, wo, bs.wi, mode, NULL);
          double p = brdf_bsdf_pdf(&b, wo, bs.wi, mode, BSDF_ALL);
          if (!(isfinite(f) && isfinite(p) && isfinite(bs.weight) && isfinite(bs.f) &&
                isfinite(bs.pdf) && v3_is_finite(bs.wi) && bs.weight >= 0.0))
            if (bad++ < 3)
              fprintf(stderr, "alpha %g eta %.10g: f %g pdf %g weight %g\n", alphas[a], etas[e], f,
                      p, bs.weight);
        }
    }
  CHECK(bad == 0);
}

int main(void) {
  RUN(test_closed_forms);
  RUN(test_reciprocity);
  RUN(test_sampler);
  RUN(test_energy);
  RUN(test_index_matched);
  RUN(test_extremes_finite);
  return testing_finish();
}
