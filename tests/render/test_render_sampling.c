/* The renderer's sampling: the proxy mixture draws directions with exactly
 * the density it reports (histogram against the integrated pdf), the
 * environment's tabulated sampler is normalised, and the power-heuristic
 * MIS weights of two strategies sum to one. */
#include <stdlib.h>

#include "core/rng.h"
#include "render/env.h"
#include "render/render_sampling.h"
#include "testing.h"

#define NT 12 /* bins in cos θo */
#define NP 24 /* bins in φo */

static void test_power_heuristic(void) {
  core_rng rng;
  core_rng_init(&rng, 3, 0);
  for (int k = 0; k < 1000; k++) {
    double a = core_rng_uniform(&rng) * pow(10.0, 6.0 * core_rng_uniform(&rng) - 3.0);
    double b = core_rng_uniform(&rng) * pow(10.0, 6.0 * core_rng_uniform(&rng) - 3.0);
    CHECK_NEAR(render_power_heuristic(a, b) + render_power_heuristic(b, a), 1.0, 1e-12);
  }
  CHECK(render_power_heuristic(0.0, 2.0) == 0.0 && render_power_heuristic(2.0, 0.0) == 1.0);
  CHECK(render_power_heuristic(0.0, 0.0) == 0.0);
  CHECK(render_power_heuristic(INFINITY, 1.0) == 1.0 &&
        render_power_heuristic(1.0, INFINITY) == 0.0);
  CHECK_NEAR(render_power_heuristic(1e200, 1e200), 0.5, 0.0);
}

/* Bin of a direction on the upper hemisphere, by (cos θ, φ). */
static int bin_of(vec3 d) {
  int t = (int)(d.z * NT), p = (int)((atan2(d.y, d.x) + M_PI) / (2.0 * M_PI) * NP);
  t = t < 0 ? 0 : (t >= NT ? NT - 1 : t);
  p = p < 0 ? 0 : (p >= NP ? NP - 1 : p);
  return t * NP + p;
}

static void test_proxy_mixture(void) {
  const float sigma[3] = {0.25f, 0.5f, 0.9f}, w[3] = {0.2f, 0.6f, 0.0f};
  for (int channels = 1; channels <= 3; channels += 2) {
    vec3 wi = v3_from_spherical(40.0 * M_PI / 180.0, 0.3);
    /* Expected mass per bin: the pdf integrated with a 16 x 16 midpoint rule
     * in (cos θ, φ), where dω = d(cos θ) dφ. */
    static double expect[NT * NP];
    double total = 0.0;
    for (int b = 0; b < NT * NP; b++) {
      int t = b / NP, p = b % NP;
      double m = 0.0;
      for (int i = 0; i < 16; i++)
        for (int j = 0; j < 16; j++) {
          double c = (t + (i + 0.5) / 16.0) / NT;
          double phi = (p + (j + 0.5) / 16.0) / NP * 2.0 * M_PI - M_PI;
          vec3 wo = v3(sqrt(1 - c * c) * cos(phi), sqrt(1 - c * c) * sin(phi), c);
          m += render_proxy_mix_pdf(channels, sigma, w, wi, wo);
        }
      expect[b] = m / 256.0 * (1.0 / NT) * (2.0 * M_PI / NP);
      total += expect[b];
    }
    int n = 400000, valid = 0, pdf_ok = 1;
    static double count[NT * NP];
    for (int b = 0; b < NT * NP; b++)
      count[b] = 0;
    core_rng rng;
    core_rng_init(&rng, 11, (uint64_t)channels);
    for (int k = 0; k < n; k++) {
      double u[4] = {core_rng_uniform(&rng), core_rng_uniform(&rng), core_rng_uniform(&rng),
                     core_rng_uniform(&rng)};
      vec3 wo;
      double pdf;
      if (!render_proxy_mix_sample(channels, sigma, w, wi, u, &wo, &pdf)) continue;
      valid++;
      double want = render_proxy_mix_pdf(channels, sigma, w, wi, wo);
      if (!(fabs(pdf - want) <= 1e-9 * want)) pdf_ok = 0;
      count[bin_of(wo)]++;
    }
    CHECK_MSG(pdf_ok, "%d channels: the sampler's pdf differs from render_proxy_mix_pdf", channels);
    /* The lost mass (reflections below the horizon) is the pdf's missing mass. */
    CHECK_NEAR((double)valid / n, total, 4e-3);
    double chi2 = 0.0;
    int dof = 0;
    for (int b = 0; b < NT * NP; b++) {
      double e = expect[b] * n;
      if (e < 5.0) continue;
      chi2 += (count[b] - e) * (count[b] - e) / e;
      dof++;
    }
    /* Mean dof, standard deviation sqrt(2 dof): 6 sigmas above is a failure. */
    printf("proxy mixture, %d channels: chi2 %.1f over %d bins\n", channels, chi2, dof);
    CHECK_MSG(chi2 < dof + 6.0 * sqrt(2.0 * dof), "%d channels: chi2 %.1f over %d bins", channels,
              chi2, dof);
    CHECK(dof > 100);
  }
}

/* E[g / pdf] over the environment's samples equals ∫ g dω, and the pdf of
 * a sampled direction is what render_env_pdf reports. */
static void test_env_sampling(void) {
  nbrdf_render_options o = NBRDF_RENDER_OPTIONS_DEFAULT;
  for (int kind = 0; kind < 2; kind++) {
    o.env = kind == 0 ? NBRDF_ENV_SKY : NBRDF_ENV_CONSTANT;
    render_env *env = NULL;
    nbrdf_error err;
    CHECK_OK(render_env_create(&o, &env, &err), &err);
    if (!env) return;
    core_rng rng;
    core_rng_init(&rng, 5, (uint64_t)kind);
    int n = 200000, pdf_ok = 1;
    double s1 = 0, s1sq = 0, s2 = 0, s2sq = 0;
    for (int k = 0; k < n; k++) {
      vec3 d;
      double pdf = render_env_sample(env, core_rng_uniform(&rng), core_rng_uniform(&rng), &d);
      if (!(pdf > 0.0)) continue;
      if (!(fabs(render_env_pdf(env, d) - pdf) <= 1e-6 * pdf)) pdf_ok = 0;
      double g1 = 1.0 / pdf, g2 = fmax(d.y, 0.0) / pdf;
      s1 += g1, s1sq += g1 * g1, s2 += g2, s2sq += g2 * g2;
    }
    CHECK(pdf_ok);
    double m1 = s1 / n, m2 = s2 / n;
    double e1 = sqrt((s1sq / n - m1 * m1) / n), e2 = sqrt((s2sq / n - m2 * m2) / n);
    CHECK_MSG(fabs(m1 - 4.0 * M_PI) < 5.0 * e1 + 1e-3, "env %d: ∫ dω = %g ± %g", kind, m1, e1);
    CHECK_MSG(fabs(m2 - M_PI) < 5.0 * e2 + 1e-3, "env %d: ∫ cos⁺ dω = %g ± %g", kind, m2, e2);
    render_env_free(env);
  }
}

int main(void) {
  RUN(test_power_heuristic);
  RUN(test_proxy_mixture);
  RUN(test_env_sampling);
  return testing_finish();
}
