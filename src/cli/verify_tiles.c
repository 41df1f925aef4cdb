#include "cli/verify_tiles.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_tiles.h"
#include "core/output_file.h"
#include "verify/verify_internal.h"

static const char *const flag_names[NBRDF_BAKE_PARAM_COUNT] = {"--alpha1", "--eta",    "--alpha2",
                                                               "--r0",     "--albedo", "--sigma-t"};

typedef struct tile_progress {
  int tile, index, count;
} tile_progress;

static int on_progress(void *user, const char *stage, double done, double total) {
  const tile_progress *tp = user;
  char fields[96];
  snprintf(fields, sizeof fields, ",\"tile\":%d,\"tile_index\":%d,\"tiles\":%d", tp->tile,
           tp->index, tp->count);
  cli_progress_json_fields(stage, done, total, fields);
  return *cli_cancel_flag();
}

/* The maps' tiles must hold every tile of the textures (plain maps and constants hold all). */
static int check_maps(const verify_tiles_job *job, const texture_tile_set *textures) {
  texture_tile_map maps[NBRDF_BAKE_PARAM_COUNT];
  int n = 0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    if (job->params->tiled[id])
      maps[n++] = (texture_tile_map){flag_names[id], job->params->in.param[id].path};
  texture_tile_set set;
  nbrdf_error err = {0};
  nbrdf_status st = texture_tile_set_resolve(maps, n, &set, &err);
  if (st == NBRDF_ERR_ARGUMENT) return cli_usage_error("verify", "%s", err.message);
  if (st != NBRDF_OK) return cli_fail_error("verify", &err);
  for (int i = 0; n && i < textures->count; i++)
    if (!texture_tile_set_has(&set, textures->tiles[i]))
      return cli_fail("verify", "%s '%s' has no tile %d (the texture '%s' has it)", maps[0].name,
                      maps[0].arg, textures->tiles[i], job->pattern);
  return CLI_EXIT_OK;
}

/* Tile `tile`'s inputs: patterns substituted (paths malloc'd into owned[]). */
static int tile_inputs(const verify_tiles_job *job, int tile, nbrdf_bake_inputs *in,
                       char *owned[NBRDF_BAKE_PARAM_COUNT]) {
  *in = job->params->in;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    owned[id] = NULL;
    if (!job->params->tiled[id]) continue;
    owned[id] = cli_tiles_path("verify", in->param[id].path, tile);
    if (!owned[id]) return CLI_EXIT_FAILURE;
    in->param[id].path = owned[id];
  }
  return CLI_EXIT_OK;
}

static cJSON *summary_json(const nbrdf_verify_summary *s) {
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "texels", (double)s->texels);
  const double v[5] = {100 * s->median, 100 * s->p90, 100 * s->worst, s->albedo_median,
                       100 * s->noise_median};
  static const char *const keys[5] = {"lobe_error_median_pct", "lobe_error_p90_pct",
                                      "lobe_error_worst_pct", "albedo_error_median",
                                      "reference_noise_median_pct"};
  for (int k = 0; k < 5; k++)
    if (isfinite(v[k]))
      cJSON_AddNumberToObject(o, keys[k], v[k]);
    else
      cJSON_AddNullToObject(o, keys[k]);
  return o;
}

static void print_row(const char *label, const nbrdf_verify_summary *s) {
  printf("  %-6s %7zu %9.2f %% %8.2f %% %8.2f %% %10.4f %9.2f %%\n", label, s->texels,
         100 * s->median, 100 * s->p90, 100 * s->worst, s->albedo_median, 100 * s->noise_median);
}

/* --json: the set's report (texture, sample, per-tile and overall figures), written whole. */
static int write_json(const verify_tiles_job *job, const texture_tile_set *set,
                      nbrdf_verify_report *const *reps, char *const *paths,
                      const nbrdf_verify_summary *overall) {
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "texture", job->pattern);
  cJSON_AddNumberToObject(root, "texels_per_level", job->o.texels);
  cJSON_AddNumberToObject(root, "seed", (double)job->o.seed);
  cJSON_AddItemToObject(root, "overall", summary_json(overall));
  cJSON *tiles = cJSON_AddArrayToObject(root, "tiles");
  for (int i = 0; i < set->count; i++) {
    cJSON *t = summary_json(&reps[i]->overall);
    cJSON_AddNumberToObject(t, "tile", set->tiles[i]);
    cJSON_AddStringToObject(t, "texture", paths[i]);
    cJSON_AddNumberToObject(t, "width", reps[i]->width);
    cJSON_AddNumberToObject(t, "height", reps[i]->height);
    cJSON_AddNumberToObject(t, "damaged", (double)reps[i]->nonfinite);
    cJSON_AddItemToArray(tiles, t);
  }
  char *text = cJSON_Print(root);
  cJSON_Delete(root);
  if (!text) return cli_fail("verify", "out of memory");
  nbrdf_error err = {0};
  const char *inputs[1] = {paths[0]};
  nbrdf_status st = core_output_file_write_all(job->json, text, strlen(text), inputs, 1, &err);
  free(text);
  return st == NBRDF_OK ? CLI_EXIT_OK : cli_fail_error("verify", &err);
}

/* The set's verdict, as a single verify's (cmd_verify.c): damaged, over --max-error, pass. */
static int verdict(const verify_tiles_job *job, const texture_tile_set *set,
                   nbrdf_verify_report *const *reps, const nbrdf_verify_summary *overall) {
  size_t damaged = 0;
  int first = -1;
  for (int i = 0; i < set->count; i++) {
    damaged += reps[i]->nonfinite;
    if (reps[i]->nonfinite && first < 0) first = i;
  }
  double stat = !strcmp(job->gate, "median") ? overall->median
                : !strcmp(job->gate, "p90")  ? overall->p90
                                             : overall->worst;
  int over = job->max_error >= 0 && !(100 * stat <= job->max_error);
  if (job->ps->json)
    printf("{\"event\":\"done\",\"tiles\":%d,\"texels\":%zu,\"median_pct\":%.4f,\"p90_pct\":%.4f,"
           "\"worst_pct\":%.4f,\"damaged\":%zu,\"pass\":%s}\n",
           set->count, overall->texels, 100 * overall->median, 100 * overall->p90,
           isfinite(overall->worst) ? 100 * overall->worst : -1.0, damaged,
           damaged || over ? "false" : "true");
  if (damaged)
    return cli_fail("verify",
                    "FAIL: tile %d: %zu texel(s) of the set hold non-finite latents, the first at "
                    "level %d (%d, %d) of tile %d: a damaged file",
                    set->tiles[first], damaged, reps[first]->nonfinite_level,
                    reps[first]->nonfinite_x, reps[first]->nonfinite_y, set->tiles[first]);
  if (over)
    return cli_fail("verify", "FAIL: %s lobe error of the set %.2f %% exceeds --max-error %g %%",
                    job->gate, 100 * stat, job->max_error);
  if (!job->ps->json && job->max_error >= 0)
    printf("PASS: %s lobe error of the set %.2f %% <= %g %%\n", job->gate, 100 * stat,
           job->max_error);
  return CLI_EXIT_OK;
}

int verify_tiles_run(verify_tiles_job *job) {
  texture_tile_set set;
  int rc = cli_tiles_list("verify", job->pattern, &set);
  if (rc == CLI_EXIT_OK) rc = check_maps(job, &set);
  if (rc != CLI_EXIT_OK) return rc;
  nbrdf_verify_report **reps = calloc((size_t)set.count, sizeof *reps);
  char **paths = calloc((size_t)set.count, sizeof *paths);
  if (!reps || !paths) {
    free(reps), free(paths);
    return cli_fail("verify", "out of memory");
  }
  /* One texture's sample, spread over the tiles (at least a texel each): the first
   * texels % count tiles take one more. Each tile's sample and ground truth take the seed
   * plus the tile's place, so the tiles are not sampled at the same spots. */
  const int per = job->o.texels / set.count, extra = job->o.texels % set.count;
  if (!job->ps->json)
    printf("verify set %s: %d tile(s), %d texel(s) per level over the set (%d%s per tile)\n",
           job->pattern, set.count, per ? job->o.texels : set.count, per ? per : 1,
           extra && per ? " or one more" : "");
  fflush(stdout);
  cli_progress_start(job->ps);
  cli_cancel_watch();
  size_t n_texels = 0;
  double reference_seconds = 0, decode_seconds = 0;
  for (int i = 0; i < set.count && rc == CLI_EXIT_OK; i++) {
    tile_progress tp = {set.tiles[i], i + 1, set.count};
    nbrdf_verify_options o = job->o;
    o.texels = per + (i < extra) > 0 ? per + (i < extra) : 1;
    o.seed = job->o.seed + (uint64_t)i;
    o.cancel = cli_cancel_flag();
    o.progress = job->ps->json ? on_progress : cli_progress;
    o.user = job->ps->json ? (void *)&tp : (void *)job->ps;
    nbrdf_bake_inputs in;
    char *owned[NBRDF_BAKE_PARAM_COUNT];
    paths[i] = cli_tiles_path("verify", job->pattern, set.tiles[i]);
    rc = paths[i] ? tile_inputs(job, set.tiles[i], &in, owned) : CLI_EXIT_FAILURE;
    nbrdf_error err = {0};
    if (rc == CLI_EXIT_OK &&
        nbrdf_verify(job->model, paths[i], &in, &o, &reps[i], &err) != NBRDF_OK) {
      cli_params_explain(&err);
      if (job->ps->bar) fputc('\n', stderr);
      rc = cli_fail("verify", "tile %d: %s", set.tiles[i], err.message);
    }
    for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
      if (job->params->tiled[id]) free(owned[id]);
    if (rc != CLI_EXIT_OK) break;
    n_texels += reps[i]->n_texels;
    reference_seconds += reps[i]->reference_seconds;
    decode_seconds += reps[i]->decode_seconds;
    if (job->ps->json) {
      const nbrdf_verify_summary *s = &reps[i]->overall;
      printf("{\"event\":\"tile\",\"tile\":%d,\"index\":%d,\"tiles\":%d,\"texels\":%zu,"
             "\"median_pct\":%.4f,\"p90_pct\":%.4f,\"worst_pct\":%.4f,\"damaged\":%zu}\n",
             set.tiles[i], i + 1, set.count, s->texels, 100 * s->median, 100 * s->p90,
             isfinite(s->worst) ? 100 * s->worst : -1.0, reps[i]->nonfinite);
      fflush(stdout);
    }
  }
  cli_cancel_unwatch();
  if (rc == CLI_EXIT_OK) {
    /* The set's figures over every compared texel of every tile. */
    nbrdf_verify_texel *all = malloc(sizeof *all * (n_texels ? n_texels : 1));
    if (!all) {
      rc = cli_fail("verify", "out of memory");
    } else {
      size_t at = 0;
      for (int i = 0; i < set.count; i++) {
        memcpy(all + at, reps[i]->texels, sizeof *all * reps[i]->n_texels);
        at += reps[i]->n_texels;
      }
      nbrdf_verify_summary overall = verify_summarise(all, n_texels, NBRDF_VERIFY_ALL_LEVELS);
      free(all);
      if (!job->ps->json) {
        printf("  tile    texels  lobe err.  p90        worst      albedo err.  ref. noise\n");
        for (int i = 0; i < set.count; i++) {
          char label[16];
          snprintf(label, sizeof label, "%d", set.tiles[i]);
          print_row(label, &reps[i]->overall);
        }
        print_row("all", &overall);
        printf("cost: %.2f s ground truth, %.2f s decoding\n", reference_seconds, decode_seconds);
      }
      if (job->json) rc = write_json(job, &set, reps, paths, &overall);
      if (rc == CLI_EXIT_OK) rc = verdict(job, &set, reps, &overall);
    }
  }
  for (int i = 0; i < set.count; i++) {
    nbrdf_verify_report_free(reps[i]);
    free(paths[i]);
  }
  free(reps), free(paths);
  return rc;
}
