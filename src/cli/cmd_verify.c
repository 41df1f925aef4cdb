/* nbrdf verify: a baked latent texture against the ground truth of the
 * parameters it was baked from (docs/VERIFY.md). */
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_params.h"
#include "cli/cli_progress.h"
#include "cli/cli_tiles.h"
#include "cli/verify_tiles.h"
#include "core/output_file.h"
#include "nbrdf/verify.h"
#include "verify/verify_write.h"

typedef struct verify_args {
  cli_params params;
  const char *texture, *bundle, *json, *heatmap, *gate;
  const char *level; /* --level as typed, for messages */
  int gate_k;        /* index of --gate's word */
  double max_error;  /* percent; < 0: none */
  int worst;
  nbrdf_verify_options o;
  cli_progress_state ps;
} verify_args;

static int read_level(const char *cmd, const cli_opt *o, const char *v) {
  verify_args *a = o->dest;
  uint64_t level;
  if (!strcmp(v, "all"))
    a->o.level = NBRDF_VERIFY_ALL_LEVELS;
  else if (cli_parse_index(v, &level))
    a->o.level = level > INT_MAX ? INT_MAX : (int)level; /* the texture says which exist */
  else
    return cli_opt_bad(cmd, o->name, "a mip level (an integer, 0 the full size) or 'all'", v);
  a->level = v;
  return 0;
}

static void verify_options(verify_args *a, cli_opt_visit visit, void *user) {
  // clang-format off
  const cli_opt t[] = {
      {.help = "inputs (as for 'nbrdf bake'; --roughness defaults to the texture's setting):"},
      CLI_PARAMS_OPTIONS(&a->params),
      {.help = "\noptions:"},
      {.type = CLI_OPT_PATH, .name = "--bundle", .meta = "DIR", .dest = &a->bundle,
       .help = "the bundle the texture was baked with (default: the\n"
               "default bundle, see 'nbrdf --version'); another one\n"
               "is refused (checksum)"},
      {.type = CLI_OPT_INT, .name = "--texels", .meta = "N", .lo = 1, .hi = 100000000,
       .dest = &a->o.texels,
       .help = "per level: all texels of a level with at most N, else a\n"
               "stratified sample of N (default 256)"},
      {.type = CLI_OPT_CUSTOM, .name = "--level", .meta = "K|all", .dest = a, .parse = read_level,
       .help = "mip level to verify (default 0)"},
      {.type = CLI_OPT_INT, .name = "--spp", .meta = "N", .lo = 1, .hi = 100000000,
       .dest = &a->o.walks,
       .help = "ground-truth random walks per lobe image, per each of its\n"
               "two runs (default 256; noise falls as 1/sqrt(N))"},
      {.type = CLI_OPT_INT, .name = "--footprint", .meta = "N", .lo = 1, .hi = 1024,
       .dest = &a->o.footprint_max,
       .help = "level-0 texels averaged per coarser texel, at most\n(default 16)"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .dest = &a->o.seed,
       .help = "seed of the ground truth and of the sample (default 0)"},
      {.type = CLI_OPT_INT, .name = "--threads", .meta = "T", .lo = 0, .hi = 4096,
       .dest = &a->o.threads, .help = "threads for the ground truth; 0 = all cores (default 0)"},
      {.type = CLI_OPT_PATH, .name = "--json", .meta = "FILE", .dest = &a->json,
       .help = "the full report as JSON (docs/VERIFY.md)"},
      {.type = CLI_OPT_PATH, .name = "--heatmap", .meta = "FILE.png", .dest = &a->heatmap,
       .help = "lobe error per texel of the first level verified"},
      {.type = CLI_OPT_DOUBLE, .name = "--max-error", .meta = "PCT", .lo = 0, .hi = 1e308,
       .dest = &a->max_error, .help = "exit 1 when the --gate statistic exceeds PCT percent"},
      {.type = CLI_OPT_ENUM, .name = "--gate", .choices = "worst|p90|median", .dest = &a->gate_k,
       .help = "the statistic --max-error applies to (default worst)"},
      {.type = CLI_OPT_INT, .name = "--worst", .meta = "N", .lo = 0, .hi = 1000000,
       .dest = &a->worst, .help = "texels listed in the summary (default 5)"},
      CLI_PROGRESS_OPTION(&a->ps, "progress as JSON lines on stdout"),
      {0},
  };
  // clang-format on
  visit(user, NULL, t);
}

static void verify_args_init(verify_args *a) {
  memset(a, 0, sizeof *a);
  cli_params_init(&a->params);
  a->max_error = -1.0, a->worst = 5;
  a->o = (nbrdf_verify_options)NBRDF_VERIFY_OPTIONS_DEFAULT;
  a->ps = cli_progress_init(CLI_PROGRESS_BAR, NULL);
}

void cmd_verify_options(cli_opt_visit visit, void *user) {
  verify_args a;
  verify_args_init(&a);
  verify_options(&a, visit, user);
}

void cmd_verify_usage(FILE *out) {
  fprintf(out, "usage: nbrdf verify LATENT.exr --alpha1 V --eta V --alpha2 V --r0 V --albedo V\n"
               "                    --sigma-t V [options]\n"
               "\n"
               "Compares a baked latent texture with the physics it stands for: per texel, the\n"
               "decoded lobe images (64x64 at theta_i = 0, 30, 60, 80 degrees) against those of\n"
               "the Monte Carlo ground truth of the texel's parameters (lobe error and albedo\n"
               "error of docs/METRICS.md). A texel of mip level k is compared with the average\n"
               "of the ground truth over its level-0 footprint. Pass the same inputs as to\n"
               "'nbrdf bake'.\n"
               "A tile set ('latent.<UDIM>.exr', maps as tile patterns too) is verified with\n"
               "one texture's sample spread over its tiles: per-tile and overall figures\n"
               "(docs/VERIFY.md, \"Tile sets\").\n"
               "\n");
  cmd_verify_options(cli_options_help_visit, out);
  fprintf(out, "\n"
               "exit status: 0 verified (within --max-error when given), 1 over --max-error, a\n"
               "texture holding non-finite latents, or an error (another bundle or format\n"
               "version, a damaged file: the message says which); 2 bad usage\n");
}

static void print_params(const nbrdf_verify_texel *t, int colours) {
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    printf(" %s=", nbrdf_bake_param_name((nbrdf_bake_param_id)id));
    int same = colours == 1 ||
               (t->params[id][0] == t->params[id][1] && t->params[id][0] == t->params[id][2]);
    for (int c = 0; c < (same ? 1 : colours); c++)
      printf("%s%.4g", c ? "," : "", (double)t->params[id][c]);
  }
}

static int worse_first(const void *a, const void *b) {
  double x = (*(const nbrdf_verify_texel *const *)a)->lobe_error;
  double y = (*(const nbrdf_verify_texel *const *)b)->lobe_error;
  return (x < y) - (x > y);
}

static void print_summary_row(const char *label, const nbrdf_verify_summary *s) {
  printf("  %-6s %7zu %9.2f %% %8.2f %% %8.2f %% %10.4f %9.2f %%\n", label, s->texels,
         100 * s->median, 100 * s->p90, 100 * s->worst, s->albedo_median, 100 * s->noise_median);
}

static void print_report(const verify_args *a, const nbrdf_verify_report *r) {
  printf("verify %s: %d x %d %s, %d level(s)\n", a->texture, r->width, r->height,
         r->colours == 3 ? "rgb" : "mono", r->levels);
  if (r->decoder.own)
    printf("decoder: own (%zu bytes, checksum %s)\n", r->decoder.size, r->decoder.checksum);
  else
    printf("decoder: bundle\n");
  printf("ground truth: %zu distinct BRDF(s), 2 runs x %d walks per lobe image; "
         "reference noise = lobe error between its two runs\n",
         r->references, r->walks);
  printf("  level   texels  lobe err.  p90        worst      albedo err.  ref. noise\n");
  for (int l = 0; l < r->n_levels; l++) {
    char label[16];
    snprintf(label, sizeof label, "%d", r->per_level[l].level);
    print_summary_row(label, &r->per_level[l]);
  }
  if (r->n_levels > 1) print_summary_row("all", &r->overall);
  size_t n = (size_t)a->worst < r->n_texels ? (size_t)a->worst : r->n_texels;
  const nbrdf_verify_texel **order = malloc(sizeof *order * (r->n_texels ? r->n_texels : 1));
  if (n && order) {
    for (size_t i = 0; i < r->n_texels; i++)
      order[i] = &r->texels[i];
    qsort(order, r->n_texels, sizeof *order, worse_first);
    printf("worst texels:\n");
    for (size_t i = 0; i < n; i++) {
      const nbrdf_verify_texel *t = order[i];
      printf("  level %d (%d, %d): lobe %.2f %%, albedo %.4f, max albedo %.4f;", t->level, t->x,
             t->y, 100 * t->lobe_error, t->albedo_error, t->max_albedo);
      print_params(t, r->colours);
      if (t->footprint > 1) printf(" (mean of a %d-texel footprint)", t->footprint);
      printf("\n");
    }
  }
  free(order);
  if (r->below_trained_alpha)
    printf("note: %zu look-up(s) have alpha1 or alpha2 below the model's trained range (alpha "
           "%g); the ground truth is of the values as given, %s\n",
           r->below_trained_alpha, r->alpha_trained_min,
           r->alpha_clamped_by_texture
               ? "while this fast texture was baked with them clamped to the trained minimum "
                 "(a fitted or specialised bake fits them as given: docs/BAKE.md, \"Sharp coats\")"
               : "which this texture's level fitted");
  printf("energy: max decoded directional albedo of the compared texels %.4f%s\n", r->max_albedo,
         r->max_albedo > 1.01 ? " (above 1.01: the model creates energy there)" : "");
  printf("cost: %.2f s ground truth, %.2f s decoding (%zu distinct latents, %zu decoder "
         "queries)\n",
         r->reference_seconds, r->decode_seconds, r->decoded, r->decoder_queries);
}

static int finish(const verify_args *a, const nbrdf_verify_report *r) {
  size_t damaged = r->nonfinite;
  double stat = !strcmp(a->gate, "median") ? r->overall.median
                : !strcmp(a->gate, "p90")  ? r->overall.p90
                                           : r->overall.worst;
  int over = a->max_error >= 0 && !(100 * stat <= a->max_error);
  if (a->ps.json)
    printf("{\"event\":\"done\",\"texels\":%zu,\"median_pct\":%.4f,\"p90_pct\":%.4f,"
           "\"worst_pct\":%.4f,\"damaged\":%zu,\"pass\":%s}\n",
           r->n_texels, 100 * r->overall.median, 100 * r->overall.p90,
           isfinite(r->overall.worst) ? 100 * r->overall.worst : -1.0, damaged,
           damaged || over ? "false" : "true");
  if (damaged)
    return cli_fail("verify",
                    "FAIL: %s: %zu texel(s) hold non-finite latents, the first at level %d "
                    "(%d, %d): a damaged file",
                    a->texture, damaged, r->nonfinite_level, r->nonfinite_x, r->nonfinite_y);
  if (over)
    return cli_fail("verify", "FAIL: %s lobe error %.2f %% exceeds --max-error %g %%", a->gate,
                    100 * stat, a->max_error);
  if (!a->ps.json && a->max_error >= 0)
    printf("PASS: %s lobe error %.2f %% <= %g %%\n", a->gate, 100 * stat, a->max_error);
  return CLI_EXIT_OK;
}

int cmd_verify(int argc, char **argv) {
  verify_args a;
  verify_args_init(&a);
  cli_positionals pos = {&a.texture, 1, 0, "LATENT.exr"};
  cli_parse_call call = {"verify", NULL, argc, 1, argv, &pos, 0};
  verify_options(&a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_verify_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  static const char *const gates[] = {"worst", "p90", "median"};
  a.gate = gates[a.gate_k];
  cli_params *params = &a.params;
  if (!a.texture) return cli_usage_error("verify", "which texture? (nbrdf verify LATENT.exr ...)");
  int missing = cli_params_require("verify", params);
  if (missing != CLI_EXIT_OK) return missing;
  if (cli_params_any_tiled(params) && !cli_tiles_is_pattern(a.texture))
    return cli_usage_error("verify",
                           "the maps are tile patterns but '%s' names one texture: give the "
                           "set's pattern ('latent.<UDIM>.exr'), or the tile's own maps",
                           a.texture);
  /* A level the texture lacks is a bad option whatever its size (7 or 10^20): say which levels
   * there are. An unreadable texture is left to nbrdf_verify, which says why. */
  if (a.o.level != NBRDF_VERIFY_ALL_LEVELS) {
    int levels = cli_texture_levels(a.texture, -1, NULL, NULL);
    if (levels > 0 && a.o.level >= levels)
      return cli_level_error("verify", "--level", a.texture, levels, a.level);
  }
  if (params->roughness_given) a.o.roughness = (int)params->roughness;
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  char used[PATH_MAX];
  int loaded = cli_model_load("verify", a.bundle, &model, used, sizeof used);
  if (loaded != CLI_EXIT_OK) return loaded;
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  cli_inputs_add(&inputs, a.texture);
  cli_inputs_add_params(&inputs, params);
  cli_inputs_add_model(&inputs, model);
  const char *outputs[2] = {a.json, a.heatmap};
  if (cli_outputs_check("verify", &inputs, outputs, 2) != CLI_EXIT_OK) {
    nbrdf_model_destroy(model);
    return CLI_EXIT_FAILURE;
  }
  if (!nbrdf_model_is_trained(model))
    fprintf(stderr, "nbrdf verify: warning: bundle '%s' is untrained (random networks)\n", used);
  if (cli_tiles_is_pattern(a.texture)) {
    verify_tiles_job job = {params, model, a.o, a.texture, a.json, a.max_error, a.gate, &a.ps};
    int rc = a.heatmap ? cli_usage_error("verify", "--heatmap draws one texture, not a tile set: "
                                                   "give one tile's file")
                       : verify_tiles_run(&job);
    nbrdf_model_destroy(model);
    cli_inputs_free(&inputs);
    return rc;
  }
  cli_progress_start(&a.ps);
  a.o.progress = cli_progress, a.o.user = &a.ps, a.o.cancel = cli_cancel_flag();
  cli_cancel_watch();
  nbrdf_verify_report *rep = NULL;
  nbrdf_status st = nbrdf_verify(model, a.texture, &params->in, &a.o, &rep, &err);
  cli_cancel_unwatch();
  nbrdf_model_destroy(model);
  cli_params_explain(&err);
  if (st != NBRDF_OK) return cli_fail_error("verify", &err);
  if (!a.ps.json) print_report(&a, rep);
  /* Both outputs or neither: a report without its heat-map looks like a finished run. */
  core_output_file files[2];
  int n = 0;
  const char *texture[1] = {a.texture}; /* the model's paths went with it; checked above */
  if (a.json && (st = core_output_file_open(&files[n], a.json, texture, 1, &err)) == NBRDF_OK)
    st = verify_write_json_to(rep, a.texture, 0, &files[n++], &err);
  if (st == NBRDF_OK && a.heatmap &&
      (st = core_output_file_open(&files[n], a.heatmap, texture, 1, &err)) == NBRDF_OK)
    st = verify_write_heatmap_to(rep, rep->per_level[0].level, 0.0, &files[n++], &err);
  if (st == NBRDF_OK) {
    st = core_output_file_commit_all(files, n, &err);
  } else {
    for (int i = 0; i < n; i++)
      core_output_file_abort(&files[i]);
  }
  int code = st != NBRDF_OK ? cli_fail_error("verify", &err) : finish(&a, rep);
  nbrdf_verify_report_free(rep);
  return code;
}
