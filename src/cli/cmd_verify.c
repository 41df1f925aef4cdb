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
#include "core/output_file.h"
#include "nbrdf/verify.h"
#include "verify/verify_write.h"

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
               "\n"
               "inputs (as for 'nbrdf bake'; --roughness defaults to the texture's setting):\n");
  cli_params_usage(out);
  fprintf(out, "\n"
               "options:\n"
               "  --bundle DIR          the bundle the texture was baked with (default: the\n"
               "                        default bundle, see 'nbrdf --version'); another one\n"
               "                        is refused (checksum)\n"
               "  --texels N            per level: all texels of a level with at most N, else a\n"
               "                        stratified sample of N (default 256)\n"
               "  --level K|all         mip level to verify (default 0)\n"
               "  --spp N               ground-truth random walks per lobe image, per each of its\n"
               "                        two runs (default 256; noise falls as 1/sqrt(N))\n"
               "  --footprint N         level-0 texels averaged per coarser texel, at most\n"
               "                        (default 16)\n"
               "  --seed S              seed of the ground truth and of the sample (default 0)\n"
               "  --threads T           threads for the ground truth; 0 = all cores (default 0)\n"
               "  --json FILE           the full report as JSON (docs/VERIFY.md)\n"
               "  --heatmap FILE.png    lobe error per texel of the first level verified\n"
               "  --max-error PCT       exit 1 when the --gate statistic exceeds PCT percent\n"
               "  --gate worst|p90|median\n"
               "                        the statistic --max-error applies to (default worst)\n"
               "  --worst N             texels listed in the summary (default 5)\n"
               "  --progress=json       progress as JSON lines on stdout\n"
               "\n"
               "exit status: 0 verified (within --max-error when given), 1 over --max-error, a\n"
               "texture holding non-finite latents, or an error (another bundle or format\n"
               "version, a damaged file: the message says which); 2 bad usage\n");
}

typedef struct verify_args {
  const char *texture, *bundle, *json, *heatmap, *gate;
  const char *level; /* --level as typed, for messages */
  double max_error; /* percent; < 0: none */
  long worst;
  nbrdf_verify_options o;
  cli_progress_state ps;
} verify_args;

/* Parses the options other than the parameter inputs. Returns -1 when
 * argv[*i] is not one of them, else an exit status (CLI_EXIT_OK: go on). */
static int parse_option(int argc, char **argv, int *i, verify_args *a) {
  const char *v;
  long n;
  double d;
  if ((v = cli_option_value(argc, argv, i, "--bundle"))) {
    a->bundle = v;
  } else if ((v = cli_option_value(argc, argv, i, "--texels"))) {
    if (!cli_parse_int(v, 1, 100000000, &n))
      return cli_usage_error("verify", "--texels needs an integer >= 1, not '%s'", v);
    a->o.texels = (int)n;
  } else if ((v = cli_option_value(argc, argv, i, "--level"))) {
    uint64_t level;
    if (!strcmp(v, "all"))
      a->o.level = NBRDF_VERIFY_ALL_LEVELS;
    else if (cli_parse_index(v, &level))
      a->o.level = level > INT_MAX ? INT_MAX : (int)level; /* the texture says which exist */
    else if (*v)
      return cli_usage_error("verify",
                             "--level is a mip level (an integer, 0 the full size) or 'all', "
                             "not '%s'",
                             v);
    a->level = v;
  } else if ((v = cli_option_value(argc, argv, i, "--spp"))) {
    if (!cli_parse_int(v, 1, 100000000, &n))
      return cli_usage_error("verify", "--spp needs an integer >= 1, not '%s'", v);
    a->o.walks = (int)n;
  } else if ((v = cli_option_value(argc, argv, i, "--footprint"))) {
    if (!cli_parse_int(v, 1, 1024, &n))
      return cli_usage_error("verify", "--footprint needs an integer in [1, 1024], not '%s'", v);
    a->o.footprint_max = (int)n;
  } else if ((v = cli_option_value(argc, argv, i, "--seed"))) {
    char *end;
    unsigned long long s = strtoull(v, &end, 10);
    if (!*v || *end || *v == '-')
      return cli_usage_error("verify", "--seed needs an unsigned integer, not '%s'", v);
    a->o.seed = (uint64_t)s;
  } else if ((v = cli_option_value(argc, argv, i, "--threads"))) {
    if (!cli_parse_int(v, 0, 4096, &n))
      return cli_usage_error("verify", "--threads needs an integer >= 0, not '%s'", v);
    a->o.threads = (int)n;
  } else if ((v = cli_option_value(argc, argv, i, "--json"))) {
    a->json = v;
  } else if ((v = cli_option_value(argc, argv, i, "--heatmap"))) {
    a->heatmap = v;
  } else if ((v = cli_option_value(argc, argv, i, "--max-error"))) {
    if (!cli_parse_double(v, &d) || d < 0)
      return cli_usage_error("verify", "--max-error needs a percentage >= 0, not '%s'", v);
    a->max_error = d;
  } else if ((v = cli_option_value(argc, argv, i, "--gate"))) {
    if (strcmp(v, "worst") && strcmp(v, "p90") && strcmp(v, "median"))
      return cli_usage_error("verify", "--gate is worst, p90 or median, not '%s'", v);
    a->gate = v;
  } else if ((v = cli_option_value(argc, argv, i, "--worst"))) {
    if (!cli_parse_int(v, 0, 1000000, &a->worst))
      return cli_usage_error("verify", "--worst needs an integer >= 0, not '%s'", v);
  } else if (cli_progress_flag(argv[*i], &a->ps)) {
    return CLI_EXIT_OK;
  } else {
    return -1;
  }
  if (!*v) return cli_usage_error("verify", "%s needs a value", argv[*i]);
  return CLI_EXIT_OK;
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
  cli_params params;
  cli_params_init(&params);
  verify_args a = {NULL,
                   NULL,
                   NULL,
                   NULL,
                   "worst",
                   NULL,
                   -1.0,
                   5,
                   NBRDF_VERIFY_OPTIONS_DEFAULT,
                   cli_progress_init(CLI_PROGRESS_BAR, NULL)};
  for (int i = 1; i < argc; i++) {
    if (cli_is_help(argv[i])) {
      cmd_verify_usage(stdout);
      return CLI_EXIT_OK;
    }
    int used = cli_params_option("verify", argc, argv, &i, &params);
    if (used < 0) return CLI_EXIT_USAGE;
    if (used) continue;
    int st = parse_option(argc, argv, &i, &a);
    if (st > 0) return st;
    if (st == CLI_EXIT_OK) continue;
    if (argv[i][0] == '-' || a.texture)
      return cli_usage_error("verify", "unknown option, missing value or extra argument: '%s'",
                             argv[i]);
    a.texture = argv[i];
  }
  if (!a.texture) return cli_usage_error("verify", "which texture? (nbrdf verify LATENT.exr ...)");
  int missing = cli_params_require("verify", &params);
  if (missing != CLI_EXIT_OK) return missing;
  /* A level the texture lacks is a bad option whatever its size (7 or 10^20): say which levels
   * there are. An unreadable texture is left to nbrdf_verify, which says why. */
  if (a.o.level != NBRDF_VERIFY_ALL_LEVELS) {
    int levels = cli_texture_levels(a.texture, -1, NULL, NULL);
    if (levels > 0 && a.o.level >= levels)
      return cli_level_error("verify", "--level", a.texture, levels, a.level);
  }
  if (params.roughness_given) a.o.roughness = (int)params.roughness;
  nbrdf_error err = {0};
  nbrdf_model *model = NULL;
  char used[PATH_MAX];
  int loaded = cli_model_load("verify", a.bundle, &model, used, sizeof used);
  if (loaded != CLI_EXIT_OK) return loaded;
  cli_inputs inputs;
  cli_inputs_init(&inputs);
  cli_inputs_add(&inputs, a.texture);
  cli_inputs_add_params(&inputs, &params);
  cli_inputs_add_model(&inputs, model);
  const char *outputs[2] = {a.json, a.heatmap};
  if (cli_outputs_check("verify", &inputs, outputs, 2) != CLI_EXIT_OK) {
    nbrdf_model_destroy(model);
    return CLI_EXIT_FAILURE;
  }
  if (!nbrdf_model_is_trained(model))
    fprintf(stderr, "nbrdf verify: warning: bundle '%s' is untrained (random networks)\n", used);
  cli_progress_start(&a.ps);
  a.o.progress = cli_progress, a.o.user = &a.ps, a.o.cancel = cli_cancel_flag();
  cli_cancel_watch();
  nbrdf_verify_report *rep = NULL;
  nbrdf_status st = nbrdf_verify(model, a.texture, &params.in, &a.o, &rep, &err);
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
