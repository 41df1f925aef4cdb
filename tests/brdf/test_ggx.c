#include "brdf/ggx.h"
#include "core/rng.h"
#include "testing.h"

/* ∫ D(m) cos θm dm over the hemisphere = 1 (the projected microfacet area is
 * the macro area). Trapezoid rule in θ on a mesh graded towards θ = 0, fine
 * enough for α = 1e-3. */
static void test_d_normalised(void) {
  const double alphas[] = {1e-3, 0.01, 0.1, 0.5, 1.0};
  for (int a = 0; a < 5; a++) {
    const int n = 40000;
    double sum = 0.0, prev_theta = 0.0, prev_g = 0.0; /* the integrand is 0 at θ = 0 */
    for (int k = 1; k <= n; k++) {
      double s = (double)k / n, theta = 0.5 * M_PI * s * s * s;
      vec3 m = v3_from_spherical(theta, 0.3);
      double g = brdf_ggx_d(alphas[a], m) * cos(theta) * sin(theta);
      sum += 0.5 * (theta - prev_theta) * (g + prev_g);
      prev_theta = theta;
      prev_g = g;
    }
    CHECK_NEAR(2.0 * M_PI * sum, 1.0, 1e-4);
  }
}

/* Closed form at the pole and Λ against its textbook form. */
static void test_d_lambda_values(void) {
  /* D(z) = 1 / (π α²). */
  CHECK_REL(brdf_ggx_d(0.5, v3(0, 0, 1)), 1.0 / (M_PI * 0.25), 1e-14, 0);
  /* θ = 60°: tan² = 3; α = 0.5: Λ = (√(1 + 0.75) − 1) / 2. */
  vec3 w = v3_from_spherical(M_PI / 3.0, 1.0);
  CHECK_REL(brdf_ggx_lambda(0.5, w), (sqrt(1.75) - 1.0) / 2.0, 1e-12, 0);
  CHECK_REL(brdf_ggx_g2(0.5, w, w), 1.0 / (1.0 + (sqrt(1.75) - 1.0)), 1e-12, 0);
  /* Seen from below, Λ is the same (the interface is symmetric). */
  CHECK_REL(brdf_ggx_lambda(0.5, v3_flip_z(w)), brdf_ggx_lambda(0.5, w), 1e-15, 0);
  /* Small α keeps its digits: Λ ≈ α² tan²θ / 4. */
  CHECK_REL(brdf_ggx_lambda(1e-3, w), 1e-6 * 3.0 / 4.0, 1e-6, 0);
  /* Grazing: finite and in (0, 1]. */
  vec3 g = v3_from_spherical(89.9 * M_PI / 180.0, 0.0);
  double g1 = brdf_ggx_g1(0.01, g);
  CHECK(isfinite(g1) && g1 > 0.0 && g1 <= 1.0);
  CHECK(brdf_ggx_g1(1.0, v3(1, 0, 0)) == 0.0);
}

/* Histogram of sampled visible normals over (θ, φ) cells against the pdf's
 * integral over each cell (midpoint rule on a sub-grid); the tolerance is
 * 5 standard deviations of a cell count plus the quadrature error. */
static void check_vndf_histogram(double alpha, vec3 w, uint64_t seed) {
  enum { NT = 12, NP = 12, SUB = 32 };
  const int n = 120000;
  static int hist[NT][NP];
  for (int i = 0; i < NT; i++)
    for (int j = 0; j < NP; j++)
      hist[i][j] = 0;
  core_rng rng;
  core_rng_init(&rng, seed, 0);
  int fails = 0;
  for (int s = 0; s < n; s++) {
    vec3 m;
    double u1 = core_rng_uniform(&rng), u2 = core_rng_uniform(&rng);
    if (!brdf_ggx_sample_vndf(alpha, w, u1, u2, &m)) {
      fails++;
      continue;
    }
    CHECK_NEAR(v3_length(m), 1.0, 1e-12);
    /* cells uniform in cos θ and φ */
    int i = (int)((1.0 - m.z) * NT), j = (int)((atan2(m.y, m.x) + M_PI) / (2 * M_PI) * NP);
    if (i >= NT) i = NT - 1;
    if (j >= NP) j = NP - 1;
    hist[i][j]++;
  }
  CHECK(fails == 0);
  double total = 0.0;
  int bad = 0;
  for (int i = 0; i < NT; i++)
    for (int j = 0; j < NP; j++) {
      double integral = 0.0;
      for (int a = 0; a < SUB; a++)
        for (int b = 0; b < SUB; b++) {
          double c = 1.0 - (i + (a + 0.5) / SUB) / NT;
          double phi = -M_PI + 2 * M_PI * (j + (b + 0.5) / SUB) / NP;
          double st = sqrt(fmax(0.0, 1.0 - c * c));
          vec3 m = v3(st * cos(phi), st * sin(phi), c);
          integral += brdf_ggx_vndf_pdf(alpha, w, m);
        }
      integral *= (1.0 / NT) * (2 * M_PI / NP) / (SUB * SUB);
      total += integral;
      double expected = n * integral;
      if (fabs(hist[i][j] - expected) > 5.0 * sqrt(expected) + 0.01 * expected + 2.0) {
        bad++;
        fprintf(stderr, "alpha %g cell (%d,%d): %d samples, expected %.1f\n", alpha, i, j,
                hist[i][j], expected);
      }
    }
  CHECK_MSG(bad == 0, "alpha %g: %d cells off", alpha, bad);
  /* The visible normals' density is normalised: ∫ D_ω(m) dm = 1. */
  CHECK_NEAR(total, 1.0, 0.01);
}

static void test_vndf_sampling_matches_pdf(void) {
  check_vndf_histogram(0.3, v3_from_spherical(60 * M_PI / 180, 0.4), 1);
  check_vndf_histogram(1.0, v3_from_spherical(85 * M_PI / 180, 2.0), 2);
  check_vndf_histogram(0.6, v3(0, 0, 1), 3);
  /* From below, the sampled normals are those visible from the flipped side. */
  check_vndf_histogram(0.5, v3_flip_z(v3_from_spherical(40 * M_PI / 180, 1.0)), 4);
}

/* Tiny α at grazing: samples stay finite and unit. */
static void test_vndf_extremes(void) {
  core_rng rng;
  core_rng_init(&rng, 9, 0);
  const double alphas[] = {1e-3, 0.01, 1.0};
  for (int a = 0; a < 3; a++)
    for (int s = 0; s < 20000; s++) {
      vec3 w = v3_from_spherical(89.9 * M_PI / 180, 0.0), m;
      double u1 = core_rng_uniform(&rng), u2 = core_rng_uniform(&rng);
      if (!brdf_ggx_sample_vndf(alphas[a], w, u1, u2, &m)) continue;
      double pdf = brdf_ggx_vndf_pdf(alphas[a], w, m);
      if (!(v3_is_finite(m) && fabs(v3_length(m) - 1.0) < 1e-12 && m.z > 0.0 && isfinite(pdf))) {
        CHECK_MSG(0, "alpha %g: bad normal (%g, %g, %g) pdf %g", alphas[a], m.x, m.y, m.z, pdf);
        return;
      }
    }
}

int main(void) {
  RUN(test_d_normalised);
  RUN(test_d_lambda_values);
  RUN(test_vndf_sampling_matches_pdf);
  RUN(test_vndf_extremes);
  return testing_finish();
}
