/* The pdf proxy of Eq. 6 (src/model/proxy.c): sampler against pdf, pdf
 * normalisation by quadrature, and its limits. */
#include <math.h>

#include "core/rng.h"
#include "model/proxy.h"
#include "nbrdf/model.h"
#include "testing.h"

/* ∫ pdf dω by the midpoint rule in polar coordinates (θ, φ) about `pole`, over
 * θ ∈ [0, theta_max]. About −ωi for the whole sphere: the Gaussian lobe's
 * density has an integrable 1/θ singularity at ωo = −ωi (every h with ωi·h = 0
 * reflects there), which sin θ dθ cancels when θ is measured from it. */
static double integrate(double (*pdf)(double, double, vec3, vec3), double sigma, double w, vec3 wi,
                        vec3 pole, double theta_max, int nt, int np) {
  vec3 t, b;
  v3_basis(pole, &t, &b);
  double sum = 0.0, dt = theta_max / nt, dp = 2 * M_PI / np;
  for (int i = 0; i < nt; i++) {
    double th = (i + 0.5) * dt, row = 0.0;
    for (int j = 0; j < np; j++) {
      vec3 l = v3_from_spherical(th, (j + 0.5) * dp);
      vec3 wo = v3_add(v3_add(v3_scale(t, l.x), v3_scale(b, l.y)), v3_scale(pole, l.z));
      row += pdf(sigma, w, wi, wo);
    }
    sum += row * sin(th);
  }
  return sum * dt * dp;
}

static double mixture(double sigma, double w, vec3 wi, vec3 wo) {
  return model_proxy_pdf(sigma, w, wi, wo);
}
static double gaussian_sphere(double sigma, double w, vec3 wi, vec3 wo) {
  (void)w;
  return model_proxy_gaussian_pdf_sphere(sigma, wi, wo);
}
static double gaussian_lower(double sigma, double w, vec3 wi, vec3 wo) {
  (void)w;
  return wo.z < 0.0 ? model_proxy_gaussian_pdf_sphere(sigma, wi, wo) : 0.0;
}

/* The Gaussian lobe integrates to 1 over the sphere; over the upper hemisphere
 * the mixture integrates to 1 − (1 − w) · (mass below the horizon). */
static void test_normalisation(void) {
  const double sigmas[] = {0.1, 0.3, 1.0, 5.0};
  const double thetas[] = {0.0, 45.0, 80.0};
  for (int s = 0; s < 4; s++) {
    for (int t = 0; t < 3; t++) {
      vec3 wi = v3_from_spherical(thetas[t] * M_PI / 180.0, 0.3);
      double sphere = integrate(gaussian_sphere, sigmas[s], 0.0, wi, v3_neg(wi), M_PI, 600, 300);
      CHECK_MSG(fabs(sphere - 1.0) < 1e-4, "sigma %g theta_i %g: sphere integral %.6f", sigmas[s],
                thetas[t], sphere);
      double lost = integrate(gaussian_lower, sigmas[s], 0.0, wi, v3_neg(wi), M_PI, 600, 300);
      double upper = integrate(mixture, sigmas[s], 0.25, wi, v3(0, 0, 1), M_PI / 2, 600, 300);
      CHECK_MSG(fabs(upper - (1.0 - 0.75 * lost)) < 1e-3,
                "sigma %g theta_i %g: upper integral %.6f, lost mass %.6f", sigmas[s], thetas[t],
                upper, lost);
      if (thetas[t] == 0.0 && sigmas[s] <= 0.1) CHECK(lost < 1e-6);
      if (thetas[t] == 80.0) CHECK(lost > 0.01); /* grazing: some reflections go below */
    }
  }
}

/* Histogram of 400k samples in 8 × 16 (cos θ, φ) cells against the pdf
 * integrated over each cell; the fraction of lost samples against the lost mass. */
static void test_sampler_matches_pdf(void) {
  enum { NZ = 8, NP = 16, N = 400000 };
  const double sigma = 0.35, w = 0.3;
  vec3 wi = v3_from_spherical(50.0 * M_PI / 180.0, 0.0);
  static double count[NZ][NP];
  core_rng rng;
  core_rng_init(&rng, 11, 0);
  int invalid = 0;
  for (int k = 0; k < N; k++) {
    vec3 wo;
    double pdf;
    double u0 = core_rng_uniform(&rng), u1 = core_rng_uniform(&rng), u2 = core_rng_uniform(&rng);
    if (!model_proxy_sample(sigma, w, wi, u0, u1, u2, &wo, &pdf)) {
      invalid++;
      continue;
    }
    CHECK_REL(pdf, model_proxy_pdf(sigma, w, wi, wo), 1e-12, 0.0);
    double phi = atan2(wo.y, wo.x);
    if (phi < 0) phi += 2 * M_PI;
    int iz = (int)(wo.z * NZ), ip = (int)(phi / (2 * M_PI) * NP);
    count[iz < NZ ? iz : NZ - 1][ip < NP ? ip : NP - 1] += 1.0;
  }
  double worst = 0.0, total = 0.0;
  for (int iz = 0; iz < NZ; iz++) {
    for (int ip = 0; ip < NP; ip++) {
      /* Cell probability: midpoint rule on a 24 × 24 sub-grid in (z, φ), dω = dz dφ. */
      double p = 0.0, dz = 1.0 / NZ / 24, dp = 2 * M_PI / NP / 24;
      for (int a = 0; a < 24; a++) {
        for (int b = 0; b < 24; b++) {
          double z = (iz + (a + 0.5) / 24) / NZ, phi = (ip + (b + 0.5) / 24) * 2 * M_PI / NP;
          double r = sqrt(1 - z * z);
          p += model_proxy_pdf(sigma, w, wi, v3(r * cos(phi), r * sin(phi), z)) * dz * dp;
        }
      }
      total += p;
      double expected = p * N, dev = fabs(count[iz][ip] - expected) / sqrt(expected + 1.0);
      if (dev > worst) worst = dev;
    }
  }
  CHECK_MSG(worst < 5.0, "worst cell deviates by %.2f standard deviations", worst);
  double lost = 1.0 - total;
  CHECK_MSG(fabs((double)invalid / N - lost) < 5.0 * sqrt(lost / N) + 2e-3,
            "lost fraction %.5f vs lost mass %.5f", (double)invalid / N, lost);
}

static void test_limits(void) {
  core_rng rng;
  core_rng_init(&rng, 5, 0);
  vec3 wi = v3_from_spherical(0.6, 1.0), mirror = v3(-wi.x, -wi.y, wi.z);
  /* σ → its floor: every Gaussian sample is (almost) the mirror direction. */
  for (int k = 0; k < 1000; k++) {
    vec3 wo;
    double pdf;
    int ok = model_proxy_sample(MODEL_PROXY_SIGMA_MIN, 0.0, wi, core_rng_uniform(&rng),
                                core_rng_uniform(&rng), core_rng_uniform(&rng), &wo, &pdf);
    CHECK(ok);
    CHECK(acos(fmin(1.0, v3_dot(wo, mirror))) < 0.012);
    CHECK(pdf > 1.0); /* far above Lambert's 1/π */
  }
  /* w = 1: exactly Lambert; w = 0: exactly the Gaussian lobe. */
  for (int k = 0; k < 100; k++) {
    vec3 wo = v3_from_spherical(acos(core_rng_uniform(&rng)), 2 * M_PI * core_rng_uniform(&rng));
    CHECK_REL(model_proxy_pdf(0.2, 1.0, wi, wo), wo.z / M_PI, 1e-14, 0.0);
    CHECK_REL(model_proxy_pdf(0.2, 0.0, wi, wo), model_proxy_gaussian_pdf(0.2, wi, wo), 1e-14, 0.0);
    /* σ → ∞: the projected half vector is uniform on the disk, p(h) = cos θh / π. */
    vec3 h = v3_normalize(v3_add(wi, wo));
    CHECK_REL(model_proxy_gaussian_pdf(1e4, wi, wo), h.z / M_PI / (4 * v3_dot(wo, h)), 1e-6, 0.0);
  }
  /* Below the horizon: pdf 0, never NaN. */
  CHECK(model_proxy_pdf(0.2, 0.5, wi, v3(0.0, 0.0, -1.0)) == 0.0);
  CHECK(model_proxy_pdf(0.2, 0.5, v3(1.0, 0.0, 0.0), v3(0.0, 0.0, 1.0)) == 0.0);
}

static void test_public_wrappers(void) {
  double wi[3] = {0.0, 0.6, 0.8}, u[3] = {0.7, 0.25, 0.5}, wo[3], pdf;
  CHECK(nbrdf_proxy_sample(0.3, 0.2, wi, u, wo, &pdf) == 1);
  CHECK_REL(pdf, nbrdf_proxy_pdf(0.3, 0.2, wi, wo), 1e-12, 0.0);
  CHECK_NEAR(wo[0] * wo[0] + wo[1] * wo[1] + wo[2] * wo[2], 1.0, 1e-12);
}

int main(void) {
  RUN(test_normalisation);
  RUN(test_sampler_matches_pdf);
  RUN(test_limits);
  RUN(test_public_wrappers);
  return testing_finish();
}
