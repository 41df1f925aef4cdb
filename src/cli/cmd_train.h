/* The subcommands of `nbrdf train`, one file each (cmd_train_<what>.c). */
#ifndef NBRDF_CLI_CMD_TRAIN_H
#define NBRDF_CLI_CMD_TRAIN_H

#include "model/base_table.h"
#include "model/layering.h"
#include "model/sampler.h"
#include "nbrdf/status.h"

int cmd_train_tables(int argc, char **argv);
int cmd_train_layering(int argc, char **argv);
int cmd_train_bundle(int argc, char **argv);
int cmd_train_sampler(int argc, char **argv);

/* The rest is cli_train_common.c. */

/* The trainer's flags (src/train/trainer.h) every training takes:
 * --checkpoint FILE, --checkpoint-minutes M, --minutes M, --stop-at-step N. */
typedef struct cli_train_limits {
  const char *checkpoint;
  double checkpoint_seconds, max_seconds;
  long stop_at_step;
} cli_train_limits;
#define CLI_TRAIN_LIMITS_DEFAULT                                                                   \
  { NULL, 300.0, 0.0, 0 }
/* 1 when argv[*i] is one of them (*exit_code: a usage error's, else 0), 0 when not. */
int cli_train_limits_option(int argc, char **argv, int *i, cli_train_limits *l, int *exit_code);
/* The note a resume from a checkpoint without nbrdf.options prints. */
void cli_train_limits_note(const char *checkpoint, int legacy);
/* The help lines of those flags. */
#define CLI_TRAIN_LIMITS_HELP                                                                      \
  "  --checkpoint FILE   resumable state (resume: run the same command again; another\n"           \
  "                      setting is refused, naming it). Ctrl-C checkpoints and stops\n"           \
  "  --checkpoint-minutes M (5)  --minutes M (stop, checkpointed, after M minutes)\n"              \
  "  --stop-at-step N    stop (checkpointed) after N steps of the whole run\n"

/* Splits a comma-separated list in place into at most max items. */
int cli_train_split_list(char *list, const char **out, int max);
/* Both base tables (dielectric, conductor) of a tables file, D = 32. */
nbrdf_status cli_train_load_tables(const char *path, model_base_table t[2], nbrdf_error *err);
/* A layering (layering != 0) or sampling network's weights file. */
nbrdf_status cli_train_read_net(const char *path, int layering, model_layering **lay,
                                model_sampler **smp, nbrdf_error *err);

#endif
