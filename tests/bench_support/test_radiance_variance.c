/* The estimators of bench_sampling (src/bench/support/radiance_variance.c): every
 * strategy is unbiased for a known integral (its sampler draws the density it
 * reports), and the variance ordering holds where it must: a BRDF shaped like
 * its proxy is integrated exactly by proxy sampling, and a GGX conductor is
 * integrated better by GGX sampling than by cosine sampling. (The proxy pdf's
 * normalisation is tests/model/test_proxy.c's.) */
#include <math.h>
#include <string.h>

#include "support/radiance_variance.h"
#include "model/proxy.h"
#include "testing.h"

static double furnace(void *user, vec3 wi) {
  (void)user, (void)wi;
  return 1.0;
}

/* f(ωi, ωo) cos θi = proxy pdf of ωi given ωo: ∫ f cos θi dωi = 1 − lost mass. */
typedef struct proxy_shaped {
  double sigma, w;
} proxy_shaped;

static nbrdf_status proxy_shaped_fn(void *user, size_t n, const nbrdf_query *q, double *f,
                                    nbrdf_error *err) {
  (void)err;
  const proxy_shaped *p = user;
  for (size_t k = 0; k < n; k++) {
    vec3 wi = v3(q[k].wi[0], q[k].wi[1], q[k].wi[2]), wo = v3(q[k].wo[0], q[k].wo[1], q[k].wo[2]);
    f[k] = model_proxy_pdf(p->sigma, p->w, wo, wi) / wi.z;
  }
  return NBRDF_OK;
}

static bench_is_setup setup_of(lobe_fn fn, void *user) {
  bench_is_setup s = {fn, user, furnace, NULL, 200, 2, {16, 64}, 7};
  return s;
}

static void test_proxy_shaped_brdf(void) {
  /* A narrow lobe at normal view: no reflection falls below the horizon. */
  proxy_shaped p = {0.08, 0.05};
  bench_is_lobe lobe = {p.sigma, p.w, 0.3};
  bench_is_setup s = setup_of(proxy_shaped_fn, &p);
  bench_is_result r;
  nbrdf_error err = {0}, *e = &err;
  CHECK_OK(bench_is_variance(&s, &lobe, v3(0, 0, 1), 1, &r, &err), e);
  CHECK(r.lost[BENCH_IS_PROXY] == 0.0);
  CHECK_NEAR(r.mean[BENCH_IS_PROXY], 1.0, 1e-9);
  CHECK(r.var[BENCH_IS_PROXY][1] < 1e-20);
  CHECK_NEAR(r.radiance, 1.0, 1e-9);
  for (int k = 0; k < 2; k++) {
    /* A lobe of σ = 0.08 covers ~2 % of the cosine-weighted hemisphere. */
    CHECK_MSG(r.var[BENCH_IS_COSINE][k] > 0.1, "cosine variance %g at N %d",
              r.var[BENCH_IS_COSINE][k], s.counts[k]);
    CHECK(r.var[BENCH_IS_MIX][k] < r.var[BENCH_IS_COSINE][k]);
  }
  /* Four times the samples, a quarter of the variance. */
  double ratio = r.var[BENCH_IS_COSINE][1] / r.var[BENCH_IS_COSINE][0];
  CHECK_MSG(ratio > 0.15 && ratio < 0.4, "variance ratio N 64 / N 16: %g", ratio);
  for (int t = 0; t < BENCH_IS_COUNT; t++) {
    double se = sqrt(r.var[t][1] / s.reps);
    CHECK_MSG(fabs(r.mean[t] - 1.0) < 5 * se + 1e-9, "%s: mean %.5f +- %.5f, want 1",
              bench_is_strategy_name((bench_is_strategy)t), r.mean[t], se);
  }
}

static void test_ggx_conductor(void) {
  nbrdf_brdf *b = NULL;
  nbrdf_error err = {0}, *e = &err;
  CHECK_OK(nbrdf_brdf_create_conductor(0.1, 0.9, &b, &err), e);
  if (!b) return;
  lobe_brdf lb = {b, NBRDF_EVAL_OPTIONS_DEFAULT};
  bench_is_setup s = setup_of(lobe_brdf_fn, &lb);
  const double theta = 40.0 * M_PI / 180.0;
  bench_is_lobe lobe = {0.2, 0.1, 0.1};
  bench_is_result r;
  CHECK_OK(bench_is_variance(&s, &lobe, v3(sin(theta), 0, cos(theta)), 2, &r, &err), e);
  double rho = 0, rho_se = 0;
  CHECK_OK(nbrdf_brdf_albedo(b, theta, 1 << 18, 3, &rho, &rho_se, &err), e);
  CHECK_MSG(r.var[BENCH_IS_GGX][1] < 0.1 * r.var[BENCH_IS_COSINE][1], "ggx %g vs cosine %g",
            r.var[BENCH_IS_GGX][1], r.var[BENCH_IS_COSINE][1]);
  for (int t = 0; t < BENCH_IS_COUNT; t++) {
    double se = sqrt(r.var[t][1] / s.reps + rho_se * rho_se);
    CHECK_MSG(fabs(r.mean[t] - rho) < 5 * se, "%s: mean %.5f +- %.5f, albedo %.5f",
              bench_is_strategy_name((bench_is_strategy)t), r.mean[t], se, rho);
  }
  nbrdf_brdf_destroy(b);
}

static void test_pdf_matches_sampler(void) {
  bench_is_lobe lobe = {0.3, 0.25, 0.4};
  vec3 wo = v3_from_spherical(1.1, 0.7);
  for (int t = 0; t < BENCH_IS_COUNT; t++)
    for (int k = 0; k < 200; k++) {
      double u[3] = {(k % 10 + 0.5) / 10, ((k / 10) % 5 + 0.3) / 5, (k / 50 + 0.6) / 4};
      vec3 wi;
      double pdf = bench_is_sample((bench_is_strategy)t, &lobe, wo, u, &wi);
      if (pdf > 0.0) CHECK_REL(pdf, bench_is_pdf((bench_is_strategy)t, &lobe, wo, wi), 1e-9, 0.0);
    }
}

static void test_bad_arguments(void) {
  bench_is_setup s = setup_of(proxy_shaped_fn, NULL);
  s.reps = 1;
  bench_is_lobe lobe = {0.3, 0.25, 0.4};
  bench_is_result r;
  nbrdf_error err = {0}, *e = &err;
  CHECK_FAILS(bench_is_variance(&s, &lobe, v3(0, 0, 1), 0, &r, &err), NBRDF_ERR_ARGUMENT, e,
              "reps");
}

int main(void) {
  RUN(test_proxy_shaped_brdf);
  RUN(test_ggx_conductor);
  RUN(test_pdf_matches_sampler);
  RUN(test_bad_arguments);
  return testing_finish();
}
