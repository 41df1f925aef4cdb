/* Progress and cancel for the library's long calls, between chunks of work.
 *
 * The work inside a call (a band of a bake, a verify texel, a render tile, a
 * dataset BRDF, a training step) is cut into chunks that take well under a
 * second even on a loaded 2-core machine; after each chunk the call asks its
 * ticker. The ticker reads the caller's cancel flag every time (a flag costs
 * nothing) but calls the progress callback at most every
 * NBRDF_PROGRESS_INTERVAL seconds (and always when forced: the first and last
 * report), so that callers' JSON lines stay few. A non-zero return of the
 * callback cancels like the flag. docs/RELIABILITY.md, "Cancel and progress". */
#ifndef NBRDF_CORE_PROGRESS_H
#define NBRDF_CORE_PROGRESS_H

#include <signal.h>

#include "nbrdf/status.h"

/* Seconds between calls of a progress callback at most (about 10 a second). */
#define NBRDF_PROGRESS_INTERVAL 0.1

typedef struct core_ticker {
  nbrdf_progress_fn fn; /* may be NULL */
  void *user;
  volatile sig_atomic_t *cancel; /* may be NULL */
  double last;                   /* monotonic seconds of the last call of fn; < 0: none yet */
  int stopped;                   /* 1 once cancelled: every later tick says so too */
} core_ticker;

void core_ticker_init(core_ticker *t, nbrdf_progress_fn fn, void *user,
                      volatile sig_atomic_t *cancel);
/* Non-zero when the work must stop: the cancel flag is set, or the callback,
 * called when `force` is set or NBRDF_PROGRESS_INTERVAL has passed since its
 * last call, returned non-zero. */
int core_ticker_tick(core_ticker *t, const char *stage, double done, double total, int force);

/* Monotonic seconds (CLOCK_MONOTONIC). */
double core_monotonic_seconds(void);

#endif
