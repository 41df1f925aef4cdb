/* The ticker of the library's long calls (src/core/progress.h): the cancel
 * flag is seen on every tick, the progress callback at most ~10 times a
 * second unless forced, and a cancel sticks. */
#include <signal.h>

#include "core/progress.h"
#include "testing.h"

typedef struct counter {
  int calls, stop_at;
  double last_done;
} counter;

static int count(void *user, const char *stage, double done, double total) {
  (void)stage, (void)total;
  counter *c = user;
  c->calls++;
  c->last_done = done;
  return c->stop_at && c->calls >= c->stop_at;
}

static void test_throttle(void) {
  counter c = {0, 0, -1.0};
  core_ticker t;
  core_ticker_init(&t, count, &c, NULL);
  double t0 = core_monotonic_seconds();
  int ticks = 0;
  while (core_monotonic_seconds() - t0 < 0.35) {
    CHECK(!core_ticker_tick(&t, "s", ticks, 1e9, 0));
    ticks++;
  }
  /* ~0.35 s of ticks: the first call and one per 0.1 s after it */
  CHECK_MSG(c.calls >= 2 && c.calls <= 5, "%d calls in 0.35 s of %d ticks", c.calls, ticks);
  int before = c.calls;
  CHECK(!core_ticker_tick(&t, "s", 7, 7, 1));
  CHECK(c.calls == before + 1 && c.last_done == 7); /* forced: always */
}

static void test_cancel(void) {
  volatile sig_atomic_t flag = 0;
  counter c = {0, 0, -1.0};
  core_ticker t;
  core_ticker_init(&t, count, &c, &flag);
  CHECK(!core_ticker_tick(&t, "s", 0, 1, 0));
  flag = 1;
  CHECK(core_ticker_tick(&t, "s", 0, 1, 0)); /* seen at once, throttle or not */
  flag = 0;
  CHECK(core_ticker_tick(&t, "s", 0, 1, 0)); /* and it sticks */

  counter d = {0, 2, -1.0};
  core_ticker_init(&t, count, &d, NULL);
  CHECK(!core_ticker_tick(&t, "s", 0, 1, 1));
  CHECK(core_ticker_tick(&t, "s", 1, 1, 1)); /* the callback's non-zero return */
  CHECK(core_ticker_tick(&t, "s", 1, 1, 1) && d.calls == 2);

  core_ticker_init(&t, NULL, NULL, NULL); /* neither: never stops */
  CHECK(!core_ticker_tick(&t, "s", 1, 1, 1));
}

int main(void) {
  RUN(test_throttle);
  RUN(test_cancel);
  return testing_finish();
}
