#include "cli/cli_cancel.h"

#include <string.h>

static const int watched[3] = {SIGINT, SIGTERM, SIGHUP};
static volatile sig_atomic_t cancelled;
static struct sigaction previous[3];

static void on_signal(int sig) { cancelled = sig; }

void cli_signals_setup(void) { signal(SIGXFSZ, SIG_IGN); }

volatile sig_atomic_t *cli_cancel_flag(void) { return &cancelled; }

void cli_cancel_watch(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  cancelled = 0;
  for (int i = 0; i < 3; i++)
    sigaction(watched[i], &sa, &previous[i]);
}

void cli_cancel_unwatch(void) {
  for (int i = 0; i < 3; i++)
    sigaction(watched[i], &previous[i], NULL);
}

const char *cli_cancel_reason(void) {
  switch (cancelled) {
  case SIGTERM:
    return "terminated (SIGTERM)";
  case SIGHUP:
    return "hung up (SIGHUP)";
  default:
    return "interrupted";
  }
}
