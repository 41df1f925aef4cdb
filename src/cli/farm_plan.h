/* A farm plan for a tile set: one fit job (levels above fast), one bake job per
 * tile that depends on it, and a verify job that depends on every tile. The
 * same plan is written as a scheduler-neutral job list (plan.json: command
 * lines, dependencies, resources) and as Slurm batch scripts (a job array over
 * the tiles, chained with --dependency=afterok by submit.sh). docs/FARM.md. */
#ifndef NBRDF_CLI_FARM_PLAN_H
#define NBRDF_CLI_FARM_PLAN_H

#include <stddef.h>

#include "nbrdf/status.h"
#include "texture/tile_pattern.h"

/* What one job asks of a node, from the measured cost of a bake (farm_plan.c). */
typedef struct farm_resources {
  int cpus;
  int memory_mib;
  int time_limit_s;
} farm_resources;

typedef struct farm_tile {
  int tile;          /* 1001.. */
  int width, height; /* of the tile's first map (0 x 0: constants only) */
} farm_tile;

/* A command line as argv (borrowed strings). */
typedef struct farm_argv {
  const char **arg;
  int n;
} farm_argv;

typedef struct farm_plan {
  const char *dir;     /* where the plan goes (absolute) */
  const char *cwd;     /* where every job runs: relative paths of the arguments (absolute) */
  const char *nbrdf;   /* the executable the jobs run (absolute) */
  const char *output;  /* the bake's -o: a tile pattern */
  const char *fit;     /* DIR/scene.nbfit, or NULL at the fast level (no fit job) */
  farm_argv fit_args;  /* `nbrdf fit` without -o */
  farm_argv bake_args; /* `nbrdf bake` without -o, the tile and --fit */
  farm_argv verify_args; /* the parameter inputs and --bundle, for `nbrdf verify` */
  const char *tile_option; /* the bake's option naming one tile of a set */
  farm_tile tiles[TEXTURE_TILE_COUNT];
  int n_tiles;
  /* Slurm: partition and account (NULL: the cluster's defaults), CPUs per job, and at most
   * this many tile jobs at once (0: no limit). */
  const char *partition, *account;
  int cpus, max_parallel;
} farm_plan;

/* Resources of a tile bake of w x h texels on `cpus` CPUs, of the fit (its cost-model
 * budget in seconds) and of the verify job over n tiles. */
farm_resources farm_tile_resources(int width, int height, int cpus);
farm_resources farm_fit_resources(double budget_s, int cpus);
farm_resources farm_verify_resources(int n_tiles, int cpus);

/* `text` quoted for a POSIX shell (single quotes; a quote inside as '\''), into buf. */
const char *farm_shell_quote(const char *text, char *buf, size_t cap);

/* Writes plan.json, fit.sbatch (when p->fit), tiles.sbatch, verify.sbatch and submit.sh into
 * p->dir (created if missing; logs/ inside it), all or none. `budget_s`: the fit's budget. */
nbrdf_status farm_plan_write(const farm_plan *p, double budget_s, nbrdf_error *err);

#endif
