/* Clocks for the benchmarks. CPU time of the whole process is reported beside
 * wall time because the build machines are shared: CPU seconds stay meaningful
 * under other load, wall seconds do not. Run multi-threaded benches with
 * OMP_WAIT_POLICY=passive so that idle OpenMP threads do not spin into the
 * CPU time. */
#ifndef NBRDF_BENCH_CLOCK_H
#define NBRDF_BENCH_CLOCK_H

#include <time.h>

static inline double bench_wall_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline double bench_cpu_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
