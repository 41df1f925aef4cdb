#include "cli/cli_cancel.h"

#include <string.h>

static volatile sig_atomic_t cancelled;

static void on_sigint(int sig) {
  (void)sig;
  cancelled = 1;
}

volatile sig_atomic_t *cli_cancel_flag(void) { return &cancelled; }

void cli_cancel_watch(struct sigaction *old) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  cancelled = 0;
  sigaction(SIGINT, &sa, old);
}

void cli_cancel_unwatch(const struct sigaction *old) { sigaction(SIGINT, old, NULL); }
