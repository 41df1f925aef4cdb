/* Command-line helpers of the benchmarks: "--name value" options and lists of
 * counts ("1,4,16"). Header-only, like bench_clock.h. */
#ifndef NBRDF_BENCH_ARGS_H
#define NBRDF_BENCH_ARGS_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The value of option argv[*i] (advancing *i past it), or NULL after saying
 * that it needs one. -h / --help prints `usage` and exits 0. */
static inline const char *bench_option_value(int argc, char **argv, int *i, const char *prog,
                                             void (*usage)(FILE *)) {
  const char *a = argv[*i];
  if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
    usage(stdout);
    exit(0);
  }
  if (*i + 1 >= argc) {
    fprintf(stderr, "%s: %s needs a value\n", prog, a);
    return NULL;
  }
  return argv[++*i];
}

/* Parses up to `max` comma-separated counts in [lo, hi] (strictly increasing
 * if `increasing`) into out; returns how many, or 0 if the list is invalid. */
static inline int bench_parse_counts(const char *v, int *out, int max, long lo, long hi,
                                     int increasing) {
  int n = 0;
  for (char *s = (char *)v; *s;) {
    long k = strtol(s, &s, 10);
    if (n == max || k < lo || k > hi || (*s && *s != ',') || (increasing && n && k <= out[n - 1]))
      return 0;
    out[n++] = (int)k;
    if (*s == ',') s++;
  }
  return n;
}

#endif
