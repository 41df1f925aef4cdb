#include <string.h>

#include "core/error.h"
#include "core/rng.h"
#include "core/warp.h"
#include "testing.h"

static void test_uniform_moments(void) {
  core_rng rng;
  core_rng_init(&rng, 42, 0);
  const int n = 200000;
  double sum = 0, sum2 = 0, lo = 1, hi = 0;
  for (int i = 0; i < n; i++) {
    double u = core_rng_uniform(&rng);
    sum += u;
    sum2 += u * u;
    lo = fmin(lo, u);
    hi = fmax(hi, u);
  }
  double mean = sum / n, var = sum2 / n - mean * mean;
  CHECK_NEAR(mean, 0.5, 5 * sqrt(1.0 / 12.0 / n));
  CHECK_NEAR(var, 1.0 / 12.0, 0.002);
  CHECK(lo >= 0.0 && hi < 1.0);
}

static void test_streams_independent_and_deterministic(void) {
  core_rng a, b, c;
  core_rng_init(&a, 7, 1);
  core_rng_init(&b, 7, 2);
  core_rng_init(&c, 7, 1);
  int same_ab = 0, same_ac = 0;
  for (int i = 0; i < 1000; i++) {
    uint32_t x = core_rng_u32(&a), y = core_rng_u32(&b), z = core_rng_u32(&c);
    same_ab += x == y;
    same_ac += x == z;
  }
  CHECK(same_ab < 3);
  CHECK(same_ac == 1000);
}

static void test_cosine_warp_matches_pdf(void) {
  /* Histogram of cos θ against the integral of the pdf over each bin. */
  core_rng rng;
  core_rng_init(&rng, 3, 0);
  enum { BINS = 10 };
  int hist[BINS] = {0};
  const int n = 100000;
  for (int i = 0; i < n; i++) {
    double u1 = core_rng_uniform(&rng), u2 = core_rng_uniform(&rng);
    vec3 w = core_warp_cosine_hemisphere(u1, u2);
    CHECK_NEAR(v3_length(w), 1.0, 1e-12);
    int bin = (int)(w.z * BINS);
    if (bin >= BINS) bin = BINS - 1;
    hist[bin]++;
  }
  for (int k = 0; k < BINS; k++) {
    /* P(z in [a,b]) for pdf cos/π: b² - a². */
    double a = (double)k / BINS, b = (double)(k + 1) / BINS;
    double expected = n * (b * b - a * a);
    CHECK_NEAR(hist[k], expected, 5 * sqrt(expected));
  }
}

static void test_check_range_messages(void) {
  nbrdf_error err = {0};
  CHECK(core_check_range(&err, "alpha", 0.5, 0.01, 1) == NBRDF_OK);
  CHECK_FAILS(core_check_range(&err, "alpha", NAN, 0.01, 1), NBRDF_ERR_ARGUMENT, &err,
              "alpha is NaN");
  CHECK_FAILS(core_check_range(&err, "eta", INFINITY, 1, 3), NBRDF_ERR_ARGUMENT, &err,
              "eta is infinite");
  CHECK_FAILS(core_check_range(&err, "r0", -0.5, 0, 1), NBRDF_ERR_ARGUMENT, &err,
              "r0 = -0.5 is outside [0, 1]");
  core_error_prefix(&err, "%s: ", "r0.png");
  CHECK(strcmp(err.message, "r0.png: r0 = -0.5 is outside [0, 1]") == 0);
}

int main(void) {
  RUN(test_uniform_moments);
  RUN(test_streams_independent_and_deterministic);
  RUN(test_cosine_warp_matches_pdf);
  RUN(test_check_range_messages);
  return testing_finish();
}
