/* Clocks for the benchmarks. CPU time of the whole process is reported beside
 * wall time because the build machines are shared: CPU seconds stay meaningful
 * under other load, wall seconds do not. Run multi-threaded benches with
 * OMP_WAIT_POLICY=passive so that idle OpenMP threads do not spin into the
 * CPU time. */
#ifndef NBRDF_BENCH_CLOCK_H
#define NBRDF_BENCH_CLOCK_H

#include <stdio.h>
#include <string.h>
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

/* The three load averages as /proc/loadavg writes them ("" if unknown). */
static inline void bench_load_line(char *buf, size_t n) {
  FILE *f = fopen("/proc/loadavg", "r");
  buf[0] = '\0';
  if (f) {
    if (!fgets(buf, (int)n, f)) buf[0] = '\0';
    fclose(f);
  }
  char *p = buf;
  for (int k = 0; k < 3 && p; k++)
    p = strchr(p + 1, ' ');
  if (p) *p = '\0';
}

#endif
