/* How far a set's median lobe error could move with other BRDFs of the same
 * draws: a bootstrap interval. The `tails` regions hold 33 BRDFs at the usual
 * --count 99, and the same bundle's region median moved by up to 3 points
 * between the set's first and next 99 BRDFs (docs/notes/2026-11-29-tails-
 * decoder.md): a figure near a target needs its interval beside it. */
#ifndef NBRDF_EVAL_MEDIAN_INTERVAL_H
#define NBRDF_EVAL_MEDIAN_INTERVAL_H

#include <stdint.h>

/* Resamples of the bootstrap (fixed: the interval is part of a report). */
#define EVAL_MEDIAN_RESAMPLES 2000

/* The 5th and 95th percentiles of the median (x[n/2] of the sorted sample, as
 * evaluate's) over EVAL_MEDIAN_RESAMPLES resamples with replacement of x[0..n),
 * drawn from the stream `seed`: a 90 % percentile-bootstrap interval. A pure
 * function of (x, n, seed); n = 0 gives NaN, n = 1 the value itself. Returns 0,
 * or -1 when out of memory (*lo and *hi NaN). */
int eval_median_interval(const double *x, int n, uint64_t seed, double *lo, double *hi);

#endif
