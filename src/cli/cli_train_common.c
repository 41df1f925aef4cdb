/* What the `nbrdf train` subcommands share: the trainer's flags, list splitting and
 * the readers of trained parts. */
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cmd_train.h"
#include "nn/safetensors.h"

int cli_train_limits_option(int argc, char **argv, int *i, cli_train_limits *l, int *exit_code) {
  const char *v;
  double x;
  long n;
  *exit_code = CLI_EXIT_OK;
  if ((v = cli_option_value(argc, argv, i, "--checkpoint"))) {
    l->checkpoint = v;
  } else if ((v = cli_option_value(argc, argv, i, "--checkpoint-minutes"))) {
    if (!cli_parse_double(v, &x) || !(x >= 1e-3 && x <= 1e6))
      *exit_code = cli_usage_error("train", "--checkpoint-minutes '%s': expected 0.001..1e6", v);
    l->checkpoint_seconds = 60.0 * x;
  } else if ((v = cli_option_value(argc, argv, i, "--minutes"))) {
    if (!cli_parse_double(v, &x) || !(x >= 0 && x <= 1e9))
      *exit_code = cli_usage_error("train", "--minutes '%s': expected 0..1e9", v);
    l->max_seconds = 60.0 * x;
  } else if ((v = cli_option_value(argc, argv, i, "--stop-at-step"))) {
    if (!cli_parse_int(v, 0, 2147483647, &n))
      *exit_code = cli_usage_error("train", "--stop-at-step '%s': expected 0..2^31-1", v);
    l->stop_at_step = n;
  } else {
    return 0;
  }
  return 1;
}

void cli_train_limits_note(const char *checkpoint, int legacy) {
  if (legacy)
    fprintf(stderr,
            "note: %s was written before checkpoints recorded their options (nbrdf.options); it "
            "was checked the old way, and the next checkpoint records them\n",
            checkpoint);
}

nbrdf_status cli_train_load_tables(const char *path, model_base_table t[2], nbrdf_error *err) {
  nn_st_reader *r = NULL;
  memset(t, 0, 2 * sizeof *t);
  nbrdf_status st = nn_st_open(path, &r, err);
  if (!st) st = model_base_table_read(r, MODEL_TABLE_DIELECTRIC, 32, &t[0], err);
  if (!st) st = model_base_table_read(r, MODEL_TABLE_CONDUCTOR, 32, &t[1], err);
  nn_st_close(r);
  return st;
}

int cli_train_split_list(char *list, const char **out, int max) {
  int n = 0;
  for (char *tok = strtok(list, ","); tok && n < max; tok = strtok(NULL, ","))
    out[n++] = tok;
  return n;
}

nbrdf_status cli_train_read_net(const char *path, int layering, model_layering **lay,
                                model_sampler **smp, nbrdf_error *err) {
  nn_st_reader *r = NULL;
  nbrdf_status st = nn_st_open(path, &r, err);
  if (!st) st = layering ? model_layering_read(r, lay, err) : model_sampler_read(r, smp, err);
  nn_st_close(r);
  return st;
}
