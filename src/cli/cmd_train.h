/* The subcommands of `nbrdf train`, one file each (cmd_train_<what>.c). */
#ifndef NBRDF_CLI_CMD_TRAIN_H
#define NBRDF_CLI_CMD_TRAIN_H

#include <signal.h>

#include "nbrdf/status.h"

int cmd_train_tables(int argc, char **argv);
int cmd_train_layering(int argc, char **argv);
int cmd_train_bundle(int argc, char **argv);
int cmd_train_sampler(int argc, char **argv);

/* Progress on stderr (a line per second, or JSON lines) that also stops on
 * Ctrl-C once train_watch_sigint() is active. */
typedef struct train_progress {
  int json;
  long last;
} train_progress;
int train_on_progress(void *user, const char *stage, double done, double total);
void train_watch_sigint(int on);

#endif
