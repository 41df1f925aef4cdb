/* nbrdf fit: the fit of an accuracy level made once, kept in a .nbfit file, for
 * `nbrdf bake --fit` to bake any number of textures (the tiles of a set) with. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_params.h"
#include "cli/cli_progress.h"
#include "nbrdf/bake.h"
#include "nbrdf/fit.h"
#include "nbrdf/model.h"
#include "texture/tile_set.h"

typedef struct fit_args {
  cli_params params;
  nbrdf_bake_options opts;
  const char *out, *bundle, *decoder;
  cli_progress_state ps;
  int accuracy_given;
} fit_args;

static int read_compact(const char *cmd, const cli_opt *o, const char *v) {
  fit_args *a = o->dest;
  int k = 0, w = 0;
  if (!cli_parse_compact(v, &k, &w)) return cli_opt_bad(cmd, o->name, CLI_COMPACT_EXPECTED, v);
  a->opts.compact_dim = k, a->opts.compact_width = w;
  return 0;
}

static void fit_options(fit_args *a, cli_opt_visit visit, void *user) {
  static const int levels[] = {NBRDF_BAKE_FITTED, NBRDF_BAKE_SPECIALISED, NBRDF_BAKE_COMPACT};
  // clang-format off
  const cli_opt t[] = {
      {.help = "inputs (as 'nbrdf bake'; the bake with the fit names the same ones):"},
      CLI_PARAMS_OPTIONS(&a->params),
      {.help = "\noptions:"},
      {.type = CLI_OPT_PATH, .name = "--output", .alias = "-o", .meta = "FILE", .dest = &a->out,
       .help = "the fit to write, e.g. scene.nbfit (written whole or not\n"
               "at all)"},
      {.type = CLI_OPT_ENUM, .name = "--accuracy", .choices = "fitted|specialised|compact",
       .values = levels, .dest = &a->opts.accuracy, .seen = &a->accuracy_given,
       .help = "the level to fit (required): as 'nbrdf bake --accuracy'"},
      {.type = CLI_OPT_CUSTOM, .name = "--compact", .meta = "K[,WIDTH]", .dest = a,
       .parse = read_compact,
       .help = "compact's latent channels per colour channel (1..8,\n"
               "default 8) and decoder width (4..256, default 32)"},
      {.type = CLI_OPT_DOUBLE, .name = "--budget", .meta = "SECONDS", .lo = 1e-9, .hi = 1e7,
       .dest = &a->opts.budget,
       .help = "the cost-model seconds the ground truth and fit may take\n"
               "(defaults 120 / 300 / 400, as 'nbrdf bake')"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .dest = &a->opts.seed,
       .help = "random walks and tuple selection (1)"},
      {.type = CLI_OPT_ENUM, .name = "--range", .choices = "clamp|refuse", .dest = &a->opts.range,
       .help = "values outside the model's trained ranges: clamp\n"
               "(default) or stop naming the file and texel; the bake\n"
               "with the fit must use the same"},
      {.type = CLI_OPT_INT, .name = "--quantise", .meta = "BITS", .lo = 2, .hi = 16,
       .dest = &a->opts.quantise_bits,
       .help = "round every parameter to 2^BITS levels (as 'nbrdf bake');\n"
               "the bake with the fit must use the same"},
      {.type = CLI_OPT_PATH, .name = "--bundle", .meta = "DIR", .dest = &a->bundle,
       .help = "model bundle (default: $NBRDF_BUNDLE, else the installed\n"
               "one); the bake with the fit must use the same"},
      {.type = CLI_OPT_PATH, .name = "--decoder", .meta = "FILE", .dest = &a->decoder,
       .help = "a decoder.safetensors the fit starts from instead of the\n"
               "bundle's (as 'nbrdf bake --decoder'); the bake with the\n"
               "fit must pass the same"},
      CLI_PROGRESS_OPTION(&a->ps, "progress as JSON lines on stdout (for tools), instead of\n"
                                  "the bar drawn on stderr when it is a terminal"),
      {0},
  };
  // clang-format on
  visit(user, NULL, t);
}

static void fit_args_init(fit_args *a) {
  memset(a, 0, sizeof *a);
  cli_params_init(&a->params);
  a->opts = (nbrdf_bake_options)NBRDF_BAKE_OPTIONS_DEFAULT;
  a->ps = cli_progress_init(CLI_PROGRESS_BAR, NULL);
}

void cmd_fit_options(cli_opt_visit visit, void *user) {
  fit_args a;
  fit_args_init(&a);
  fit_options(&a, visit, user);
}

void cmd_fit_usage(FILE *out) {
  fprintf(out, "usage: nbrdf fit --alpha1 V --eta V --alpha2 V --r0 V --albedo V --sigma-t V\n"
               "                 --accuracy fitted|specialised|compact -o SCENE.nbfit [options]\n"
               "\n"
               "The fit of an accuracy level ('nbrdf bake --accuracy', docs/BAKE.md) made once\n"
               "and kept in a file: the scene's representative tuples, their ground truth, the\n"
               "latent correction and the fine-tuned or compact decoder, the held-out error,\n"
               "the bundle's checksum, the options that shape the tuples and each map's content\n"
               "hash (docs/FIT-FILE.md). 'nbrdf bake ... --fit SCENE.nbfit' then bakes with it,\n"
               "on any machine, with no fitting: every texture baked with one fit carries the\n"
               "same decoder (nbrdf:decoderChecksum) and names the fit in nbrdf:accuracy.\n"
               "The inputs are as 'nbrdf bake' takes them (a constant or a map for each); a\n"
               "map may be a UDIM tile pattern ('rough.<UDIM>.exr'): the fit then gathers the\n"
               "tuples of every tile present, for one fit shared by the whole set.\n"
               "\n");
  cmd_fit_options(cli_options_help_visit, out);
  fprintf(out,
          "\n"
          "Ctrl-C, SIGTERM or SIGHUP cancel cleanly: no file is left.\n"
          "exit status: 0 success, 1 failure (the message names the file and texel), 2 bad "
          "usage\n");
}

/* The inputs of every tile: one set when no map is a tile pattern, else one per tile the
 * patterns agree on (texture/tile_set.h), each map's path that tile's file; a constant or a
 * plain path serves every tile. The paths are malloc'ed into paths[tile * 6 + id]. */
static int expand_tiles(const cli_params *p, nbrdf_bake_inputs **tiles, size_t *n,
                        char ***paths) {
  static const char *const names[NBRDF_BAKE_PARAM_COUNT] = {"--alpha1", "--eta",    "--alpha2",
                                                            "--r0",     "--albedo", "--sigma-t"};
  nbrdf_error err = {0};
  texture_tile_map maps[NBRDF_BAKE_PARAM_COUNT];
  int m = 0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    if (p->tiled[id]) maps[m++] = (texture_tile_map){names[id], p->in.param[id].path};
  texture_tile_set set = {0};
  if (m && texture_tile_set_resolve(maps, m, &set, &err) != NBRDF_OK)
    return cli_fail_error("fit", &err);
  *n = set.count ? (size_t)set.count : 1;
  *tiles = calloc(*n, sizeof **tiles);
  *paths = calloc(*n * NBRDF_BAKE_PARAM_COUNT, sizeof **paths);
  if (!*tiles || !*paths) return cli_fail("fit", "out of memory for %zu tiles", *n);
  nbrdf_status st = NBRDF_OK;
  for (size_t t = 0; t < *n; t++) {
    (*tiles)[t] = p->in;
    for (int id = 0; st == NBRDF_OK && set.count && id < NBRDF_BAKE_PARAM_COUNT; id++) {
      if (!p->tiled[id]) continue;
      texture_tile_pattern *tp = NULL;
      char **path = &(*paths)[t * NBRDF_BAKE_PARAM_COUNT + id];
      st = texture_tile_pattern_parse(p->in.param[id].path, &tp, &err);
      if (st == NBRDF_OK) st = texture_tile_pattern_path(tp, set.tiles[t], path, &err);
      texture_tile_pattern_free(tp);
      (*tiles)[t].param[id].path = *path;
    }
  }
  return st == NBRDF_OK ? CLI_EXIT_OK : cli_fail_error("fit", &err);
}

static void print_report(const fit_args *a, const nbrdf_fit_info *f) {
  const char *level = nbrdf_bake_accuracy_name(f->accuracy);
  if (a->ps.json) {
    printf("{\"event\":\"done\",\"output\":");
    cli_json_string(stdout, a->out);
    printf(",\"accuracy\":\"%s\",\"tiles\":%d,\"budget\":%g,\"distinct\":%zu,\"fitted_tuples\":%zu,"
           "\"heldout_tuples\":%zu,\"heldout_error\":%.5f,\"heldout_error_fast\":%.5f,"
           "\"decoder_checksum\":\"%s\",\"fit_checksum\":\"%s\"}\n",
           level, f->tiles, f->budget, f->distinct, f->fitted_tuples, f->heldout_tuples,
           f->heldout_error, f->heldout_error_fast, f->decoder_checksum, f->file_checksum);
    return;
  }
  printf("wrote %s: %s fit (budget %g s) over %d set(s) of inputs: %zu of %zu distinct tuples "
         "fitted; lobe error on %zu held-out tuples: median %.2f %% (fast: %.2f %%)\n",
         a->out, level, f->budget, f->tiles, f->fitted_tuples, f->distinct, f->heldout_tuples,
         100.0 * f->heldout_error, 100.0 * f->heldout_error_fast);
  if (f->decoder_checksum[0])
    printf("decoder %s: the decoder every texture baked with this fit carries\n",
           f->decoder_checksum);
}

int cmd_fit(int argc, char **argv) {
  fit_args a;
  fit_args_init(&a);
  nbrdf_error err = {0};
  cli_parse_call call = {"fit", NULL, argc, 1, argv, NULL, 0};
  fit_options(&a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_fit_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  int missing = cli_params_require("fit", &a.params);
  if (missing != CLI_EXIT_OK) return missing;
  if (!a.accuracy_given)
    return cli_usage_error("fit", "--accuracy fitted, specialised or compact is required");
  if ((a.opts.compact_dim || a.opts.compact_width) && a.opts.accuracy != NBRDF_BAKE_COMPACT)
    return cli_usage_error("fit", "--compact goes with --accuracy compact, not '%s'",
                           nbrdf_bake_accuracy_name(a.opts.accuracy));
  if (!a.out) return cli_usage_error("fit", "-o SCENE.nbfit is required");
  a.opts.roughness = a.params.roughness;
  nbrdf_model *model = NULL;
  char used[PATH_MAX];
  int loaded = cli_model_load("fit", a.bundle, &model, used, sizeof used);
  if (loaded != CLI_EXIT_OK) return loaded;
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  cli_inputs_add_params(&inputs, &a.params);
  cli_inputs_add_model(&inputs, model);
  if (a.decoder) {
    nbrdf_model *with = NULL;
    if (nbrdf_model_with_decoder_file(model, a.decoder, &with, &err) != NBRDF_OK) {
      nbrdf_model_destroy(model);
      cli_inputs_free(&inputs);
      return cli_fail_error("fit", &err);
    }
    nbrdf_model_destroy(model);
    model = with;
    cli_inputs_add(&inputs, a.decoder);
  }
  int checked = cli_output_check("fit", &inputs, a.out);
  cli_inputs_free(&inputs);
  if (checked != CLI_EXIT_OK) {
    nbrdf_model_destroy(model);
    return CLI_EXIT_FAILURE;
  }
  if (nbrdf_bake_options_check(model, &a.opts, &err) != NBRDF_OK) {
    nbrdf_model_destroy(model);
    return cli_usage_error("fit", "%s",
                           strncmp(err.message, "bake: ", 6) ? err.message : err.message + 6);
  }
  if (!nbrdf_model_is_trained(model))
    fprintf(stderr, "nbrdf fit: warning: bundle '%s' is untrained (random networks)\n", used);

  cli_progress_start(&a.ps);
  a.opts.progress = cli_progress;
  a.opts.user = &a.ps;
  a.opts.cancel = cli_cancel_flag();
  cli_cancel_watch();
  nbrdf_fit_info info;
  nbrdf_bake_inputs *tiles = NULL;
  size_t n_tiles = 0;
  char **paths = NULL;
  int expanded = expand_tiles(&a.params, &tiles, &n_tiles, &paths);
  nbrdf_status st = NBRDF_OK;
  if (expanded == CLI_EXIT_OK)
    st = nbrdf_fit_run(model, tiles, n_tiles, &a.opts, a.out, &info, &err);
  cli_cancel_unwatch();
  nbrdf_model_destroy(model);
  for (size_t i = 0; paths && i < n_tiles * NBRDF_BAKE_PARAM_COUNT; i++)
    free(paths[i]);
  free(paths);
  free(tiles);
  if (expanded != CLI_EXIT_OK) return expanded;
  if (st != NBRDF_OK) return cli_progress_fail("fit", st, &err, &a.ps);
  print_report(&a, &info);
  return CLI_EXIT_OK;
}
