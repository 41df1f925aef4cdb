/* Statistics of the layered estimator: reciprocity within the reported
 * errors, honest standard errors, determinism whatever the thread count. */
#include <omp.h>

#include "layered_util.h"

static nbrdf_brdf *bench_brdf(int which) {
  switch (which) {
  case 0:
    return layered2(0.02, 1.5, 0.5, 0.9, 0.0, 0.0); /* smooth coat, rough metal */
  case 1:
    return layered2(0.6, 1.5, 0.02, 0.9, 0.0, 0.0); /* rough coat, smooth metal */
  case 2:
    return layered2(0.1, 1.5, 0.3, 0.5, 0.95, 5.0); /* thick scattering medium */
  default:
    return layered2(0.3, 2.0, 0.2, 0.7, 0.6, 1.0); /* a bit of everything */
  }
}

/* f(ωi, ωo) = f(ωo, ωi): swapping starts the walk from the other side, so
 * the two estimates are independent and must agree within their errors. */
static void test_reciprocity(void) {
  const double pairs[][4] = {
      {0, 0, 45, 180}, {30, 0, 60, 180}, {60, 0, 20, 90}, {75, 0, 75, 180}, {80, 0, 40, 45}};
  double sum_z2 = 0.0;
  int n = 0;
  for (int b = 0; b < 4; b++) {
    nbrdf_brdf *l = bench_brdf(b);
    for (int p = 0; p < 5; p++) {
      nbrdf_query q = query_deg(pairs[p][0], pairs[p][1], pairs[p][2], pairs[p][3]);
      nbrdf_query r = query_deg(pairs[p][2], pairs[p][3], pairs[p][0], pairs[p][1]);
      double sa, sb, fa = eval1(l, q, 2048, 10, &sa), fb = eval1(l, r, 2048, 11, &sb);
      double z = (fa - fb) / sqrt(sa * sa + sb * sb);
      CHECK_MSG(fabs(z) < 4.5, "brdf %d pair %d: f(i,o) = %.6g ± %.2g, f(o,i) = %.6g ± %.2g", b, p,
                fa, sa, fb, sb);
      sum_z2 += z * z;
      n++;
    }
    nbrdf_brdf_destroy(l);
  }
  double rms = sqrt(sum_z2 / n);
  printf("  reciprocity: RMS z-score %.3f over %d pairs\n", rms, n);
  CHECK(rms > 0.5 && rms < 1.5);
}

/* Over independent repetitions, (f_a − f_b) / √(se_a² + se_b²) must behave
 * like N(0, 1): RMS ≈ 1 (±0.2 for 150 pairs, allowing for the slightly heavy
 * tails of walk contributions) and few beyond 3. */
static void test_standard_error_is_honest(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  enum { PAIRS = 150 };
  const double dirs[][4] = {{30, 0, 30, 180}, {0, 0, 60, 0}, {70, 0, 50, 120}};
  static nbrdf_query q[2 * PAIRS];
  static double f[2 * PAIRS], se[2 * PAIRS];
  for (int b = 0; b < 4; b++) {
    nbrdf_brdf *l = bench_brdf(b);
    for (int d = 0; d < 3; d++) {
      for (int k = 0; k < 2 * PAIRS; k++)
        q[k] = query_deg(dirs[d][0], dirs[d][1], dirs[d][2], dirs[d][3]);
      nbrdf_eval_options o = NBRDF_EVAL_OPTIONS_DEFAULT;
      o.spp = 64;
      o.seed = 100 + (uint64_t)(3 * b + d);
      CHECK_OK(nbrdf_brdf_eval(l, 2 * PAIRS, q, &o, f, se, err), err);
      double sum_z2 = 0.0;
      int beyond3 = 0;
      for (int k = 0; k < PAIRS; k++) {
        double z =
            (f[2 * k] - f[2 * k + 1]) / sqrt(se[2 * k] * se[2 * k] + se[2 * k + 1] * se[2 * k + 1]);
        sum_z2 += z * z;
        beyond3 += fabs(z) > 3.0;
      }
      double rms = sqrt(sum_z2 / PAIRS);
      printf("  brdf %d dir %d: RMS z %.3f, %d of %d beyond 3\n", b, d, rms, beyond3, PAIRS);
      CHECK_MSG(rms > 0.8 && rms < 1.2, "brdf %d dir %d: RMS z-score %.3f", b, d, rms);
      CHECK_MSG(beyond3 <= 3, "brdf %d dir %d: %d of %d z-scores beyond 3", b, d, beyond3, PAIRS);
    }
    nbrdf_brdf_destroy(l);
  }
}

static void test_deterministic(void) {
  nbrdf_error err_ = {0}, *err = &err_;
  enum { N = 40 };
  nbrdf_query q[N];
  for (int k = 0; k < N; k++)
    q[k] = query_deg(2.0 * k, 10.0 * k, 85.0 - 2.0 * k, 180.0 - 7.0 * k);
  nbrdf_brdf *l = bench_brdf(3);
  double f1[N], s1[N], f2[N], s2[N], f3[N], s3[N];
  nbrdf_eval_options o = NBRDF_EVAL_OPTIONS_DEFAULT;
  o.spp = 32;
  o.seed = 77;
  o.threads = 1;
  CHECK_OK(nbrdf_brdf_eval(l, N, q, &o, f1, s1, err), err);
  o.threads = 2;
  CHECK_OK(nbrdf_brdf_eval(l, N, q, &o, f2, s2, err), err);
  CHECK(memcmp(f1, f2, sizeof f1) == 0 && memcmp(s1, s2, sizeof s1) == 0);
  /* Query k's value does not depend on the other queries of the batch. */
  double one, one_se;
  nbrdf_eval_options o1 = o;
  CHECK_OK(nbrdf_brdf_eval(l, 1, &q[0], &o1, &one, &one_se, err), err);
  CHECK(one == f1[0]);
  o.seed = 78;
  CHECK_OK(nbrdf_brdf_eval(l, N, q, &o, f3, s3, err), err);
  int same = 0;
  for (int k = 0; k < N; k++)
    same += f3[k] == f1[k];
  CHECK(same == 0);

  /* Albedo: the same bits with 1 and 2 threads. */
  double r1, e1, r2, e2;
  omp_set_num_threads(1);
  CHECK_OK(nbrdf_brdf_albedo(l, 0.5, 5000, 3, &r1, &e1, err), err);
  omp_set_num_threads(2);
  CHECK_OK(nbrdf_brdf_albedo(l, 0.5, 5000, 3, &r2, &e2, err), err);
  CHECK(r1 == r2 && e1 == e2);
  /* Sampling: (seed, index) fixes the draw. */
  double wi[3], a[3], b[3], wa, wb;
  set_dir(wi, 40, 10);
  CHECK_OK(nbrdf_brdf_sample(l, wi, 5, 17, a, &wa, err), err);
  CHECK_OK(nbrdf_brdf_sample(l, wi, 5, 17, b, &wb, err), err);
  CHECK(memcmp(a, b, sizeof a) == 0 && wa == wb);
  /* Other indices give other draws (some may be absorbed: weight 0). */
  int differ = 0;
  for (uint64_t i = 18; i < 58; i++) {
    CHECK_OK(nbrdf_brdf_sample(l, wi, 5, i, b, &wb, err), err);
    differ += memcmp(a, b, sizeof a) != 0;
  }
  CHECK(differ >= 5);
  nbrdf_brdf_destroy(l);
}

int main(void) {
  RUN(test_reciprocity);
  RUN(test_standard_error_is_honest);
  RUN(test_deterministic);
  return testing_finish();
}
