/* nbrdf evaluate: the docs/METRICS.md figures of a model on the held-out sets. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_progress.h"
#include "eval/evaluate.h"
#include "model/bundle.h"

typedef struct evaluate_args {
  eval_settings s;
  const char *bundle, *decoder, *sets, *json, *plots;
  cli_progress_state prog;
} evaluate_args;

static void evaluate_options(evaluate_args *a, cli_opt_visit visit, void *user) {
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_PATH, .name = "--bundle", .meta = "DIR", .dest = &a->bundle,
       .help = "the model bundle to evaluate"},
      {.type = CLI_OPT_PATH, .name = "--decoder", .meta = "FILE", .dest = &a->decoder,
       .help = "a decoder alone (sets rep and single)"},
      {.type = CLI_OPT_STRING, .name = "--sets", .meta = "LIST", .dest = &a->sets,
       .help = "held-out sets, comma-separated: rep, single, layer,\nlayer3, table, tails, tails-rep, extremes"},
      {.type = CLI_OPT_INT, .name = "--count", .meta = "N", .lo = 1, .hi = 100000,
       .dest = &a->s.count, .help = "BRDFs per set (100)"},
      {.type = CLI_OPT_INT, .name = "--walks", .meta = "N", .lo = 2, .hi = 1 << 30,
       .dest = &a->s.walks, .help = "whole-lobe walks per reference image (16000)"},
      {.type = CLI_OPT_INT, .name = "--noise-brdfs", .meta = "N", .lo = 0, .hi = 100000,
       .dest = &a->s.noise_brdfs, .help = "BRDFs whose reference noise is reported (10)"},
      {.type = CLI_OPT_INT, .name = "--steps", .meta = "N", .lo = 1, .hi = 1000000,
       .dest = &a->s.project_steps, .help = "projection steps (1000)"},
      {.type = CLI_OPT_PATH, .name = "--cache", .meta = "DIR", .dest = &a->s.cache_dir,
       .help = "keeps references between runs"},
      {.type = CLI_OPT_PATH, .name = "--json", .meta = "FILE", .dest = &a->json,
       .help = "the figures as JSON"},
      {.type = CLI_OPT_PATH, .name = "--plots", .meta = "DIR", .dest = &a->plots,
       .help = "lobe images of the worst BRDFs"},
      CLI_PROGRESS_OPTION(&a->prog, "progress as JSON lines on stdout"),
      {0},
  };
  // clang-format on
  visit(user, NULL, t);
}

static void evaluate_args_init(evaluate_args *a) {
  memset(a, 0, sizeof *a);
  a->s = (eval_settings)EVAL_SETTINGS_DEFAULT;
  a->prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
}

void cmd_evaluate_options(cli_opt_visit visit, void *user) {
  evaluate_args a;
  evaluate_args_init(&a);
  evaluate_options(&a, visit, user);
}

void cmd_evaluate_usage(FILE *out) {
  fprintf(out,
          "usage: nbrdf evaluate (--bundle DIR | --decoder FILE) [--sets rep,single,layer,...]\n"
          "                      [--count N] [--walks N] [--noise-brdfs N] [--steps N]\n"
          "                      [--cache DIR] [--json FILE] [--plots DIR] [--progress=json]\n"
          "\n"
          "Lobe error and albedo error (docs/METRICS.md) of a model on the held-out sets,\n"
          "which no training ever sees: rep (two-layer BRDFs projected), single (conductors\n"
          "and dielectrics projected), layer (two-layer, tables + layering network, as a bake\n"
          "does), layer3 (three layers, recursive layering), table (the single BRDFs from the\n"
          "bundle's base tables: their interpolation error), tails (as layer, on coats\n"
          "with eta <= 1.2, alpha1 <= 0.05 or both, a third each, figures per region),\n"
          "tails-rep (the tails BRDFs projected: the decoder's own limit there),\n"
          "extremes (nine named constants at the corners, e.g. a smooth coat over a\n"
          "mirror, each with its decoded and true directional albedo per theta_i).\n"
          "A decoder alone serves rep, single and tails-rep. References: exact for single BRDFs, "
          "the whole-lobe estimator with --walks\n"
          "walks per image (16000) for layered ones; its own seed-to-seed error on the first\n"
          "--noise-brdfs BRDFs (10) is reported. --cache DIR keeps references between runs.\n"
          "Also per set: the point-wise error (median |f/f_ref - 1| where f_ref > 1 %% of the\n"
          "lobe's peak) and the error at the mirror direction at theta_i 0, 30, 60, 80, 85,\n"
          "89 deg, and the decoded directional albedo there (importance-sampled) against the\n"
          "ground truth's: the largest, and the largest excess. Each median comes\n"
          "with its 90 %% bootstrap interval (a tails region of 33 BRDFs spans points).\n"
          "Defaults: --sets rep,single (plus layer,layer3,table with a bundle), --count 100,\n"
          "--steps 1000 projection steps.\n"
          "\n");
  cmd_evaluate_options(cli_options_help_visit, out);
}

int cmd_evaluate(int argc, char **argv) {
  evaluate_args a;
  evaluate_args_init(&a);
  cli_parse_call call = {"evaluate", NULL, argc, 1, argv, NULL, 0};
  evaluate_options(&a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_evaluate_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  eval_settings s = a.s;
  const char *bundle = a.bundle, *decoder = a.decoder, *sets = a.sets, *json = a.json,
             *plots = a.plots;
  cli_progress_state prog = a.prog;
  if (!bundle == !decoder) return cli_usage_error("evaluate", "give --bundle or --decoder");
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  model_decoder *dec = NULL;
  nbrdf_status st =
      bundle ? nbrdf_model_load(bundle, &model, &err) : model_decoder_load(decoder, &dec, &err);
  if (st) return cli_fail_error("evaluate", &err);
  cli_inputs inputs; /* the --cache references are read and rewritten: that is the cache */
  cli_inputs_init(&inputs);
  cli_inputs_add(&inputs, decoder);
  cli_inputs_add_model(&inputs, model);
  int rc = cli_output_check("evaluate", &inputs, json);
  for (int k = 0; k < EVAL_SET_COUNT && plots && rc == CLI_EXIT_OK; k++) {
    char median[4096], worst[4096];
    snprintf(median, sizeof median, "%s_median.png", eval_set_name((eval_set)k));
    snprintf(worst, sizeof worst, "%s_worst.png", eval_set_name((eval_set)k));
    const char *const names[3] = {median, worst, NULL};
    rc = cli_outputs_check_in("evaluate", &inputs, plots, names);
  }
  if (rc != CLI_EXIT_OK) {
    nbrdf_model_destroy(model);
    model_decoder_destroy(dec);
    return rc;
  }
  char list[256];
  snprintf(list, sizeof list, "%s",
           sets    ? sets
           : model ? "rep,single,layer,layer3,table"
                   : "rep,single");
  eval_result results[EVAL_SET_COUNT];
  int n_results = 0;
  cli_progress_start(&prog);
  s.progress = cli_progress, s.user = &prog;
  cli_cancel_watch();
  for (char *tok = strtok(list, ","); tok && !st; tok = strtok(NULL, ",")) {
    eval_set set;
    if (!eval_set_parse(tok, &set) || n_results == EVAL_SET_COUNT) {
      st = NBRDF_ERR_ARGUMENT;
      snprintf(err.message, sizeof err.message,
               "unknown or repeated set '%s' (rep, single, layer, layer3, table, tails, "
               "tails-rep, extremes)",
               tok);
      break;
    }
    eval_settings ss = s; /* a fixed set (extremes) has as many BRDFs as it has */
    if (eval_set_size_max(set) && ss.count > eval_set_size_max(set))
      ss.count = eval_set_size_max(set);
    st = eval_run(model, dec, set, &ss, &results[n_results], &err);
    if (st) break;
    const eval_result *r = &results[n_results++];
    if (!prog.json) fputc('\n', stderr);
    printf("%-7s median %6.2f %% (90 %% interval %.2f-%.2f)  p90 %6.2f %%  worst %6.2f %% (#%d)  "
           "median albedo error %.4f  max albedo %.4f  reference noise %.2f %%\n",
           tok, 100 * r->median, 100 * r->median_lo, 100 * r->median_hi, 100 * r->p90,
           100 * r->worst, r->worst_index, r->median_albedo_error, r->max_albedo,
           100 * r->ref_noise);
    printf("        point-wise median %6.2f %% (by theta_i", 100 * r->median_pointwise_all);
    for (int t = 0; t < EVAL_N_THETA_ALL; t++)
      printf(" %g: %.1f", eval_theta_all_deg[t], 100 * r->median_pointwise[t]);
    printf(" %%)\n        mirror error median by theta_i:");
    for (int t = 0; t < EVAL_N_THETA_ALL; t++)
      printf(" %g: %.1f", eval_theta_all_deg[t], 100 * r->median_mirror[t]);
    printf(" %%\n        max decoded albedo by theta_i:");
    for (int t = 0; t < EVAL_N_THETA_ALL; t++)
      printf(" %g: %.3f", eval_theta_all_deg[t], r->max_decoded_albedo[t]);
    printf("\n        max decoded - reference albedo:");
    for (int t = 0; t < EVAL_N_THETA_ALL; t++)
      printf(" %g: %+.3f", eval_theta_all_deg[t], r->max_albedo_excess[t]);
    printf("\n");
    for (int i = 0; i < r->n && set == EVAL_EXTREMES; i++) {
      const eval_case *c = &r->cases[i];
      double worst = 0.0; /* |decoded - reference albedo| over theta_i <= 85 deg */
      for (int t = 0; t < EVAL_N_THETA_ALL && eval_theta_all_deg[t] <= 85.0; t++)
        worst = fmax(worst, fabs(c->albedo[t] - c->albedo_ref[t]));
      printf("        %-42s lobe %6.2f %%  albedo |decoded - truth| <= 85 deg: %.3f  (",
             eval_extremes_name(i), 100 * c->lobe_error, worst);
      for (int t = 0; t < EVAL_N_THETA_ALL; t++)
        printf("%s%g: %.3f/%.3f", t ? ", " : "", eval_theta_all_deg[t], c->albedo[t],
               c->albedo_ref[t]);
      printf(")\n");
    }
    for (int g = 0; g < TRAIN_TAILS_REGIONS && eval_set_has_regions(set); g++)
      printf("        region %-12s median %6.2f %% (90 %% interval %.2f-%.2f)  p90 %6.2f %%  "
             "(%d BRDFs)\n",
             train_tails_region_name(g), 100 * r->region_median[g], 100 * r->region_median_lo[g],
             100 * r->region_median_hi[g], 100 * r->region_p90[g], r->region_n[g]);
    fflush(stdout);
  }
  cli_cancel_unwatch();
  const char *label = bundle ? bundle : decoder;
  if (!st && json) st = eval_write_json(json, label, &s, results, n_results, &err);
  if (!st && plots) st = eval_write_plots(plots, results, n_results, &err);
  for (int k = 0; k < n_results; k++)
    eval_result_free(&results[k]);
  nbrdf_model_destroy(model);
  model_decoder_destroy(dec);
  if (st) return cli_fail_error("evaluate", &err);
  return CLI_EXIT_OK;
}
