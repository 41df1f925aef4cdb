/* The bootstrap interval of a median (src/eval/median_interval.c): it brackets
 * the sample median, repeats for a seed, narrows as the sample grows (about as
 * 1/√n), is a point for a constant sample, and covers the population median
 * about as often as a 90 % interval should. */
#include <math.h>
#include <stdlib.h>

#include "core/rng.h"
#include "eval/median_interval.h"
#include "testing.h"

static int cmp(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* n lobe-error-like values: log-normal around 8 % (median exactly 0.08). */
static void draw(double *x, int n, uint64_t stream) {
  core_rng rng;
  core_rng_init(&rng, 42, stream);
  for (int i = 0; i < n; i++) {
    double u1 = core_rng_uniform(&rng), u2 = core_rng_uniform(&rng);
    double g = sqrt(-2.0 * log(1.0 - u1)) * cos(2.0 * M_PI * u2);
    x[i] = 0.08 * exp(0.5 * g);
  }
}

static void test_brackets_and_repeats(void) {
  double x[33], s[33], lo, hi, lo2, hi2;
  draw(x, 33, 1);
  for (int i = 0; i < 33; i++)
    s[i] = x[i];
  qsort(s, 33, sizeof *s, cmp);
  CHECK(eval_median_interval(x, 33, 5, &lo, &hi) == 0);
  CHECK(lo < s[16] && s[16] < hi);
  CHECK(eval_median_interval(x, 33, 5, &lo2, &hi2) == 0);
  CHECK(lo == lo2 && hi == hi2);
  /* the bounds are values of the sample */
  int found_lo = 0, found_hi = 0;
  for (int i = 0; i < 33; i++)
    found_lo |= x[i] == lo, found_hi |= x[i] == hi;
  CHECK(found_lo && found_hi);
}

static void test_narrows_with_n(void) {
  static double x[297];
  double lo33, hi33, lo297, hi297;
  draw(x, 297, 2);
  CHECK(eval_median_interval(x, 33, 1, &lo33, &hi33) == 0);
  CHECK(eval_median_interval(x, 297, 1, &lo297, &hi297) == 0);
  double w33 = hi33 - lo33, w297 = hi297 - lo297;
  /* √(297/33) = 3: allow the bootstrap's own spread */
  CHECK_MSG(w297 < 0.6 * w33 && w297 > 0.15 * w33, "widths %g (33) and %g (297)", w33, w297);
}

static void test_degenerate(void) {
  double c[5] = {0.07, 0.07, 0.07, 0.07, 0.07}, lo, hi;
  CHECK(eval_median_interval(c, 5, 3, &lo, &hi) == 0);
  CHECK(lo == 0.07 && hi == 0.07);
  CHECK(eval_median_interval(c, 1, 3, &lo, &hi) == 0);
  CHECK(lo == 0.07 && hi == 0.07);
  CHECK(eval_median_interval(c, 0, 3, &lo, &hi) == 0);
  CHECK(isnan(lo) && isnan(hi));
}

/* Of 200 samples of 33, the interval holds the population median (0.08) in
 * about 90 %: percentile bootstraps of a median at this n cover 85-95 %. */
static void test_coverage(void) {
  int covered = 0;
  for (int k = 0; k < 200; k++) {
    double x[33], lo, hi;
    draw(x, 33, 100 + (uint64_t)k);
    CHECK(eval_median_interval(x, 33, (uint64_t)k, &lo, &hi) == 0);
    covered += lo <= 0.08 && 0.08 <= hi;
  }
  CHECK_MSG(covered >= 160 && covered <= 196, "covered %d of 200", covered);
}

int main(void) {
  RUN(test_brackets_and_repeats);
  RUN(test_narrows_with_n);
  RUN(test_degenerate);
  RUN(test_coverage);
  return testing_finish();
}
