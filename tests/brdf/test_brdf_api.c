/* The public API of the ground truth: parameter validation with messages
 * that name the parameter, ownership, analytic values through eval. */
#include "layered_util.h"

static void test_create_rejects_bad_parameters(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  nbrdf_brdf *b = (nbrdf_brdf *)1;
  CHECK_FAILS(nbrdf_brdf_create_conductor(NAN, 0.5, &b, err), NBRDF_ERR_ARGUMENT, err,
              "alpha is NaN");
  CHECK(b == NULL);
  CHECK_FAILS(nbrdf_brdf_create_conductor(INFINITY, 0.5, &b, err), NBRDF_ERR_ARGUMENT, err,
              "alpha is infinite");
  CHECK_FAILS(nbrdf_brdf_create_conductor(-0.1, 0.5, &b, err), NBRDF_ERR_ARGUMENT, err,
              "alpha = -0.1");
  CHECK_FAILS(nbrdf_brdf_create_conductor(0.0, 0.5, &b, err), NBRDF_ERR_ARGUMENT, err,
              "alpha = 0 is outside");
  CHECK_FAILS(nbrdf_brdf_create_conductor(1.5, 0.5, &b, err), NBRDF_ERR_ARGUMENT, err,
              "alpha = 1.5");
  CHECK_FAILS(nbrdf_brdf_create_conductor(0.5, NAN, &b, err), NBRDF_ERR_ARGUMENT, err, "r0 is NaN");
  CHECK_FAILS(nbrdf_brdf_create_conductor(0.5, -0.2, &b, err), NBRDF_ERR_ARGUMENT, err,
              "r0 = -0.2");
  CHECK_FAILS(nbrdf_brdf_create_conductor(0.5, 1.01, &b, err), NBRDF_ERR_ARGUMENT, err,
              "conductor: r0 = 1.01");
  CHECK_FAILS(nbrdf_brdf_create_conductor(0.5, 0.5, NULL, err), NBRDF_ERR_ARGUMENT, err, "out");

  CHECK_FAILS(nbrdf_brdf_create_dielectric(NAN, 1.5, &b, err), NBRDF_ERR_ARGUMENT, err,
              "alpha is NaN");
  CHECK_FAILS(nbrdf_brdf_create_dielectric(0.5, 0.9, &b, err), NBRDF_ERR_ARGUMENT, err,
              "eta = 0.9");
  CHECK_FAILS(nbrdf_brdf_create_dielectric(0.5, 4.5, &b, err), NBRDF_ERR_ARGUMENT, err,
              "eta = 4.5");
  CHECK_FAILS(nbrdf_brdf_create_dielectric(0.5, -INFINITY, &b, err), NBRDF_ERR_ARGUMENT, err,
              "eta is infinite");

  nbrdf_brdf *c = conductor_or_die(0.3, 0.5);
  CHECK_FAILS(nbrdf_brdf_create_layered(NAN, 1.5, 0.5, 1, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "layered: alpha1 is NaN");
  CHECK_FAILS(nbrdf_brdf_create_layered(2.0, 1.5, 0.5, 1, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "alpha1 = 2");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, NAN, 0.5, 1, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "eta is NaN");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, 0.5, 0.5, 1, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "eta = 0.5");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, 1.5, -0.1, 1, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "albedo = -0.1");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, 1.5, 1.1, 1, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "albedo = 1.1");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, 1.5, NAN, 1, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "albedo is NaN");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, 1.5, 0.5, -1, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "sigma_t = -1");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, 1.5, 0.5, 2000, c, &b, err), NBRDF_ERR_ARGUMENT, err,
              "sigma_t = 2000");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, 1.5, 0.5, INFINITY, c, &b, err), NBRDF_ERR_ARGUMENT,
              err, "sigma_t is infinite");
  CHECK_FAILS(nbrdf_brdf_create_layered(0.3, 1.5, 0.5, 1, NULL, &b, err), NBRDF_ERR_ARGUMENT, err,
              "bottom is NULL");
  /* The accepted extremes. */
  CHECK_OK(nbrdf_brdf_create_layered(1e-3, 1.0, 0.0, 0.0, c, &b, err), err);
  nbrdf_brdf_destroy(b);
  CHECK_OK(nbrdf_brdf_create_layered(1.0, 4.0, 1.0, 1000.0, c, &b, err), err);
  nbrdf_brdf_destroy(b);
  nbrdf_brdf_destroy(c);
  nbrdf_brdf_destroy(NULL);
}

static void test_eval_rejects_bad_queries(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  nbrdf_brdf *l = layered2(0.3, 1.5, 0.3, 0.9, 0.5, 1.0);
  nbrdf_query q[3] = {query_deg(10, 0, 20, 0), query_deg(10, 0, 20, 0), query_deg(10, 0, 20, 0)};
  double f[3], se[3];
  nbrdf_eval_options o = NBRDF_EVAL_OPTIONS_DEFAULT;
  o.spp = 4;
  q[1].wi[2] = -q[1].wi[2];
  CHECK_FAILS(nbrdf_brdf_eval(l, 3, q, &o, f, se, err), NBRDF_ERR_ARGUMENT, err, "query 1: wi");
  CHECK(strstr(err->message, "z <= 0") != NULL);
  q[1] = query_deg(10, 0, 20, 0);
  q[2].wo[0] *= 1.01;
  CHECK_FAILS(nbrdf_brdf_eval(l, 3, q, &o, f, se, err), NBRDF_ERR_ARGUMENT, err, "query 2: wo");
  CHECK(strstr(err->message, "not a unit vector") != NULL);
  q[2] = query_deg(10, 0, 20, 0);
  q[0].wo[1] = NAN;
  CHECK_FAILS(nbrdf_brdf_eval(l, 3, q, &o, f, se, err), NBRDF_ERR_ARGUMENT, err, "query 0: wo");
  q[0] = query_deg(90, 0, 20, 0); /* exactly grazing: z = cos(90°) ≈ 6e-17 > 0 is allowed */
  q[0].wi[2] = 0.0;
  CHECK_FAILS(nbrdf_brdf_eval(l, 3, q, &o, f, se, err), NBRDF_ERR_ARGUMENT, err, "query 0: wi");
  q[0] = query_deg(10, 0, 20, 0);
  /* A direction within 1e-6 of unit length is accepted. */
  q[0].wi[0] *= 1.0 + 5e-7;
  CHECK_OK(nbrdf_brdf_eval(l, 3, q, &o, f, se, err), err);
  o.spp = 0;
  CHECK_FAILS(nbrdf_brdf_eval(l, 3, q, &o, f, se, err), NBRDF_ERR_ARGUMENT, err, "spp = 0");
  o.spp = 4;
  o.threads = -1;
  CHECK_FAILS(nbrdf_brdf_eval(l, 3, q, &o, f, se, err), NBRDF_ERR_ARGUMENT, err, "threads = -1");
  o.threads = 0;
  const nbrdf_brdf *many[3] = {l, NULL, l};
  CHECK_FAILS(nbrdf_brdf_eval_many(3, many, q, &o, f, se, err), NBRDF_ERR_ARGUMENT, err,
              "query 1: BRDF is NULL");
  CHECK_FAILS(nbrdf_brdf_eval(NULL, 3, q, &o, f, se, err), NBRDF_ERR_ARGUMENT, err, "NULL");
  CHECK_OK(nbrdf_brdf_eval(l, 0, NULL, &o, NULL, NULL, err), err);
  /* One walk cannot estimate its own spread. */
  o.spp = 1;
  CHECK_OK(nbrdf_brdf_eval(l, 3, q, &o, f, se, err), err);
  CHECK(isinf(se[0]) && isfinite(f[0]));

  double wi[3] = {0, 0, -1}, wo[3], w;
  CHECK_FAILS(nbrdf_brdf_sample(l, wi, 1, 0, wo, &w, err), NBRDF_ERR_ARGUMENT, err, "sample: wi");
  double rho, rse;
  CHECK_FAILS(nbrdf_brdf_albedo(l, NAN, 10, 1, &rho, &rse, err), NBRDF_ERR_ARGUMENT, err,
              "theta_i = nan");
  CHECK_FAILS(nbrdf_brdf_albedo(l, -0.1, 10, 1, &rho, &rse, err), NBRDF_ERR_ARGUMENT, err,
              "theta_i = -0.1");
  CHECK_FAILS(nbrdf_brdf_albedo(l, M_PI / 2, 10, 1, &rho, &rse, err), NBRDF_ERR_ARGUMENT, err,
              "theta_i");
  CHECK_FAILS(nbrdf_brdf_albedo(l, 0.1, 0, 1, &rho, &rse, err), NBRDF_ERR_ARGUMENT, err,
              "samples = 0");
  nbrdf_brdf_destroy(l);
}

/* The layered handle owns a copy of its bottom (ASan would flag a use after
 * free), and nests: 3 layers built from handles destroyed right away. */
static void test_bottom_is_copied(void) {
  nbrdf_brdf *c = conductor_or_die(0.2, 0.8);
  nbrdf_brdf *inner = layered_or_die(0.1, 1.5, 0.5, 1.0, c);
  nbrdf_brdf_destroy(c);
  nbrdf_brdf *outer = layered_or_die(0.3, 1.3, 0.2, 0.5, inner);
  nbrdf_brdf_destroy(inner);
  double se, f = eval1(outer, query_deg(20, 0, 30, 180), 64, 1, &se);
  CHECK(isfinite(f) && f > 0.0 && se > 0.0);
  CHECK(nbrdf_brdf_is_stochastic(outer));
  nbrdf_brdf_destroy(outer);
}

static void test_analytic_through_api(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  nbrdf_brdf *c = conductor_or_die(0.5, 0.04), *d = NULL;
  CHECK_OK(nbrdf_brdf_create_dielectric(0.5, 1.5, &d, err), err);
  CHECK(!nbrdf_brdf_is_stochastic(c) && !nbrdf_brdf_is_stochastic(d));
  double se = -1;
  /* Normal incidence: R0 / (4π α²) = 0.04/π for both (F(0°) = 0.04 at η = 1.5). */
  CHECK_REL(eval1(c, query_deg(0, 0, 0, 0), 1, 1, &se), 0.04 / M_PI, 1e-12, 0);
  CHECK(se == 0.0);
  CHECK_REL(eval1(d, query_deg(0, 0, 0, 0), 1, 1, &se), 0.04 / M_PI, 1e-12, 0);
  /* The dielectric's sampler as a BRDF draws its reflection lobe only. */
  double wi[3], wo[3], w, sum = 0;
  set_dir(wi, 30, 0);
  for (uint64_t i = 0; i < 2000; i++) {
    CHECK_OK(nbrdf_brdf_sample(d, wi, 1, i, wo, &w, err), err);
    CHECK(wo[2] > 0.0 && w >= 0.0 && w <= 1.0);
    sum += w;
  }
  /* Its mean weight is the reflection lobe's albedo ∫ f cos θo dωo, here by
   * the midpoint rule over (cos θo, φo) through the public eval. */
  enum { NC = 200, NP = 200 };
  static nbrdf_query q[NC * NP];
  static double f[NC * NP];
  for (int i = 0; i < NC; i++)
    for (int j = 0; j < NP; j++) {
      double ct = (i + 0.5) / NC, st = sqrt(1 - ct * ct), phi = 2 * M_PI * (j + 0.5) / NP;
      nbrdf_query *qq = &q[i * NP + j];
      memcpy(qq->wi, wi, sizeof wi);
      qq->wo[0] = st * cos(phi), qq->wo[1] = st * sin(phi), qq->wo[2] = ct;
    }
  CHECK_OK(nbrdf_brdf_eval(d, NC * NP, q, NULL, f, NULL, err), err);
  double rho = 0;
  for (int k = 0; k < NC * NP; k++)
    rho += f[k] * q[k].wo[2];
  rho *= (1.0 / NC) * (2 * M_PI / NP);
  CHECK_MSG(fabs(sum / 2000 - rho) < 0.002, "mean weight %g, quadrature %g", sum / 2000, rho);
  nbrdf_brdf_destroy(c);
  nbrdf_brdf_destroy(d);
}

int main(void) {
  RUN(test_create_rejects_bad_parameters);
  RUN(test_eval_rejects_bad_queries);
  RUN(test_bottom_is_copied);
  RUN(test_analytic_through_api);
  return testing_finish();
}
