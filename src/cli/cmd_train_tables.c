/* nbrdf train tables: base-latent tables for a trained decoder. */
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_progress.h"
#include "cli/cmd_train.h"
#include "model/bundle.h"
#include "train/table_fit.h"

int cmd_train_tables(int argc, char **argv) {
  train_table_settings s = TRAIN_TABLE_SETTINGS_DEFAULT;
  const char *decoder = NULL, *out = NULL;
  cli_progress_state prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
  cli_train_limits lim = CLI_TRAIN_LIMITS_DEFAULT;
  for (int i = 2; i < argc; i++) {
    const char *v;
    long n;
    int code;
    if (cli_train_limits_option(argc, argv, &i, &lim, &code)) {
      if (code) return code;
    } else if ((v = cli_option_value(argc, argv, &i, "--decoder"))) {
      decoder = v;
    } else if ((v = cli_option_value(argc, argv, &i, "-o"))) {
      out = v;
    } else if ((v = cli_option_value(argc, argv, &i, "--alpha-nodes"))) {
      if (!cli_parse_int(v, 2, 1024, &n))
        return cli_usage_error("train", "--alpha-nodes '%s': expected 2..1024", v);
      s.alpha_nodes = (int)n;
    } else if ((v = cli_option_value(argc, argv, &i, "--eta-nodes"))) {
      if (!cli_parse_int(v, 2, 1024, &n))
        return cli_usage_error("train", "--eta-nodes '%s': expected 2..1024", v);
      s.eta_nodes = (int)n;
    } else if ((v = cli_option_value(argc, argv, &i, "--r0-nodes"))) {
      if (!cli_parse_int(v, 2, 1024, &n))
        return cli_usage_error("train", "--r0-nodes '%s': expected 2..1024", v);
      s.r0_nodes = (int)n;
    } else if ((v = cli_option_value(argc, argv, &i, "--eta-warp"))) {
      if (!cli_parse_double(v, &s.eta_warp) || !(s.eta_warp >= 0.25 && s.eta_warp <= 4))
        return cli_usage_error("train", "--eta-warp '%s': expected 0.25..4", v);
    } else if ((v = cli_option_value(argc, argv, &i, "--eta-min"))) {
      if (!cli_parse_double(v, &s.eta_min) || !(s.eta_min >= 1.0 && s.eta_min <= 1.9))
        return cli_usage_error("train", "--eta-min '%s': expected 1..1.9", v);
    } else if ((v = cli_option_value(argc, argv, &i, "--r0-warp"))) {
      if (!cli_parse_double(v, &s.r0_warp) || !(s.r0_warp >= 0.25 && s.r0_warp <= 4))
        return cli_usage_error("train", "--r0-warp '%s': expected 0.25..4", v);
    } else if ((v = cli_option_value(argc, argv, &i, "--steps"))) {
      if (!cli_parse_int(v, 1, 1000000, &n))
        return cli_usage_error("train", "--steps '%s': expected 1..1000000", v);
      s.steps = (int)n;
    } else if ((v = cli_option_value(argc, argv, &i, "--seed"))) {
      if (!cli_parse_int(v, 0, 2147483647, &n))
        return cli_usage_error("train", "--seed '%s': expected 0..2^31-1", v);
      s.seed = (uint64_t)n;
    } else if (cli_progress_flag(argv[i], &prog)) {
    } else {
      return cli_usage_error("train", "unexpected argument '%s'", argv[i]);
    }
  }
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
