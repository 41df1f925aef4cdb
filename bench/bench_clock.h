/* Clocks for the benchmarks. CPU time of the whole process is reported beside
 * wall time because the build machines are shared: CPU seconds stay meaningful
 * under other load, wall seconds do not. Run multi-threaded benches with
 * OMP_WAIT_POLICY=passive so that idle OpenMP threads do not spin into the
 * CPU time. */
#ifndef NBRDF_BENCH_CLOCK_H
#define NBRDF_BENCH_CLOCK_H

#include <stdio.h>
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

/* The 1-minute load average (-1 if unknown), printed beside timings taken on
 * a shared machine. */
static inline double bench_load_average(void) {
  double l = -1;
  FILE *f = fopen("/proc/loadavg", "r");
  if (f && fscanf(f, "%lf", &l) != 1) l = -1;
  if (f) fclose(f);
  return l;
}

#endif
