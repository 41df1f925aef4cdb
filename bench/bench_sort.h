/* qsort comparator of doubles for the benchmarks' medians and percentiles.
 * Header-only, like bench_clock.h. */
#ifndef NBRDF_BENCH_SORT_H
#define NBRDF_BENCH_SORT_H

static inline int bench_cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

#endif
