/* The subcommands of `nbrdf train`, one file each (cmd_train_<what>.c). */
#ifndef NBRDF_CLI_CMD_TRAIN_H
#define NBRDF_CLI_CMD_TRAIN_H

#include <stdio.h>

#include "cli/cli_options.h"
#include "model/base_table.h"
#include "model/layering.h"
#include "model/sampler.h"
#include "nbrdf/status.h"

int cmd_train_tables(int argc, char **argv);
int cmd_train_layering(int argc, char **argv);
int cmd_train_bundle(int argc, char **argv);
int cmd_train_sampler(int argc, char **argv);
/* Their option tables (cli_options.h), each shown as subcommand "tables", "layering", ... */
void cmd_train_tables_options(cli_opt_visit visit, void *user);
void cmd_train_layering_options(cli_opt_visit visit, void *user);
void cmd_train_bundle_options(cli_opt_visit visit, void *user);
void cmd_train_sampler_options(cli_opt_visit visit, void *user);
void cmd_train_usage(FILE *out);
/* Parses `nbrdf train SUB ...` with `options` (a subcommand's, showing `args`' table):
 * CLI_OPTIONS_OK; CLI_OPTIONS_HELP once the usage is printed (exit 0); else a usage
 * error's exit status. */
int cli_train_parse(const char *sub, int argc, char **argv,
                    void (*options)(void *args, cli_opt_visit visit, void *user), void *args);

/* The rest is cli_train_common.c. */

/* The trainer's flags (src/train/trainer.h) every training takes:
 * --checkpoint FILE, --checkpoint-minutes M, --minutes M, --stop-at-step N. */
typedef struct cli_train_limits {
  const char *checkpoint;
  double checkpoint_seconds, max_seconds;
  int stop_at_step;
} cli_train_limits;
#define CLI_TRAIN_LIMITS_DEFAULT                                                                   \
  { NULL, 300.0, 0.0, 0 }
/* A value in minutes [o->lo, o->hi] stored in seconds (a double). */
int cli_train_read_minutes(const char *cmd, const cli_opt *o, const char *value);
/* Their table entries; `l` a cli_train_limits *. */
// clang-format off
#define CLI_TRAIN_LIMITS_OPTIONS(l)                                                                \
  {.type = CLI_OPT_PATH, .name = "--checkpoint", .meta = "FILE", .dest = &(l)->checkpoint,         \
   .help = "resumable state (resume: run the same command again; another\n"                        \
           "setting is refused, naming it). Ctrl-C checkpoints and stops"},                        \
  {.type = CLI_OPT_CUSTOM, .name = "--checkpoint-minutes", .meta = "M", .lo = 1e-3, .hi = 1e6,     \
   .dest = &(l)->checkpoint_seconds, .parse = cli_train_read_minutes,                              \
   .help = "minutes between checkpoints (5)"},                                                     \
  {.type = CLI_OPT_CUSTOM, .name = "--minutes", .meta = "M", .lo = 0, .hi = 1e9,                   \
   .dest = &(l)->max_seconds, .parse = cli_train_read_minutes,                                     \
   .help = "stop, checkpointed, after M minutes"},                                                 \
  {.type = CLI_OPT_INT, .name = "--stop-at-step", .meta = "N", .lo = 0, .hi = 2147483647,          \
   .dest = &(l)->stop_at_step, .help = "stop (checkpointed) after N steps of the whole run"}
// clang-format on

/* A comma-separated list of files (--data A,B): split into a copy the caller frees. */
typedef struct cli_train_list {
  char *copy;
  const char *item[64];
  int n;
} cli_train_list;
int cli_train_read_list(const char *cmd, const cli_opt *o, const char *value);
/* The note a resume from a checkpoint without nbrdf.options prints. */
void cli_train_limits_note(const char *checkpoint, int legacy);
/* Splits a comma-separated list in place into at most max items. */
int cli_train_split_list(char *list, const char **out, int max);
/* Both base tables (dielectric, conductor) of a tables file, D = 32. */
nbrdf_status cli_train_load_tables(const char *path, model_base_table t[2], nbrdf_error *err);
/* A layering (layering != 0) or sampling network's weights file. */
nbrdf_status cli_train_read_net(const char *path, int layering, model_layering **lay,
                                model_sampler **smp, nbrdf_error *err);

#endif
