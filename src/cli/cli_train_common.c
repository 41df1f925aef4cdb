/* What the `nbrdf train` subcommands share: the trainer's flags, list splitting and
 * the readers of trained parts. */
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cmd_train.h"
#include "nn/safetensors.h"

int cli_train_read_minutes(const char *cmd, const cli_opt *o, const char *v) {
  double x;
  if (!cli_parse_double(v, &x) || !(x >= o->lo && x <= o->hi)) {
    char what[96], lo[32], hi[32];
    snprintf(what, sizeof what, "a number of minutes in [%s, %s]",
             cli_opt_number(o->lo, lo, sizeof lo), cli_opt_number(o->hi, hi, sizeof hi));
    return cli_opt_bad(cmd, o->name, what, v);
  }
  *(double *)o->dest = 60.0 * x;
  return 0;
}

int cli_train_read_list(const char *cmd, const cli_opt *o, const char *v) {
  cli_train_list *l = o->dest;
  free(l->copy);
  l->copy = strdup(v);
  if (!l->copy) return cli_usage_error(cmd, "%s: out of memory", o->name);
  l->n = cli_train_split_list(l->copy, l->item, 64);
  return 0;
}

int cli_train_parse(const char *sub, int argc, char **argv,
                    void (*options)(void *args, cli_opt_visit visit, void *user), void *args) {
  cli_parse_call call = {"train", sub, argc, 2, argv, NULL, 0};
  options(args, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) cmd_train_usage(stdout);
  return call.rc;
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
