/* The CLI's signal handling, all of it (docs/RELIABILITY.md, "Outputs and signals").
 *
 * While a long command watches, SIGINT, SIGTERM and SIGHUP set one flag, which the
 * library calls take as their cancel flag (bake, verify, render) or the progress
 * callbacks return (dataset, train, evaluate), so the command stops cleanly, leaves
 * no partial output and exits 1. SIGXFSZ is ignored for the whole process, so a write
 * over `ulimit -f` fails with EFBIG and is reported naming the file instead of killing
 * the process. A signal needs a process-wide flag; it lives here, in the executable,
 * never in the library. */
#ifndef NBRDF_CLI_CANCEL_H
#define NBRDF_CLI_CANCEL_H

#include <signal.h>

/* Once, at start: ignores SIGXFSZ. */
void cli_signals_setup(void);
/* 0, or the number of the signal that asked to stop. */
volatile sig_atomic_t *cli_cancel_flag(void);
/* Clears the flag and installs the handler for SIGINT, SIGTERM and SIGHUP. */
void cli_cancel_watch(void);
/* Puts back the handlers cli_cancel_watch replaced. */
void cli_cancel_unwatch(void);
/* "interrupt", "terminate", "hangup": what stopped the command, for its message. */
const char *cli_cancel_reason(void);

#endif
