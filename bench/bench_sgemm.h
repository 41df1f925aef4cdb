/* The machine's cblas_sgemm rate, the yardstick the benchmarks measure the
 * networks against (in the same run, since the build machine is shared).
 * Header-only, like bench_clock.h. */
#ifndef NBRDF_BENCH_SGEMM_H
#define NBRDF_BENCH_SGEMM_H

#include <cblas.h>
#include <stdlib.h>

#include "bench_clock.h"

/* GFLOP/s of y[m×n] = x[m×k] · W[n×k]ᵀ (the networks' layout), one warm-up call
 * then repeated for at least min_s seconds of CPU time (cpu_clock != 0: stays
 * meaningful under other load) or of wall time. */
static inline double bench_sgemm_gflops(int m, int n, int k, double min_s, int cpu_clock) {
  float *a = calloc((size_t)m * k, sizeof(float)), *b = calloc((size_t)n * k, sizeof(float));
  float *c = calloc((size_t)m * n, sizeof(float));
  if (!a || !b || !c) exit(1);
  for (size_t i = 0; i < (size_t)m * k; i++)
    a[i] = (float)(i % 7) * 0.1f;
  for (size_t i = 0; i < (size_t)n * k; i++)
    b[i] = (float)(i % 5) * 0.1f;
  cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasTrans, m, n, k, 1.0f, a, k, b, k, 0.0f, c, n);
  double (*clock)(void) = cpu_clock ? bench_cpu_seconds : bench_wall_seconds;
  long reps = 0;
  double t0 = clock(), t;
  do {
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasTrans, m, n, k, 1.0f, a, k, b, k, 0.0f, c, n);
    reps++;
  } while ((t = clock() - t0) < min_s);
  free(a), free(b), free(c);
  return 2.0 * m * n * k * (double)reps / t * 1e-9;
}

#endif
