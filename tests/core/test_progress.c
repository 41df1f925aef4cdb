/* The ticker of the library's long calls (src/core/progress.h): the cancel
 * flag is seen on every tick, the progress callback at most ~10 times a
 * second unless forced, and a cancel sticks. */
#include <signal.h>

#include "core/progress.h"
#include "testing.h"

typedef struct counter {
  int calls, stop_at;
  double last_done;
  double at[8];          /* the ticker's time of each of the first calls */
  const core_ticker *t;  /* NULL: not recorded */
} counter;

static int count(void *user, const char *stage, double done, double total) {
  (void)stage, (void)total;
  counter *c = user;
  /* The ticker's own reading, not a later clock: a wait for a CPU in between would move it. */
  if (c->t && c->calls < 8) c->at[c->calls] = c->t->last;
  c->calls++;
  c->last_done = done;
  return c->stop_at && c->calls >= c->stop_at;
}

/* Asserts what load cannot change: calls at least NBRDF_PROGRESS_INTERVAL apart, however
 * fast the ticks come (a loaded machine only makes the gaps longer), and calls go on
 * coming (the loop runs until the fourth; ctest's timeout bounds it). A count of calls in
 * so many seconds of wall time failed when the process waited for a CPU. */
static void test_throttle(void) {
  core_ticker t;
  counter c = {0, 0, -1.0, {0}, &t};
  core_ticker_init(&t, count, &c, NULL);
  long ticks = 0;
  while (c.calls < 4) {
    CHECK(!core_ticker_tick(&t, "s", (double)ticks, 1e18, 0));
    ticks++;
  }
  CHECK_MSG(ticks > c.calls, "the throttle let every tick call back (%ld ticks, %d calls)", ticks, c.calls);
  for (int i = 1; i < 4; i++)
    CHECK_MSG(c.at[i] - c.at[i - 1] >= NBRDF_PROGRESS_INTERVAL,
              "calls %d and %d %.4f s apart", i - 1, i, c.at[i] - c.at[i - 1]);
  int before = c.calls;
  CHECK(!core_ticker_tick(&t, "s", 7, 7, 1));
  CHECK(c.calls == before + 1 && c.last_done == 7); /* forced: always */
}

static void test_cancel(void) {
  volatile sig_atomic_t flag = 0;
  counter c = {0, 0, -1.0, {0}, NULL};
  core_ticker t;
  core_ticker_init(&t, count, &c, &flag);
  CHECK(!core_ticker_tick(&t, "s", 0, 1, 0));
  flag = 1;
  CHECK(core_ticker_tick(&t, "s", 0, 1, 0)); /* seen at once, throttle or not */
  flag = 0;
  CHECK(core_ticker_tick(&t, "s", 0, 1, 0)); /* and it sticks */

  counter d = {0, 2, -1.0, {0}, NULL};
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
