/* nbrdf bake: parameter maps or constants -> a latent OpenEXR texture. */
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/bake_tiles.h"
#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_device.h"
#include "cli/cli_outputs.h"
#include "cli/cli_params.h"
#include "cli/cli_progress.h"
#include "cli/cli_range.h"
#include "nbrdf/bake.h"
#include "nbrdf/fit.h"
#include "nbrdf/model.h"

typedef struct bake_args {
  cli_params params;
  nbrdf_bake_options opts;
  const char *out, *bundle, *decoder;
  const char *tiles; /* --tiles */
  int force;
  cli_progress_state ps;
  uint64_t energy_audit;
  int budget_given, compact_given, max_error_given, fit_energy_given;
  double fit_energy; /* --fit-energy (0: off) */
  const char *fit; /* --fit */
} bake_args;

/* "WxH" or "N" (square), each 1..NBRDF_BAKE_SIZE_MAX. */
static int parse_size(const char *text, int *w, int *h) {
  char a[64], *x;
  long lw, lh;
  if (strlen(text) >= sizeof a) return 0;
  snprintf(a, sizeof a, "%s", text);
  x = strchr(a, 'x');
  if (!x) x = strchr(a, 'X');
  if (x) *x = '\0';
  if (!cli_parse_int(a, 1, NBRDF_BAKE_SIZE_MAX, &lw)) return 0;
  if (!x)
    lh = lw;
  else if (!cli_parse_int(x + 1, 1, NBRDF_BAKE_SIZE_MAX, &lh))
    return 0;
  *w = (int)lw, *h = (int)lh;
  return 1;
}

static int read_size(const char *cmd, const cli_opt *o, const char *v) {
  bake_args *a = o->dest;
  if (parse_size(v, &a->params.in.width, &a->params.in.height)) return 0;
  char what[96];
  snprintf(what, sizeof what, "WxH (or N for NxN), each an integer in [1, %d]",
           NBRDF_BAKE_SIZE_MAX);
  return cli_opt_bad(cmd, o->name, what, v);
}

/* --accuracy and --compact: --compact implies compact, so another level with it is refused,
 * whichever comes first. */
static int read_accuracy(const char *cmd, const cli_opt *o, const char *v) {
  bake_args *a = o->dest;
  int level = nbrdf_bake_accuracy_parse(v);
  if (level < 0)
    return cli_opt_bad(cmd, o->name, "fast, fitted, specialised, compact or auto", v);
  /* auto with --compact: the compact level is auto's top rung (bake_auto.h). */
  if (a->compact_given && level != NBRDF_BAKE_COMPACT && level != NBRDF_BAKE_AUTO)
    return cli_usage_error(cmd, "--compact goes with --accuracy compact, not '%s'", v);
  a->opts.accuracy = (nbrdf_bake_accuracy)level;
  return 0;
}

static int read_compact(const char *cmd, const cli_opt *o, const char *v) {
  bake_args *a = o->dest;
  int k = 0, w = 0;
  if (!cli_parse_compact(v, &k, &w)) return cli_opt_bad(cmd, o->name, CLI_COMPACT_EXPECTED, v);
  if (a->opts.accuracy != NBRDF_BAKE_FAST && a->opts.accuracy != NBRDF_BAKE_COMPACT &&
      a->opts.accuracy != NBRDF_BAKE_AUTO)
    return cli_usage_error(cmd, "--compact goes with --accuracy compact, not '%s'",
                           nbrdf_bake_accuracy_name(a->opts.accuracy));
  if (a->opts.accuracy != NBRDF_BAKE_AUTO) a->opts.accuracy = NBRDF_BAKE_COMPACT;
  a->compact_given = 1;
  a->opts.compact_dim = k, a->opts.compact_width = w;
  return 0;
}

static int read_budget(const char *cmd, const cli_opt *o, const char *v) {
  bake_args *a = o->dest;
  double b;
  if (!cli_parse_double(v, &b) || !(b > 0.0) || b > 1e7)
    return cli_opt_bad(cmd, o->name, "a number of seconds in (0, 1e7]", v);
  a->opts.budget = b, a->budget_given = 1;
  return 0;
}

static void bake_options(bake_args *a, cli_opt_visit visit, void *user) {
  static const int mip_values[] = {0, 1, 0};
  // clang-format off
  const cli_opt t[] = {
      {.help = "inputs (shared with 'nbrdf verify'):"},
      CLI_PARAMS_OPTIONS(&a->params),
      {.help = "\noptions:"},
      {.type = CLI_OPT_PATH, .name = "--output", .alias = "-o", .meta = "FILE", .dest = &a->out,
       .help = "the texture to write (written whole or not at all); with\n"
               "maps given as tile patterns ('rough.<UDIM>.exr'), a pattern\n"
               "too: one texture per tile (docs/FARM.md, \"Tile sets\")"},
      {.type = CLI_OPT_STRING, .name = "--tiles", .meta = "LIST", .dest = &a->tiles,
       .help = "a tile set's tiles to bake, e.g. 1001,1003-1005 (default:\n"
               "every tile the maps have)"},
      {.type = CLI_OPT_FLAG, .name = "--force", .dest = &a->force, .value = 1,
       .help = "a tile set: bake the tiles whose texture is up to date\n"
               "too (by default they are skipped)"},
      {.type = CLI_OPT_FLAG, .name = "--half", .dest = &a->opts.storage, .value = NBRDF_BAKE_HALF,
       .help = "latent storage half (the default)"},
      {.type = CLI_OPT_FLAG, .name = "--float", .dest = &a->opts.storage, .value = NBRDF_BAKE_FLOAT,
       .help = "latent storage float"},
      {.type = CLI_OPT_ENUM, .name = "--mip-levels", .meta = "full|1", .choices = "full|1|0",
       .values = mip_values, .dest = &a->opts.mip_levels,
       .help = "the full mip chain (default) or level 0 only (OpenEXR\n"
               "mip chains are complete)"},
      {.type = CLI_OPT_INT, .name = "--tile", .meta = "N", .lo = 8, .hi = 1024,
       .dest = &a->opts.tile_size, .help = "tile edge in texels (default 64)"},
      {.type = CLI_OPT_CUSTOM, .name = "--size", .meta = "WxH", .dest = a, .parse = read_size,
       .help = "output size (1..65536 each; default: the maps' size, or\n"
               "1x1 when every input is a constant); maps of another\n"
               "size need --resample bilinear"},
      {.type = CLI_OPT_ENUM, .name = "--compression", .choices = "zip|piz|rle|none",
       .dest = &a->opts.compression,
       .help = "lossless EXR compression (default zip: smallest; rle or\n"
               "none write faster, see docs/BAKE.md)"},
      {.type = CLI_OPT_PATH, .name = "--bundle", .meta = "DIR", .dest = &a->bundle,
       .help = "model bundle (default: $NBRDF_BUNDLE, else the installed\n"
               "one: see 'nbrdf --version')"},
      {.type = CLI_OPT_PATH, .name = "--decoder", .meta = "FILE", .dest = &a->decoder,
       .help = "a decoder.safetensors of the bundle's latent size (a fine-\n"
               "tuned copy, say) that the texture carries and is decoded\n"
               "with (format version 2, docs/LATENT-TEXTURE.md); default:\n"
               "none, the bundle's decoder (a version-1 texture). It takes\n"
               "the bundle decoder's place in every stage: specialised\n"
               "carries it fine-tuned to the scene, compact the small\n"
               "decoder distilled from that fine-tuned copy"},
      {.type = CLI_OPT_ENUM, .name = "--range", .choices = "clamp|refuse", .dest = &a->opts.range,
       .help = "values outside the model's trained ranges: clamp (default)\n"
               "or stop naming the file and texel; either way each\n"
               "parameter outside is reported first, in the units typed"},
      {.type = CLI_OPT_INT, .name = "--quantise", .meta = "BITS", .lo = 2, .hi = 16,
       .dest = &a->opts.quantise_bits,
       .help = "round every parameter to 2^BITS levels over its trained\n"
               "range (2..16; default off): fewer distinct tuples for\n"
               "smooth float maps, at a measured cost (docs/BAKE.md)"},
      {.type = CLI_OPT_U64, .name = "--energy-audit", .meta = "N", .hi = 1099511627776.0,
       .dest = &a->energy_audit,
       .help = "decoded directional albedo of the first N distinct latents\n"
               "(16384; 0: off): the worst goes into the header as\n"
               "nbrdf:maxAlbedo, a warning names it above 1.01"},
      {.type = CLI_OPT_CUSTOM, .name = "--accuracy",
       .meta = "fast|fitted|specialised|compact|auto",
       .choices = "fast|fitted|specialised|compact|auto", .dest = a, .parse = read_accuracy,
       .help = "fast (default): the universal networks; fitted: latents\n"
               "fitted to the layered ground truth of the scene's own\n"
               "BRDFs (representative tuples; any reader decodes it);\n"
               "specialised: also a decoder fine-tuned to the scene,\n"
               "carried in the texture (format 2); compact: as\n"
               "specialised, then 8 latent channels per colour channel\n"
               "and a small decoder distilled for the scene (fast to\n"
               "decode, a third of the channels); auto: the cheapest of\n"
               "them whose held-out error meets --max-error.\n"
               "docs/BAKE.md measures the trade"},
      {.type = CLI_OPT_DOUBLE, .name = "--max-error", .meta = "P", .lo = 1e-6, .hi = 1000.0,
       .dest = &a->opts.max_error, .seen = &a->max_error_given,
       .help = "auto: the held-out lobe error to meet, in percent\n"
               "(verify's metric): fast is measured first, then fitted,\n"
               "specialised (compact too with --compact) are tried, each\n"
               "at --budget, until one meets it"},
      {.type = CLI_OPT_FLAG, .name = "--no-fallback", .dest = &a->opts.no_fallback, .value = 1,
       .help = "fitted/specialised/compact: bake the level even when its\n"
               "held-out error is worse than fast's (by default such a\n"
               "bake falls back to fast and says so)"},
      {.type = CLI_OPT_DOUBLE, .name = "--fit-energy", .meta = "LAMBDA", .lo = 0.0, .hi = 1e6,
       .dest = &a->fit_energy, .seen = &a->fit_energy_given,
       .help = "specialised/compact: weight of the energy term in the\n"
               "decoder fine-tune (default 0.1; 0: off, for measuring it;\n"
               "the held-out check still falls back on energy creation)"},
      {.type = CLI_OPT_FLAG, .name = "--require", .dest = &a->opts.require, .value = 1,
       .help = "auto: fail (exit 1, no file) when no level within the\n"
               "budget meets --max-error, instead of baking the best"},
      {.type = CLI_OPT_CUSTOM, .name = "--compact", .meta = "K[,WIDTH]", .dest = a,
       .parse = read_compact,
       .help = "compact's latent channels per colour channel (1..8,\n"
               "default 8) and decoder width (4..256, default 32);\n"
               "implies --accuracy compact (with auto: compact is tried\n"
               "after specialised meets --max-error)"},
      {.type = CLI_OPT_CUSTOM, .name = "--budget", .meta = "SECONDS", .dest = a,
       .parse = read_budget,
       .help = "fitted/specialised/compact/auto (each level tried): the\n"
               "cost-model seconds the ground truth and fit may take\n"
               "(defaults 120 / 300 / 400; about the wall time on one\n"
               "free core; the result does not depend on the machine or\n"
               "its load)"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .dest = &a->opts.seed,
       .help = "above fast: random walks and tuple selection (1)"},
      {.type = CLI_OPT_PATH, .name = "--fit", .meta = "FILE", .dest = &a->fit,
       .help = "bake with the fit 'nbrdf fit' wrote (its level, no\n"
               "fitting): refused when made with another bundle, other\n"
               "options or from other maps"},
      CLI_DEVICE_OPTION(&a->opts.device),
      CLI_PROGRESS_OPTION(&a->ps, "progress as JSON lines on stdout (for tools), instead of\n"
                                  "the bar drawn on stderr when it is a terminal"),
      {0},
  };
  // clang-format on
  visit(user, NULL, t);
}

static void bake_args_init(bake_args *a) {
  memset(a, 0, sizeof *a);
  cli_params_init(&a->params);
  a->opts = (nbrdf_bake_options)NBRDF_BAKE_OPTIONS_DEFAULT;
  a->ps = cli_progress_init(CLI_PROGRESS_BAR, NULL);
  a->energy_audit = a->opts.energy_audit;
}

void cmd_bake_options(cli_opt_visit visit, void *user) {
  bake_args a;
  bake_args_init(&a);
  bake_options(&a, visit, user);
}

void cmd_bake_usage(FILE *out) {
  fprintf(out, "usage: nbrdf bake --alpha1 V --eta V --alpha2 V --r0 V --albedo V --sigma-t V\n"
               "                  -o OUT.exr [options]\n"
               "\n"
               "Bakes a layered BRDF (rough dielectric coat over a rough conductor, with a slab\n"
               "of albedo A and optical depth sigma_t between them) into a tiled, mip-mapped\n"
               "latent OpenEXR texture (docs/LATENT-TEXTURE.md). Each V is a constant ('0.3',\n"
               "or '0.8,0.5,0.2' for RGB; decimal, no hex/inf/nan) or an existing image file\n"
               "(grey or RGB, either optionally with alpha, which is ignored: colour under\n"
               "alpha 0 is read as stored; a regular file, at most 65536x65536; all maps one\n"
               "size, or --resample). Write './0.5' for a file named like a number.\n"
               "The texture is mono when every input is grey, else RGB (one BRDF per channel).\n"
               "Every option is '--name value' or '--name=value'.\n"
               "\n");
  cmd_bake_options(cli_options_help_visit, out);
  fprintf(
      out,
      "\n"
      "Ctrl-C, SIGTERM or SIGHUP cancel cleanly: no output file is left. An output that\n"
      "is one of the inputs (a map, a bundle file), a FIFO or device, or read-only is\n"
      "refused (docs/RELIABILITY.md).\n"
      "exit status: 0 success, 1 failure (the message names the file and texel), 2 bad usage\n");
}

static void on_warning(void *user, const char *message) {
  const cli_progress_state *p = user;
  if (p->json) {
    printf("{\"event\":\"warning\",\"message\":");
    cli_json_string(stdout, message);
    printf("}\n");
  }
  fprintf(stderr, "nbrdf bake: warning: %s\n", message);
}

/* Where the networks run: one line on stderr (the user is the progress state, as warnings'). */
static void on_note(void *user, const char *message) {
  (void)user;
  cli_device_note("bake", message);
}

/* auto's outcome in one line: the level chosen, its error, every level tried. */
static void auto_line(FILE *out, const nbrdf_bake_report *rep) {
  fprintf(out, "nbrdf bake: auto: %s %s, held-out lobe error %.2f %% (target %g %%; tried:",
          rep->met ? "chose" : "no level met the target; baked the best,",
          nbrdf_bake_accuracy_name(rep->accuracy),
          100.0 * (rep->accuracy == NBRDF_BAKE_FAST ? rep->tried_error[0] : rep->heldout_error),
          rep->max_error);
  for (int i = 0; i < rep->tried; i++)
    fprintf(out, "%s %s %.2f %%", i ? "," : "", nbrdf_bake_accuracy_name(rep->tried_level[i]),
            100.0 * rep->tried_error[i]);
  fprintf(out, ")\n");
}

/* The summary: a "done" JSON line, or text. */
static void print_report(const bake_args *a, const nbrdf_bake_report *rep) {
  if (rep->requested == NBRDF_BAKE_AUTO) auto_line(stderr, rep);
  if (a->ps.json) {
    printf("{\"event\":\"done\",\"output\":");
    cli_json_string(stdout, a->out);
    printf(",\"width\":%d,\"height\":%d,\"channels\":%d,\"evaluated\":%zu", rep->width, rep->height,
           rep->colour_channels, rep->evaluated);
    printf(",\"device\":");
    cli_json_string(stdout, rep->device);
    if (rep->audited)
      printf(",\"audited\":%zu,\"audit_measured\":%zu,\"max_albedo\":%.5f,\"audit_cpu_s\":%.3f",
             rep->audited, rep->audit_measured, rep->max_albedo, rep->audit_seconds);
    if (rep->requested != NBRDF_BAKE_FAST)
      printf(",\"accuracy\":\"%s\",\"requested\":\"%s\",\"fell_back\":%s,\"budget\":%g,"
             "\"distinct\":%zu,\"fitted_tuples\":%zu,\"heldout_tuples\":%zu,"
             "\"heldout_error\":%.5f,\"heldout_error_fast\":%.5f",
             nbrdf_bake_accuracy_name(rep->accuracy), nbrdf_bake_accuracy_name(rep->requested),
             rep->fell_back ? "true" : "false", rep->budget, rep->distinct, rep->fitted_tuples,
             rep->heldout_tuples, rep->heldout_error, rep->heldout_error_fast);
    if (rep->requested != NBRDF_BAKE_FAST && rep->fit_albedo_tuples)
      printf(",\"fit_max_albedo\":%.5f,\"fit_max_albedo_fast\":%.5f,\"creates_energy\":%s",
             rep->fit_max_albedo, rep->fit_max_albedo_fast,
             rep->creates_energy ? "true" : "false");
    if (rep->requested == NBRDF_BAKE_AUTO) {
      printf(",\"max_error\":%g,\"met\":%s,\"tried\":[", rep->max_error,
             rep->met ? "true" : "false");
      for (int i = 0; i < rep->tried; i++)
        printf("%s{\"level\":\"%s\",\"heldout_error\":%.5f}", i ? "," : "",
               nbrdf_bake_accuracy_name(rep->tried_level[i]), rep->tried_error[i]);
      printf("]");
      if (!rep->met) printf(",\"suggested_budget\":%g", rep->suggested_budget);
    }
    if (rep->compact_dim)
      printf(",\"compact\":%d,\"decoder_macs\":%lld,\"variance_kept\":%.5f", rep->compact_dim,
             rep->decoder_macs, rep->compact_kept);
    printf("}\n");
  } else {
    printf("wrote %s: %d x %d %s, %zu BRDFs (%zu evaluated, %zu reused from earlier bands)\n",
           a->out, rep->width, rep->height, rep->colour_channels == 3 ? "rgb" : "mono", rep->brdfs,
           rep->evaluated, rep->reused);
    if (rep->audited)
      printf("energy audit: max decoded directional albedo %.4f over %zu distinct latents (%zu "
             "measured, %.2f CPU-s)\n",
             rep->max_albedo, rep->audited, rep->audit_measured, rep->audit_seconds);
    if (rep->accuracy != NBRDF_BAKE_FAST || rep->fell_back)
      printf("accuracy %s (budget %g s): %zu of %zu distinct tuples fitted; lobe error on %zu "
             "held-out tuples: median %.2f %% (fast: %.2f %%)%s\n",
             nbrdf_bake_accuracy_name(rep->fell_back && rep->requested != NBRDF_BAKE_AUTO
                                          ? rep->requested
                                          : rep->accuracy),
             rep->budget, rep->fitted_tuples, rep->distinct, rep->heldout_tuples,
             100.0 * rep->heldout_error, 100.0 * rep->heldout_error_fast,
             rep->fell_back ? "; worse than fast: the texture is fast's" : "");
    if ((rep->accuracy != NBRDF_BAKE_FAST || rep->fell_back) && rep->fit_albedo_tuples)
      printf("energy guard: decoded directional albedo up to %.3f on the fit's %zu tuples "
             "(fast: %.3f)%s\n",
             rep->fit_max_albedo, rep->fit_albedo_tuples, rep->fit_max_albedo_fast,
             rep->creates_energy ? "; creates energy" : "");
    if (rep->compact_dim)
      printf("compact: %d latent channels per colour channel (%.2f %% of the scene's latent "
             "variance), decoder %lld multiply-adds per query\n",
             rep->compact_dim, 100.0 * rep->compact_kept, rep->decoder_macs);
    /* Above fitted the texture does not carry --decoder itself: say what became of it. */
    if (a->decoder && rep->compact_dim)
      printf("decoder: %s, fine-tuned to the scene, taught the compact decoder the texture "
             "carries\n",
             a->decoder);
    else if (a->decoder && rep->accuracy == NBRDF_BAKE_SPECIALISED)
      printf("decoder: %s, fine-tuned to the scene, is the decoder the texture carries\n",
             a->decoder);
  }
}

int cmd_bake(int argc, char **argv) {
  bake_args a;
  bake_args_init(&a);
  nbrdf_error err = {0};
  if (cli_device_default("bake", &a.opts.device) < 0) return CLI_EXIT_USAGE;
  cli_parse_call call = {"bake", NULL, argc, 1, argv, NULL, 0};
  bake_options(&a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_bake_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  a.opts.energy_audit = (size_t)a.energy_audit;
  const char *out = a.out, *decoder = a.decoder;
  int missing = cli_params_require("bake", &a.params);
  if (missing != CLI_EXIT_OK) return missing;
  a.opts.roughness = a.params.roughness;
  if (a.budget_given && a.opts.accuracy == NBRDF_BAKE_FAST)
    return cli_usage_error(
        "bake", "--budget applies to --accuracy fitted, specialised, compact or auto, not fast");
  if (a.fit_energy_given) a.opts.fit_energy = a.fit_energy > 0.0 ? a.fit_energy : -1.0;
  if (a.opts.accuracy == NBRDF_BAKE_AUTO && !a.max_error_given)
    return cli_usage_error("bake", "--accuracy auto needs --max-error P (percent)");
  if (a.opts.accuracy != NBRDF_BAKE_AUTO && (a.max_error_given || a.opts.require))
    return cli_usage_error("bake", "--max-error and --require go with --accuracy auto");
  if (a.opts.accuracy == NBRDF_BAKE_AUTO && a.fit)
    return cli_usage_error("bake", "--accuracy auto chooses a level; --fit has its own");
  if (!out) return cli_usage_error("bake", "-o OUT.exr is required");
  nbrdf_model *model = NULL;
  char used[PATH_MAX];
  int loaded = cli_model_load("bake", a.bundle, &model, used, sizeof used);
  if (loaded != CLI_EXIT_OK) return loaded;
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  cli_inputs_add_params(&inputs, &a.params);
  cli_inputs_add_model(&inputs, model);
  if (a.fit) cli_inputs_add(&inputs, a.fit);
  if (decoder) {
    /* The texture carries this decoder (format version 2). */
    nbrdf_model *with = NULL;
    if (nbrdf_model_with_decoder_file(model, decoder, &with, &err) != NBRDF_OK) {
      nbrdf_model_destroy(model);
      cli_inputs_free(&inputs);
      return cli_fail_error("bake", &err);
    }
    nbrdf_model_destroy(model);
    model = with;
    cli_inputs_add(&inputs, decoder);
  }
  if (cli_output_check("bake", &inputs, out) != CLI_EXIT_OK) {
    nbrdf_model_destroy(model);
    return CLI_EXIT_FAILURE;
  }
  /* The options against the model (a budget too small for the level and this decoder): a bad
   * option is a usage error, whereas nbrdf_bake's own failures are the inputs'. */
  if (nbrdf_bake_options_check(model, &a.opts, &err) != NBRDF_OK) {
    nbrdf_model_destroy(model);
    cli_inputs_free(&inputs);
    return cli_usage_error("bake", "%s%s", a.budget_given ? "--budget: " : "",
                           strncmp(err.message, "bake: ", 6) ? err.message : err.message + 6);
  }
  /* A fit made before (--fit): opened once, for every texture the command bakes. */
  nbrdf_fit *fit = NULL;
  if (a.fit && nbrdf_fit_open(a.fit, &fit, &err) != NBRDF_OK) {
    nbrdf_model_destroy(model);
    cli_inputs_free(&inputs);
    return cli_fail_error("bake", &err);
  }
  a.opts.fit = fit;

  if (!nbrdf_model_is_trained(model))
    fprintf(stderr, "nbrdf bake: warning: bundle '%s' is untrained (random networks)\n", used);

  if (bake_tiles_wanted(&a.params, out, a.tiles, a.force)) {
    bake_tiles_job job = {&a.params, a.opts, out, a.tiles, a.force, model, decoder, &a.ps};
    int rc = bake_tiles_run(&job);
    nbrdf_fit_destroy(fit);
    nbrdf_model_destroy(model);
    cli_inputs_free(&inputs);
    return rc;
  }
  cli_progress_start(&a.ps);
  a.opts.progress = cli_progress;
  a.opts.warning = on_warning;
  a.opts.note = on_note;
  a.opts.range_report = cli_range_report;
  a.opts.user = &a.ps;
  a.opts.cancel = cli_cancel_flag();
  cli_cancel_watch();
  nbrdf_bake_report rep;
  nbrdf_status st = nbrdf_bake(model, &a.params.in, &a.opts, out, &rep, &err);
  cli_cancel_unwatch();
  nbrdf_fit_destroy(fit);
  nbrdf_model_destroy(model);
  if (st != NBRDF_OK) return cli_progress_fail("bake", st, &err, &a.ps);
  print_report(&a, &rep);
  return CLI_EXIT_OK;
}
