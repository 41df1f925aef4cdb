/* nbrdf train tables: base-latent tables for a trained decoder. */
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_progress.h"
#include "cli/cmd_train.h"
#include "model/bundle.h"
#include "train/table_fit.h"

typedef struct tables_args {
  train_table_settings s;
  const char *decoder, *out;
  cli_progress_state prog;
  cli_train_limits lim;
} tables_args;

static void tables_options(void *args, cli_opt_visit visit, void *user) {
  tables_args *a = args;
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_PATH, .name = "--decoder", .meta = "FILE", .dest = &a->decoder,
       .help = "the trained decoder, frozen"},
      {.type = CLI_OPT_PATH, .name = "--output", .alias = "-o", .meta = "FILE", .dest = &a->out,
       .help = "the base_tables.safetensors to write"},
      {.type = CLI_OPT_INT, .name = "--alpha-nodes", .meta = "N", .lo = 2, .hi = 1024,
       .dest = &a->s.alpha_nodes, .help = "roughness nodes of both tables (16)"},
      {.type = CLI_OPT_INT, .name = "--eta-nodes", .meta = "N", .lo = 2, .hi = 1024,
       .dest = &a->s.eta_nodes, .help = "eta nodes of the dielectric table (8)"},
      {.type = CLI_OPT_INT, .name = "--r0-nodes", .meta = "N", .lo = 2, .hi = 1024,
       .dest = &a->s.r0_nodes, .help = "r0 nodes of the conductor table (9)"},
      {.type = CLI_OPT_DOUBLE, .name = "--eta-warp", .meta = "P", .lo = 0.25, .hi = 4,
       .dest = &a->s.eta_warp, .help = "eta nodes E + (2 - E) u^P (1)"},
      {.type = CLI_OPT_DOUBLE, .name = "--eta-min", .meta = "E", .lo = 1, .hi = 1.9,
       .dest = &a->s.eta_min, .help = "the smallest eta node (1.05)"},
      {.type = CLI_OPT_DOUBLE, .name = "--r0-warp", .meta = "P", .lo = 0.25, .hi = 4,
       .dest = &a->s.r0_warp, .help = "r0 nodes u^P (1)"},
      {.type = CLI_OPT_INT, .name = "--steps", .meta = "N", .lo = 1, .hi = 1000000,
       .dest = &a->s.steps, .help = "projection steps (800)"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .hi = 2147483647.0, .dest = &a->s.seed,
       .help = "seed (1)"},
      CLI_TRAIN_LIMITS_OPTIONS(&a->lim),
      CLI_PROGRESS_OPTION(&a->prog, "progress as JSON lines on stdout"),
      {0},
  };
  // clang-format on
  visit(user, "tables", t);
}

static void tables_args_init(tables_args *a) {
  memset(a, 0, sizeof *a);
  a->s = (train_table_settings)TRAIN_TABLE_SETTINGS_DEFAULT;
  a->prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
  a->lim = (cli_train_limits)CLI_TRAIN_LIMITS_DEFAULT;
}

void cmd_train_tables_options(cli_opt_visit visit, void *user) {
  tables_args a;
  tables_args_init(&a);
  tables_options(&a, visit, user);
}

int cmd_train_tables(int argc, char **argv) {
  tables_args a;
  tables_args_init(&a);
  int rc = cli_train_parse("tables", argc, argv, tables_options, &a);
  if (rc) return rc == CLI_OPTIONS_HELP ? CLI_EXIT_OK : rc;
  train_table_settings s = a.s;
  const char *decoder = a.decoder, *out = a.out;
  cli_progress_state prog = a.prog;
  cli_train_limits lim = a.lim;
  if (!decoder || !out) return cli_usage_error("train", "tables: --decoder and -o are required");
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  cli_inputs_add(&inputs, decoder);
  const char *outputs[2] = {out, lim.checkpoint};
  if (cli_outputs_check("train", &inputs, outputs, 2) != CLI_EXIT_OK) return CLI_EXIT_FAILURE;
  s.checkpoint = lim.checkpoint, s.checkpoint_seconds = lim.checkpoint_seconds;
  s.max_seconds = lim.max_seconds, s.stop_at_step = lim.stop_at_step;
  nbrdf_error err = {0};
  model_decoder *dec = NULL;
  model_base_table tables[2];
  memset(tables, 0, sizeof tables);
  nbrdf_status st = model_decoder_load(decoder, &dec, &err);
  cli_progress_start(&prog);
  s.progress = cli_progress, s.user = &prog, s.cancel = cli_cancel_flag();
  cli_cancel_watch();
  if (!st) st = train_tables_fit(dec, &s, tables, &err);
  cli_cancel_unwatch();
  const model_base_table *const parts[2] = {&tables[0], &tables[1]};
  if (!st) st = model_tables_save(parts, out, &err);
  model_base_table_free(&tables[0]);
  model_base_table_free(&tables[1]);
  model_decoder_destroy(dec);
  if (!prog.json) fputc('\n', stderr);
  if (st) return cli_fail_error("train", &err);
  printf("train tables: %s (%d x %d dielectric, %d x %d conductor latents, %d steps)\n", out,
         s.alpha_nodes, s.eta_nodes, s.alpha_nodes, s.r0_nodes, s.steps);
  return CLI_EXIT_OK;
}
