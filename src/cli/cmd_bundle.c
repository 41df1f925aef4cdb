/* nbrdf bundle: create an untrained model bundle, describe one, or measure its
 * energy audit's slopes. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/bake_audit_slopes.h"
#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_outputs.h"
#include "cli/cli_progress.h"
#include "model/audit_slopes.h"
#include "model/audit_slopes_write.h"
#include "model/bundle.h"

typedef struct bundle_args {
  const char *dir, *name, *preset;
  uint64_t seed;
  int force;
  int bases, sharp_bases;
  uint64_t slopes_seed;
  cli_progress_state prog;
} bundle_args;

static void bundle_options(bundle_args *a, cli_opt_visit visit, void *user) {
  // clang-format off
  const cli_opt init[] = {
      {.type = CLI_OPT_STRING, .name = "--name", .meta = "NAME", .dest = &a->name,
       .help = "model name (default: the folder's last component)"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .dest = &a->seed,
       .help = "unsigned 64-bit seed (default 1); same seed, same bytes"},
      {.type = CLI_OPT_STRING, .name = "--decoder", .meta = "PRESET",
       .choices = "paper|large|medium|small", .dest = &a->preset,
       .help = "paper (1.06 M MACs/query), large (103 k), medium (27 k),\n"
               "small (5.3 k; default)"},
      {.type = CLI_OPT_FLAG, .name = "--force", .dest = &a->force, .value = 1,
       .help = "replace a bundle already in DIR (refused otherwise)"},
      {0},
  };
  // clang-format on
  const cli_opt info[] = {{0}};
  // clang-format off
  const cli_opt slopes[] = {
      {.type = CLI_OPT_INT, .name = "--bases", .meta = "N", .dest = &a->bases, .lo = 0,
       .hi = 1 << 20, .help = "base tuples over the whole range (4096: 64 per region)"},
      {.type = CLI_OPT_INT, .name = "--clearcoat-bases", .meta = "N", .dest = &a->sharp_bases,
       .lo = 0, .hi = 1 << 20,
       .help = "base tuples of a sharp clearcoat (alpha1 at the range's low end; 256)"},
      {.type = CLI_OPT_U64, .name = "--seed", .meta = "S", .dest = &a->slopes_seed,
       .help = "the draws' seed (11)"},
      CLI_PROGRESS_OPTION(&a->prog, "progress as JSON lines on stdout"),
      {0},
  };
  // clang-format on
  visit(user, "init", init);
  visit(user, "info", info);
  visit(user, "audit-slopes", slopes);
}

static void bundle_args_init(bundle_args *a) {
  a->dir = NULL, a->name = NULL, a->preset = "small", a->seed = 1, a->force = 0;
  a->bases = 4096, a->sharp_bases = 256, a->slopes_seed = 11;
  a->prog = cli_progress_init(CLI_PROGRESS_COUNT, NULL);
}

void cmd_bundle_options(cli_opt_visit visit, void *user) {
  bundle_args a;
  bundle_args_init(&a);
  bundle_options(&a, visit, user);
}

void cmd_bundle_usage(FILE *out) {
  fprintf(out,
          "usage: nbrdf bundle init DIR [--name NAME] [--seed S] [--decoder PRESET] [--force]\n"
          "       nbrdf bundle info DIR\n"
          "       nbrdf bundle audit-slopes DIR [--bases N] [--clearcoat-bases N] [--seed S]\n"
          "                                 [--progress=json]\n"
          "\n"
          "A model bundle is a folder with decoder.safetensors, layering.safetensors,\n"
          "sampler.safetensors, base_tables.safetensors, model.json and MODEL_CARD.md.\n"
          "\n"
          "init  writes a complete bundle of RANDOMLY INITIALISED networks and base tables of\n"
          "      smooth random latents, marked untrained in model.json and the card: its BRDF\n"
          "      values mean nothing, but the bake, the evaluator, the Blender add-on and the\n"
          "      shaders can be built and tested with it before training finishes.\n");
  cmd_bundle_options(cli_options_help_visit, out);
  fprintf(out, "info  loads and validates a bundle and prints its name, checksum, architecture,\n"
               "      multiply-adds per query and base-table grids.\n"
               "audit-slopes  measures how fast the bundle's decoded albedo moves with each\n"
               "      parameter (the bake's energy audit clears a tuple near a measured one\n"
               "      with them) and records them in DIR/model.json; a bundle without them\n"
               "      has every distinct tuple of a bake measured. Run it after `nbrdf train\n"
               "      bundle` (about 3 CPU-minutes with the defaults; docs/BAKE.md, \"Slopes\").\n"
               "\n"
               "exit status: 0 success, 1 failure (the message names the file), 2 bad usage\n");
}

/* Parses `bundle SUB ...` into `a`: CLI_OPTIONS_OK, CLI_OPTIONS_HELP (printed) or a usage
 * error's status. */
static int bundle_parse(const char *sub, int argc, char **argv, bundle_args *a) {
  bundle_args_init(a);
  cli_positionals pos = {&a->dir, 1, 0, "folder"};
  cli_parse_call call = {"bundle", sub, argc, 2, argv, &pos, 0};
  bundle_options(a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) cmd_bundle_usage(stdout);
  if (call.rc == CLI_OPTIONS_OK && !a->dir)
    return cli_usage_error("bundle", "%s needs a folder", sub);
  return call.rc;
}

static int bundle_init(int argc, char **argv) {
  bundle_args a;
  int rc = bundle_parse("init", argc, argv, &a);
  if (rc != CLI_OPTIONS_OK) return rc == CLI_OPTIONS_HELP ? CLI_EXIT_OK : rc;
  const char *dir = a.dir, *name = a.name, *preset = a.preset;
  uint64_t seed = a.seed;
  int force = a.force;
  int known = 0;
  for (int p = 0; model_decoder_presets[p]; p++)
    known |= !strcmp(preset, model_decoder_presets[p]);
  if (!known)
    return cli_usage_error("bundle", "unknown decoder preset '%s' (paper, large, medium, small)",
                           preset);
  char json[4096];
  snprintf(json, sizeof json, "%s/model.json", dir);
  if (!force && access(json, F_OK) == 0)
    return cli_fail("bundle", "%s already holds a bundle; use --force to replace it", dir);
  if (!name) {
    size_t len = strlen(dir);
    while (len > 1 && dir[len - 1] == '/')
      len--;
    size_t start = len;
    while (start > 0 && dir[start - 1] != '/')
      start--;
    static char base[64];
    size_t n = len - start < sizeof base - 1 ? len - start : sizeof base - 1;
    memcpy(base, dir + start, n);
    base[n] = '\0';
    name = n > 0 && strcmp(base, ".") && strcmp(base, "..") ? base : "untrained";
  }
  cli_inputs none; /* nothing read; the files replaced are still checked */
  cli_inputs_init(&none);
  if (cli_outputs_check_bundle("bundle", &none, dir) != CLI_EXIT_OK) return CLI_EXIT_FAILURE;
  nbrdf_error err = {0};
  if (model_bundle_init_random(dir, name, seed, preset, &err) != NBRDF_OK)
    return cli_fail_error("bundle", &err);
  nbrdf_model *m = NULL;
  if (nbrdf_model_load(dir, &m, &err) != NBRDF_OK) return cli_fail_error("bundle", &err);
  printf("wrote untrained bundle '%s' to %s (checksum %s, decoder %s)\n", nbrdf_model_name(m), dir,
         nbrdf_model_checksum(m), preset);
  nbrdf_model_destroy(m);
  return CLI_EXIT_OK;
}

static int bundle_info(int argc, char **argv) {
  bundle_args a;
  int rc = bundle_parse("info", argc, argv, &a);
  if (rc != CLI_OPTIONS_OK) return rc == CLI_OPTIONS_HELP ? CLI_EXIT_OK : rc;
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  if (nbrdf_model_load(a.dir, &m, &err) != NBRDF_OK) return cli_fail_error("bundle", &err);
  printf("bundle:    %s\n", a.dir);
  model_bundle_describe(m, stdout);
  nbrdf_model_destroy(m);
  return CLI_EXIT_OK;
}

static int bundle_audit_slopes(int argc, char **argv) {
  bundle_args a;
  int rc = bundle_parse("audit-slopes", argc, argv, &a);
  if (rc != CLI_OPTIONS_OK) return rc == CLI_OPTIONS_HELP ? CLI_EXIT_OK : rc;
  if (a.bases + a.sharp_bases < 1)
    return cli_usage_error("bundle", "audit-slopes needs at least one base tuple");
  nbrdf_error err = {0};
  nbrdf_model *m = NULL;
  if (nbrdf_model_load(a.dir, &m, &err) != NBRDF_OK) return cli_fail_error("bundle", &err);
  bake_audit_slopes_options o = BAKE_AUDIT_SLOPES_OPTIONS_DEFAULT;
  o.bases = a.bases, o.sharp_bases = a.sharp_bases, o.seed = a.slopes_seed;
  cli_progress_state prog = a.prog;
  o.progress = cli_progress, o.user = &prog;
  cli_progress_start(&prog);
  cli_cancel_watch();
  double table[BAKE_AUDIT_REGIONS * BAKE_AUDIT_REGIONS * NBRDF_BAKE_PARAM_COUNT * BAKE_AUDIT_DIRS];
  nbrdf_status st = bake_audit_slopes_measure(m, &o, table, NULL, &err);
  if (!prog.json) fputc('\n', stderr);
  char note[256];
  snprintf(note, sizeof note,
           "nbrdf bundle audit-slopes --bases %d --clearcoat-bases %d --seed %llu", a.bases,
           a.sharp_bases, (unsigned long long)a.slopes_seed);
  if (!st) st = model_audit_slopes_write(a.dir, nbrdf_model_checksum(m), table, note, &err);
  if (st) {
    nbrdf_model_destroy(m);
    return cli_progress_fail("bundle", st, &err, &prog);
  }
  double mx[NBRDF_BAKE_PARAM_COUNT];
  bake_audit_slope_max(table, mx);
  printf("%s/model.json: audit slopes of '%s' (checksum %s) from %d base tuples, %.0f s; "
         "largest per parameter:",
         a.dir, nbrdf_model_name(m), nbrdf_model_checksum(m), a.bases + a.sharp_bases,
         cli_progress_seconds(&prog));
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    printf(" %s %.2f", nbrdf_bake_param_name((nbrdf_bake_param_id)id), mx[id]);
  putchar('\n');
  nbrdf_model_destroy(m);
  return CLI_EXIT_OK;
}

int cmd_bundle(int argc, char **argv) {
  if (argc < 2) return cli_usage_error("bundle", "missing action: init, info or audit-slopes");
  if (!strcmp(argv[1], "init")) return bundle_init(argc, argv);
  if (!strcmp(argv[1], "info")) return bundle_info(argc, argv);
  if (!strcmp(argv[1], "audit-slopes")) return bundle_audit_slopes(argc, argv);
  return cli_usage_error("bundle", "unknown action '%s' (init, info or audit-slopes)", argv[1]);
}
