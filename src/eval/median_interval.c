/* The bootstrap interval of median_interval.h. */
#include "eval/median_interval.h"

#include <math.h>
#include <stdlib.h>

#include "core/rng.h"
#include "core/sort.h"

int eval_median_interval(const double *x, int n, uint64_t seed, double *lo, double *hi) {
  *lo = *hi = NAN;
  if (n <= 0) return 0;
  double *sample = malloc((size_t)n * sizeof *sample);
  double *medians = malloc(EVAL_MEDIAN_RESAMPLES * sizeof *medians);
  if (!sample || !medians) {
    free(sample), free(medians);
    return -1;
  }
  core_rng rng;
  core_rng_init(&rng, seed, 0x6d656469616eu);
  for (int b = 0; b < EVAL_MEDIAN_RESAMPLES; b++) {
    for (int i = 0; i < n; i++) {
      int k = (int)(core_rng_uniform(&rng) * n);
      sample[i] = x[k < n ? k : n - 1];
    }
    core_sort_doubles(sample, (size_t)n);
    medians[b] = sample[n / 2];
  }
  core_sort_doubles(medians, EVAL_MEDIAN_RESAMPLES);
  *lo = medians[(int)(0.05 * EVAL_MEDIAN_RESAMPLES)];
  *hi = medians[(int)(0.95 * EVAL_MEDIAN_RESAMPLES) - 1];
  free(sample), free(medians);
  return 0;
}
