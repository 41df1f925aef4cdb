/* nbrdf farm slurm: a tile set's bake as a farm plan (cli/farm_plan.h). The bake's own
 * arguments follow `--` exactly as `nbrdf bake` takes them; they are checked by the bake's
 * own parser now, so that a typo fails here and not on the farm, and each job gets the ones
 * its command takes (fit: those in its table; verify: the parameter inputs). */
#define _GNU_SOURCE
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/cli.h"
#include "cli/cli_params.h"
#include "cli/farm_plan.h"
#include "core/error.h"
#include "texture/oiio_shim.h"
#include "texture/tile_set.h"

/* The bake's option that picks the tiles of a set to bake. */
#define FARM_TILE_OPTION "--tiles"
#define FARM_ARGS_MAX 512

typedef struct farm_args {
  const char *plan, *partition, *account, *nbrdf;
  int submit, cpus, max_parallel;
  const char *rest[FARM_ARGS_MAX];
  cli_positionals pos;
} farm_args;

static void farm_options(farm_args *a, cli_opt_visit visit, void *user) {
  // clang-format off
  const cli_opt t[] = {
      {.type = CLI_OPT_PATH, .name = "--plan", .meta = "DIR", .dest = &a->plan,
       .help = "the folder the plan is written to (created if missing;\n"
               "the fit, logs and the verify report go there too)"},
      {.type = CLI_OPT_FLAG, .name = "--submit", .dest = &a->submit, .value = 1,
       .help = "also submit it (DIR/submit.sh: sbatch, chained with\n"
               "--dependency=afterok); run it again to resume"},
      {.type = CLI_OPT_STRING, .name = "--partition", .meta = "NAME", .dest = &a->partition,
       .help = "Slurm partition of every job (default: the cluster's)"},
      {.type = CLI_OPT_STRING, .name = "--account", .meta = "NAME", .dest = &a->account,
       .help = "Slurm account of every job (default: the user's)"},
      {.type = CLI_OPT_INT, .name = "--cpus", .meta = "N", .lo = 1, .hi = 1024, .dest = &a->cpus,
       .help = "CPUs per job, one BLAS thread each (default 2)"},
      {.type = CLI_OPT_INT, .name = "--max-parallel", .meta = "N", .lo = 0, .hi = 100000,
       .dest = &a->max_parallel,
       .help = "at most N tile jobs at once (default 0: no limit)"},
      {.type = CLI_OPT_PATH, .name = "--nbrdf", .meta = "PATH", .dest = &a->nbrdf,
       .help = "the nbrdf the jobs run, as the nodes see it (default:\n"
               "this one)"},
      {0},
  };
  // clang-format on
  visit(user, "slurm", t);
}

void cmd_farm_options(cli_opt_visit visit, void *user) {
  farm_args a;
  memset(&a, 0, sizeof a);
  farm_options(&a, visit, user);
}

void cmd_farm_usage(FILE *out) {
  fprintf(out,
          "usage: nbrdf farm slurm --plan DIR [options] -- BAKE-ARGUMENTS\n"
          "\n"
          "Plans the bake of a tile set on a Slurm cluster: BAKE-ARGUMENTS are those of\n"
          "'nbrdf bake' for the whole set (maps as '<UDIM>' patterns, -o 'out.<UDIM>.exr',\n"
          "--accuracy ...). The plan is one fit job above the fast level (DIR/scene.nbfit),\n"
          "a job array of one bake per tile after it, and a verify job after every tile\n"
          "(DIR/verify.json). DIR gets the batch scripts, submit.sh, and plan.json: the same\n"
          "jobs for any queue (command lines, dependencies, resources; docs/FARM.md).\n"
          "Every path is taken relative to the current folder, which the jobs run in: it\n"
          "and the bundle must be visible to the nodes at the same place.\n"
          "\n");
  cmd_farm_options(cli_options_help_visit, out);
  fprintf(out, "\nexit status: 0 success, 1 failure, 2 bad usage\n");
}

/* The options of a command's table, as far as routing its arguments needs. */
typedef struct known_option {
  const char *name, *alias;
  int takes_value;
} known_option;

typedef struct option_list {
  known_option o[128];
  int n;
  int found; /* the command exists */
} option_list;

static void collect(void *user, const char *sub, const cli_opt *table) {
  (void)sub;
  option_list *l = user;
  l->found = 1;
  for (const cli_opt *o = table; o->type != CLI_OPT_END || o->help; o++) {
    if (o->type == CLI_OPT_END || l->n == (int)(sizeof l->o / sizeof l->o[0])) continue;
    l->o[l->n++] = (known_option){o->name, o->alias, o->type != CLI_OPT_FLAG};
  }
}

static void options_of(const char *command, option_list *l) {
  memset(l, 0, sizeof *l);
  for (int i = 0; i < cli_command_count; i++)
    if (!strcmp(cli_commands[i].name, command) && cli_commands[i].options)
      cli_commands[i].options(collect, l);
}

static const known_option *lookup(const option_list *l, const char *name) {
  for (int i = 0; i < l->n; i++)
    if (!strcmp(l->o[i].name, name) || (l->o[i].alias && !strcmp(l->o[i].alias, name)))
      return &l->o[i];
  return NULL;
}

/* The bake's arguments sorted by who takes them. Strings are owned here ("--name=value"). */
typedef struct routed {
  char *own[3 * FARM_ARGS_MAX];
  int n_own;
  const char *bake[FARM_ARGS_MAX + 2], *fit[FARM_ARGS_MAX + 2], *verify[FARM_ARGS_MAX + 2];
  int n_bake, n_fit, n_verify;
  const char *output, *accuracy, *size, *tiles, *bundle;
  double budget;
  texture_tile_map maps[NBRDF_BAKE_PARAM_COUNT];
  int n_maps;
} routed;

static char *keep(routed *r, const char *name, const char *value) {
  char *s = NULL;
  if (value ? asprintf(&s, "%s=%s", name, value) < 0 : !(s = strdup(name))) return NULL;
  r->own[r->n_own++] = s;
  return s;
}

static int route(const char *cmd, farm_args *a, routed *r) {
  option_list bake, fit, params;
  options_of("bake", &bake);
  options_of("fit", &fit);
  cli_params p;
  cli_params_init(&p);
  const cli_opt pt[] = {CLI_PARAMS_OPTIONS(&p), {0}};
  memset(&params, 0, sizeof params);
  collect(&params, NULL, pt);
  for (int i = 0; i < a->pos.count; i++) {
    const char *arg = a->rest[i];
    if (arg[0] != '-' || !arg[1])
      return cli_usage_error(cmd, "'%s': nbrdf bake takes no positional argument", arg);
    char name[128];
    const char *eq = strchr(arg, '=');
    size_t len = eq ? (size_t)(eq - arg) : strlen(arg);
    snprintf(name, sizeof name, "%.*s", (int)(len < sizeof name ? len : sizeof name - 1), arg);
    const known_option *o = lookup(&bake, name);
    if (!o) return cli_usage_error(cmd, "'%s' is not an option of 'nbrdf bake'", name);
    const char *value = NULL;
    if (o->takes_value) {
      if (eq)
        value = eq + 1;
      else if (i + 1 < a->pos.count)
        value = a->rest[++i];
      else
        return cli_usage_error(cmd, "%s expects a value, got nothing", name);
    }
    const char *canon = o->name;
    if (!strcmp(canon, "--output")) {
      r->output = value;
      continue;
    }
    if (!strcmp(canon, FARM_TILE_OPTION)) {
      r->tiles = value;
      continue;
    }
    if (!strcmp(canon, "--progress") || !strcmp(canon, "--fit"))
      return cli_usage_error(cmd, "%s is the plan's to set; leave it out", canon);
    if (!strcmp(canon, "--accuracy")) r->accuracy = value;
    if (!strcmp(canon, "--compact") && !r->accuracy) r->accuracy = "compact";
    if (!strcmp(canon, "--size")) r->size = value;
    if (!strcmp(canon, "--bundle")) r->bundle = value;
    if (!strcmp(canon, "--budget") && cli_parse_double(value, &r->budget) == 0)
      return cli_usage_error(cmd, "--budget expects seconds, got '%s'", value);
    char *s = keep(r, canon, value);
    if (!s) return cli_fail(cmd, "out of memory");
    r->bake[r->n_bake++] = s;
    if (lookup(&fit, canon)) r->fit[r->n_fit++] = s;
    const known_option *po = lookup(&params, canon);
    if (po || !strcmp(canon, "--bundle")) r->verify[r->n_verify++] = s;
    /* the six parameters are the table's first entries */
    if (po && po - params.o < NBRDF_BAKE_PARAM_COUNT && r->n_maps < NBRDF_BAKE_PARAM_COUNT)
      r->maps[r->n_maps++] = (texture_tile_map){canon, value};
  }
  if (!fit.found && r->accuracy && strcmp(r->accuracy, "fast"))
    return cli_fail(cmd, "this nbrdf has no 'fit' command: plan the fast level only");
  return CLI_EXIT_OK;
}

static int tile_sizes(const char *cmd, const routed *r, farm_plan *plan) {
  int w = 0, h = 0;
  if (r->size && sscanf(r->size, "%dx%d", &w, &h) != 2)
    return cli_usage_error(cmd, "--size expects WxH, got '%s'", r->size);
  for (int i = 0; i < plan->n_tiles; i++) {
    plan->tiles[i].width = w, plan->tiles[i].height = h;
    if (r->size) continue;
    for (int m = 0; m < r->n_maps; m++) {
      texture_tile_pattern *pat = NULL;
      char *path = NULL;
      nbrdf_error err = {0};
      if (texture_tile_pattern_parse(r->maps[m].arg, &pat, &err) != NBRDF_OK) continue;
      int tiled = texture_tile_pattern_is_tiled(pat);
      nbrdf_status st = tiled ? texture_tile_pattern_path(pat, plan->tiles[i].tile, &path, &err)
                              : NBRDF_ERR_ARGUMENT;
      texture_tile_pattern_free(pat);
      if (st != NBRDF_OK) continue;
      texture_image_in *img = NULL;
      texture_image_info info;
      st = texture_image_open(path, 0, &img, &info, &err);
      free(path);
      if (st != NBRDF_OK) return cli_fail_error(cmd, &err);
      texture_image_close(img);
      plan->tiles[i].width = info.width, plan->tiles[i].height = info.height;
      break;
    }
  }
  return CLI_EXIT_OK;
}

static int select_tiles(const char *cmd, const routed *r, const texture_tile_set *set,
                        farm_plan *plan) {
  for (int i = 0; i < set->count; i++) plan->tiles[i].tile = set->tiles[i];
  plan->n_tiles = set->count;
  if (!r->tiles) return CLI_EXIT_OK;
  /* A list of tiles and ranges, as the bake reads it: keep those of the set. */
  int n = 0;
  char *copy = strdup(r->tiles), *save = NULL;
  if (!copy) return cli_fail(cmd, "out of memory");
  for (char *item = strtok_r(copy, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
    int lo = 0, hi = 0;
    char *dash = strchr(item, '-');
    nbrdf_error err = {0};
    if (dash) *dash = '\0';
    if (texture_tile_parse(item, &lo, &err) != NBRDF_OK ||
        (dash && texture_tile_parse(dash + 1, &hi, &err) != NBRDF_OK)) {
      free(copy);
      return cli_usage_error(cmd, "%s: %s", FARM_TILE_OPTION, err.message);
    }
    if (!dash) hi = lo;
    for (int t = lo; t <= hi; t++) {
      if (!texture_tile_set_has(set, t)) continue;
      int dup = 0;
      for (int k = 0; k < n; k++) dup |= plan->tiles[k].tile == t;
      if (!dup) plan->tiles[n++].tile = t;
    }
  }
  free(copy);
  if (n == 0) return cli_usage_error(cmd, "%s %s: none of these tiles is in the set", FARM_TILE_OPTION, r->tiles);
  plan->n_tiles = n;
  return CLI_EXIT_OK;
}

static int run_submit(const char *cmd, const char *dir) {
  char script[PATH_MAX + 16];
  snprintf(script, sizeof script, "%s/submit.sh", dir);
  fflush(NULL);
  pid_t pid = fork();
  if (pid < 0) return cli_fail(cmd, "cannot start %s (%s)", script, strerror(errno));
  if (pid == 0) {
    execlp("bash", "bash", script, (char *)NULL);
    fprintf(stderr, "nbrdf %s: cannot run bash %s (%s)\n", cmd, script, strerror(errno));
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return cli_fail(cmd, "%s failed (exit status %d); the plan is in %s", script,
                    WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), dir);
  return CLI_EXIT_OK;
}

static int plan_and_submit(const char *cmd, farm_args *a, routed *r) {
  int rc = route(cmd, a, r);
  if (rc != CLI_EXIT_OK) return rc;
  if (!r->output) return cli_usage_error(cmd, "the bake's -o 'OUT.<UDIM>.exr' is missing");
  /* The bake's own parser checks every value now. */
  {
    char *argv[3 * FARM_ARGS_MAX];
    int argc = 0;
    argv[argc++] = "bake";
    for (int i = 0; i < r->n_bake; i++) argv[argc++] = (char *)r->bake[i];
    argv[argc++] = "-o";
    argv[argc++] = (char *)r->output;
    cli_parse_call call = {cmd, NULL, argc, 1, argv, NULL, 0};
    for (int i = 0; i < cli_command_count; i++)
      if (!strcmp(cli_commands[i].name, "bake")) cli_commands[i].options(cli_options_parse_visit, &call);
    if (call.rc == CLI_OPTIONS_HELP) return cli_usage_error(cmd, "--help is not a bake argument here");
    if (call.rc != CLI_OPTIONS_OK) return call.rc;
  }
  nbrdf_error err = {0};
  texture_tile_set set;
  if (texture_tile_set_resolve(r->maps, r->n_maps, &set, &err) != NBRDF_OK)
    return cli_fail_error(cmd, &err);
  if (set.count == 0)
    return cli_usage_error(cmd, "no map is a tile pattern ('<UDIM>'): bake it with 'nbrdf bake'");
  if (texture_tile_set_check_output(&set, "-o", r->output, &err) != NBRDF_OK)
    return cli_usage_error(cmd, "%s", err.message);

  farm_plan plan;
  memset(&plan, 0, sizeof plan);
  rc = select_tiles(cmd, r, &set, &plan);
  if (rc == CLI_EXIT_OK) rc = tile_sizes(cmd, r, &plan);
  if (rc != CLI_EXIT_OK) return rc;

  char cwd[PATH_MAX], dir[PATH_MAX], exe[PATH_MAX], fit[PATH_MAX + 16], bundle[PATH_MAX];
  if (!getcwd(cwd, sizeof cwd)) return cli_fail(cmd, "cannot read the current folder (%s)", strerror(errno));
  if (a->plan[0] == '/')
    snprintf(dir, sizeof dir, "%s", a->plan);
  else if (snprintf(dir, sizeof dir, "%s/%s", cwd, a->plan) >= (int)sizeof dir)
    return cli_usage_error(cmd, "--plan: the path is too long");
  if (a->nbrdf)
    snprintf(exe, sizeof exe, "%s", a->nbrdf);
  else if (!realpath("/proc/self/exe", exe))
    return cli_fail(cmd, "cannot find this executable (%s): pass --nbrdf", strerror(errno));
  /* Every job reads the same bundle: the one this command would use. */
  if (!r->bundle) {
    if (nbrdf_default_bundle_path(bundle, sizeof bundle, &err) != NBRDF_OK)
      return cli_fail_error(cmd, &err);
    char *s = keep(r, "--bundle", bundle);
    if (!s) return cli_fail(cmd, "out of memory");
    r->bake[r->n_bake++] = s, r->fit[r->n_fit++] = s, r->verify[r->n_verify++] = s;
  }
  int fitted = r->accuracy && strcmp(r->accuracy, "fast");
  snprintf(fit, sizeof fit, "%s/scene.nbfit", dir);
  plan.dir = dir, plan.cwd = cwd, plan.nbrdf = exe, plan.output = r->output;
  plan.fit = fitted ? fit : NULL;
  plan.fit_args = (farm_argv){r->fit, r->n_fit};
  plan.bake_args = (farm_argv){r->bake, r->n_bake};
  plan.verify_args = (farm_argv){r->verify, r->n_verify};
  plan.tile_option = FARM_TILE_OPTION;
  plan.partition = a->partition, plan.account = a->account;
  plan.cpus = a->cpus, plan.max_parallel = a->max_parallel;
  double budget = r->budget > 0 ? r->budget
                  : !fitted                       ? 0
                  : !strcmp(r->accuracy, "fitted") ? NBRDF_BAKE_BUDGET_FITTED
                  : !strcmp(r->accuracy, "specialised") ? NBRDF_BAKE_BUDGET_SPECIALISED
                                                   : NBRDF_BAKE_BUDGET_COMPACT;
  if (farm_plan_write(&plan, budget, &err) != NBRDF_OK) return cli_fail_error(cmd, &err);

  int w = 0, h = 0;
  for (int i = 0; i < plan.n_tiles; i++)
    if ((double)plan.tiles[i].width * plan.tiles[i].height > (double)w * h)
      w = plan.tiles[i].width, h = plan.tiles[i].height;
  farm_resources tr = farm_tile_resources(w, h, plan.cpus);
  printf("nbrdf farm: a plan of %d tile%s in %s\n", plan.n_tiles, plan.n_tiles == 1 ? "" : "s", dir);
  if (plan.fit) {
    farm_resources fr = farm_fit_resources(budget, plan.cpus);
    printf("  fit      1 job, %d CPUs, %d MiB, %d min -> %s\n", fr.cpus, fr.memory_mib,
           fr.time_limit_s / 60, fit);
  }
  printf("  tiles    %d jobs (one array), %d CPUs, %d MiB, %d min each (largest tile %dx%d)\n",
         plan.n_tiles, tr.cpus, tr.memory_mib, tr.time_limit_s / 60, w, h);
  printf("  verify   1 job after every tile -> %s/verify.json\n", dir);
  if (!a->submit) {
    printf("submit with: bash %s/submit.sh   (any other queue: %s/plan.json)\n", dir, dir);
    return CLI_EXIT_OK;
  }
  return run_submit(cmd, dir);
}

int cmd_farm(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    cmd_farm_usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_EXIT_USAGE : CLI_EXIT_OK;
  }
  if (strcmp(argv[1], "slurm"))
    return cli_usage_error("farm", "unknown scheduler '%s' (slurm; any other queue: the plan's "
                                   "plan.json)", argv[1]);
  const char *cmd = "farm slurm";
  farm_args a;
  memset(&a, 0, sizeof a);
  a.cpus = 2;
  a.pos = (cli_positionals){a.rest, FARM_ARGS_MAX, 0, "bake argument"};
  cli_parse_call call = {cmd, "slurm", argc, 2, argv, &a.pos, 0};
  farm_options(&a, cli_options_parse_visit, &call);
  if (call.rc == CLI_OPTIONS_HELP) {
    cmd_farm_usage(stdout);
    return CLI_EXIT_OK;
  }
  if (call.rc != CLI_OPTIONS_OK) return call.rc;
  if (!a.plan) return cli_usage_error(cmd, "where does the plan go? --plan DIR");
  if (a.pos.count == 0) return cli_usage_error(cmd, "the bake's arguments follow '--'");
  routed *r = calloc(1, sizeof *r);
  if (!r) return cli_fail(cmd, "out of memory");
  int rc = plan_and_submit(cmd, &a, r);
  for (int i = 0; i < r->n_own; i++) free(r->own[i]);
  free(r);
  return rc;
}
