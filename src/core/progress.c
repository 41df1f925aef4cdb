#include "core/progress.h"

#include <time.h>

double core_monotonic_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void core_ticker_init(core_ticker *t, nbrdf_progress_fn fn, void *user,
                      volatile sig_atomic_t *cancel) {
  t->fn = fn;
  t->user = user;
  t->cancel = cancel;
  t->last = -1.0;
  t->stopped = 0;
}

int core_ticker_tick(core_ticker *t, const char *stage, double done, double total, int force) {
  if (t->stopped || (t->cancel && *t->cancel)) return t->stopped = 1;
  if (!t->fn) return 0;
  double now = core_monotonic_seconds();
  if (!force && t->last >= 0.0 && now - t->last < NBRDF_PROGRESS_INTERVAL) return 0;
  t->last = now;
  if (t->fn(t->user, stage, done, total)) t->stopped = 1;
  return t->stopped;
}
