/* Ctrl-C for long commands: while watched, SIGINT sets one flag, which the
 * library calls take as their cancel flag (bake, verify, render) or the
 * progress callbacks return (dataset, train, evaluate), so an interrupted
 * command stops cleanly and leaves no partial output. A signal needs a
 * process-wide flag; it lives here, in the executable, never in the library. */
#ifndef NBRDF_CLI_CANCEL_H
#define NBRDF_CLI_CANCEL_H

#include <signal.h>

volatile sig_atomic_t *cli_cancel_flag(void);
/* Clears the flag and installs the handler; *old receives the previous one. */
void cli_cancel_watch(struct sigaction *old);
void cli_cancel_unwatch(const struct sigaction *old);

#endif
