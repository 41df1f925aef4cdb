#include "cli/bake_tiles.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli/cli.h"
#include "cli/cli_cancel.h"
#include "cli/cli_device.h"
#include "cli/cli_outputs.h"
#include "nbrdf/fit.h"
#include "nn/safetensors.h"
#include "texture/latent_exr.h"
#include "texture/tile_set.h"

static const char *const flag_names[NBRDF_BAKE_PARAM_COUNT] = {"--alpha1", "--eta",    "--alpha2",
                                                               "--r0",     "--albedo", "--sigma-t"};

int bake_tiles_wanted(const cli_params *params, const char *out, const char *tiles, int force) {
  if (cli_params_any_tiled(params) || tiles || force) return 1;
  texture_tile_pattern *p = NULL;
  nbrdf_error err = {0};
  if (!out || texture_tile_pattern_parse(out, &p, &err) != NBRDF_OK) return 0;
  int tiled = texture_tile_pattern_is_tiled(p);
  texture_tile_pattern_free(p);
  return tiled;
}

/* One tile's files: the maps' paths (patterns substituted) and the output. */
typedef struct tile_files {
  char *map[NBRDF_BAKE_PARAM_COUNT]; /* NULL where the parameter is not tiled */
  char *out;
} tile_files;

/* What the progress, warning and note callbacks of one tile's bake know. */
typedef struct tile_progress {
  cli_progress_state *ps;
  int tile, index, count; /* index: 1-based place in the set */
  int *noted;             /* the device note is said once for the set */
  int drawn;              /* the bar's line is open on stderr */
} tile_progress;

/* Ends the bar's line before another line is written. */
static void end_bar(tile_progress *tp) {
  if (tp->drawn) fputc('\n', stderr);
  tp->drawn = 0;
}

/* The set's progress: the bake's own line with the tile added, or one bar for the whole set
 * (each tile an equal share; a tile's stages above fast each fill its share once). */
static int on_progress(void *user, const char *stage, double done, double total) {
  tile_progress *tp = user;
  if (tp->ps->json) {
    char fields[96];
    snprintf(fields, sizeof fields, ",\"tile\":%d,\"tile_index\":%d,\"tiles\":%d", tp->tile,
             tp->index, tp->count);
    cli_progress_json_fields(stage, done, total, fields);
  } else if (tp->ps->bar) {
    double f = (tp->index - 1 + (total > 0 ? done / total : 1.0)) / tp->count;
    int width = 40, filled = (int)(width * f);
    fprintf(stderr, "\rtile %d %d/%d %-12s [", tp->tile, tp->index, tp->count, stage);
    for (int i = 0; i < width; i++)
      fputc(i < filled ? '#' : ' ', stderr);
    fprintf(stderr, "] %3.0f%%", 100.0 * f);
    fflush(stderr);
    tp->drawn = 1;
  }
  return *cli_cancel_flag();
}

static void on_warning(void *user, const char *message) {
  tile_progress *tp = user;
  if (tp->ps->json) {
    printf("{\"event\":\"warning\",\"tile\":%d,\"message\":", tp->tile);
    cli_json_string(stdout, message);
    printf("}\n");
  }
  end_bar(tp);
  fprintf(stderr, "nbrdf bake: warning: tile %d: %s\n", tp->tile, message);
}

static void on_note(void *user, const char *message) {
  tile_progress *tp = user;
  if (*tp->noted) return;
  *tp->noted = 1;
  cli_device_note("bake", message);
}

/* ---- The fingerprint: what a tile's texture is made from, as nbrdf:inputs ---- */

static void fp_text(uint64_t *h, const char *fmt, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  int n = vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (n < 0) return;
  *h = nn_st_fnv1a64(*h, buf, (size_t)n < sizeof buf ? (size_t)n : sizeof buf - 1);
  *h = nn_st_fnv1a64(*h, "\n", 1); /* so that "a"+"bc" is not "ab"+"c" */
}

/* A file by its path, size and modification time (nanoseconds): a changed map is a new
 * fingerprint without reading it whole. */
static void fp_file(uint64_t *h, const char *what, const char *path) {
  struct stat sb;
  if (!path) {
    fp_text(h, "%s=none", what);
  } else if (stat(path, &sb) != 0) {
    fp_text(h, "%s=%s missing", what, path);
  } else {
    fp_text(h, "%s=%s %lld %lld.%09ld", what, path, (long long)sb.st_size,
            (long long)sb.st_mtim.tv_sec, (long)sb.st_mtim.tv_nsec);
  }
}

/* "fnv1a64:" and 16 hex digits over the tile's inputs and every option that changes its
 * texels or its file (progress, messages and the cancel flag do not). */
static void fingerprint(const bake_tiles_job *job, const nbrdf_bake_inputs *in, char out[32]) {
  uint64_t h = NBRDF_ST_FNV1A64_INIT;
  const nbrdf_bake_options *o = &job->opts;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    const nbrdf_bake_param *p = &in->param[id];
    if (p->path)
      fp_file(&h, flag_names[id], p->path);
    else
      fp_text(&h, "%s=%a,%a,%a/%d", flag_names[id], (double)p->value[0], (double)p->value[1],
              (double)p->value[2], p->channels);
    fp_text(&h, "cs=%s remap=%d %a %a", p->colour_space ? p->colour_space : "", p->remap,
            (double)p->lo, (double)p->hi);
  }
  fp_file(&h, "ocio", in->ocio_config);
  fp_text(&h, "resample=%d size=%dx%d", (int)in->resample, in->width, in->height);
  fp_text(&h, "model=%s %s", nbrdf_model_name(job->model), nbrdf_model_checksum(job->model));
  fp_file(&h, "decoder", job->decoder);
  fp_text(&h, "storage=%d mips=%d tile=%d roughness=%d range=%d quantise=%d compression=%d",
          (int)o->storage, o->mip_levels, o->tile_size, (int)o->roughness, (int)o->range,
          o->quantise_bits, (int)o->compression);
  fp_text(&h, "audit=%zu accuracy=%d budget=%a seed=%" PRIu64 " compact=%d,%d device=%d",
          o->energy_audit, (int)o->accuracy, o->budget, o->seed, o->compact_dim, o->compact_width,
          (int)o->device);
  if (o->fit) {
    /* A tile baked with another fit is stale: the fit file's checksum names it. */
    nbrdf_fit_info fi;
    nbrdf_fit_describe(o->fit, &fi);
    fp_text(&h, "fit=%s", fi.file_checksum);
  }
  snprintf(out, 32, "fnv1a64:%016" PRIx64, h);
}

/* 1 when `path` is a latent texture whose header holds `fp`. */
static int up_to_date(const char *path, const char *fp) {
  struct stat sb;
  if (stat(path, &sb) != 0) return 0;
  texture_latent_reader *r = NULL;
  nbrdf_error err = {0};
  if (texture_latent_reader_open(&r, path, &err) != NBRDF_OK) return 0;
  int same = !strcmp(texture_latent_reader_info(r)->inputs, fp);
  texture_latent_reader_close(r);
  return same;
}

/* The options tile `tile` is baked with: the seam for one fit per set. Above the fast level
 * nbrdf_bake fits each tile on its own today; a fit computed once over the whole set
 * (`nbrdf fit`) is to be handed to every tile's bake here, the same for all of them. */
static nbrdf_bake_options tile_bake_options(const bake_tiles_job *job, tile_progress *tp,
                                            const char *fp, nbrdf_device device) {
  nbrdf_bake_options o = job->opts;
  o.device = device;
  o.progress = on_progress;
  o.warning = on_warning;
  o.note = on_note;
  o.user = tp;
  o.cancel = cli_cancel_flag();
  o.inputs = fp;
  return o;
}

static void report_tile(const bake_tiles_job *job, tile_progress *tp, const char *out,
                        const nbrdf_bake_report *rep) {
  end_bar(tp);
  if (job->ps->json) {
    printf("{\"event\":\"tile\",\"tile\":%d,\"index\":%d,\"tiles\":%d,\"status\":\"%s\","
           "\"output\":",
           tp->tile, tp->index, tp->count, rep ? "baked" : "skipped");
    cli_json_string(stdout, out);
    if (rep) {
      printf(",\"width\":%d,\"height\":%d,\"channels\":%d,\"evaluated\":%zu", rep->width,
             rep->height, rep->colour_channels, rep->evaluated);
      if (rep->accuracy != NBRDF_BAKE_FAST)
        printf(",\"accuracy\":\"%s\",\"heldout_error\":%.5f,\"heldout_error_fast\":%.5f",
               nbrdf_bake_accuracy_name(rep->accuracy), rep->heldout_error,
               rep->heldout_error_fast);
    }
    printf("}\n");
  } else if (!rep) {
    printf("tile %d (%d/%d): skipped, %s is up to date (--force bakes it again)\n", tp->tile,
           tp->index, tp->count, out);
  } else {
    printf("tile %d (%d/%d): wrote %s: %d x %d %s, %zu BRDFs (%zu evaluated)", tp->tile, tp->index,
           tp->count, out, rep->width, rep->height, rep->colour_channels == 3 ? "rgb" : "mono",
           rep->brdfs, rep->evaluated);
    if (rep->accuracy != NBRDF_BAKE_FAST)
      printf("; %s: held-out lobe error median %.2f %% (fast: %.2f %%)",
             nbrdf_bake_accuracy_name(rep->accuracy), 100.0 * rep->heldout_error,
             100.0 * rep->heldout_error_fast);
    putchar('\n');
  }
  fflush(stdout);
}

/* The set's tiles after --tiles; an exit status other than CLI_EXIT_OK on failure. */
static int resolve_set(const bake_tiles_job *job, texture_tile_set *set) {
  texture_tile_map maps[NBRDF_BAKE_PARAM_COUNT];
  int n = 0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    if (job->params->tiled[id])
      maps[n++] = (texture_tile_map){flag_names[id], job->params->in.param[id].path};
  nbrdf_error err = {0};
  nbrdf_status st = texture_tile_set_resolve(maps, n, set, &err);
  if (st == NBRDF_ERR_ARGUMENT) return cli_usage_error("bake", "%s", err.message);
  if (st != NBRDF_OK) return cli_fail_error("bake", &err);
  if (texture_tile_set_check_output(set, "-o", job->out, &err) != NBRDF_OK)
    return cli_usage_error("bake", "%s", err.message);
  if (set->count == 0)
    return cli_usage_error("bake",
                           "%s applies to a tile set, and no map is a tile pattern "
                           "(such as 'rough.<UDIM>.exr')",
                           job->tiles ? "--tiles" : "--force");
  if (job->tiles && texture_tile_set_select(set, job->tiles, &err) != NBRDF_OK)
    return cli_usage_error("bake", "--tiles: %s", err.message);
  return CLI_EXIT_OK;
}

/* Every tile's files, each output checked against that tile's inputs before any is
 * written. */
static int tile_paths(const bake_tiles_job *job, const texture_tile_set *set, tile_files *files) {
  texture_tile_pattern *pat[NBRDF_BAKE_PARAM_COUNT + 1] = {0};
  nbrdf_error err = {0};
  int rc = CLI_EXIT_OK;
  for (int id = 0; id <= NBRDF_BAKE_PARAM_COUNT && rc == CLI_EXIT_OK; id++) {
    const char *text = id == NBRDF_BAKE_PARAM_COUNT ? job->out
                       : job->params->tiled[id]     ? job->params->in.param[id].path
                                                    : NULL;
    if (text && texture_tile_pattern_parse(text, &pat[id], &err) != NBRDF_OK)
      rc = cli_fail_error("bake", &err);
  }
  for (int i = 0; i < set->count && rc == CLI_EXIT_OK; i++) {
    cli_inputs inputs;
    cli_inputs_init(&inputs);
    cli_inputs_add_model(&inputs, job->model);
    cli_inputs_add(&inputs, job->decoder);
    cli_inputs_add(&inputs, job->params->in.ocio_config);
    for (int id = 0; id <= NBRDF_BAKE_PARAM_COUNT && rc == CLI_EXIT_OK; id++) {
      char **dst = id == NBRDF_BAKE_PARAM_COUNT ? &files[i].out : &files[i].map[id];
      if (pat[id] && texture_tile_pattern_path(pat[id], set->tiles[i], dst, &err) != NBRDF_OK)
        rc = cli_fail_error("bake", &err);
      else if (id < NBRDF_BAKE_PARAM_COUNT)
        cli_inputs_add(&inputs, pat[id] ? *dst : job->params->in.param[id].path);
    }
    if (rc == CLI_EXIT_OK) rc = cli_output_check("bake", &inputs, files[i].out);
    cli_inputs_free(&inputs);
  }
  for (int id = 0; id <= NBRDF_BAKE_PARAM_COUNT; id++)
    texture_tile_pattern_free(pat[id]);
  return rc;
}

static void free_files(tile_files *files, int n) {
  for (int i = 0; i < n; i++) {
    for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
      free(files[i].map[id]);
    free(files[i].out);
  }
  free(files);
}

/* A failed or cancelled tile: its error (a JSON event too) and the exit status. */
static int tile_failed(const bake_tiles_job *job, tile_progress *tp, nbrdf_status st,
                       nbrdf_error *err, int finished) {
  cli_params_explain(err);
  end_bar(tp);
  if (job->ps->json) {
    printf("{\"event\":\"error\",\"tile\":%d,\"status\":\"%s\",\"message\":", tp->tile,
           nbrdf_status_name(st));
    cli_json_string(stdout, err->message);
    printf("}\n");
  }
  if (st == NBRDF_ERR_CANCELLED)
    return cli_fail("bake",
                    "%s: cancelled in tile %d (%d/%d); no file written for it, %d tile%s "
                    "finished before it stay%s whole (a re-run skips %s)",
                    cli_cancel_reason(), tp->tile, tp->index, tp->count, finished,
                    finished == 1 ? "" : "s", finished == 1 ? "s" : "",
                    finished == 1 ? "it" : "them");
  return cli_fail("bake", "tile %d: %s", tp->tile, err->message);
}

int bake_tiles_run(bake_tiles_job *job) {
  texture_tile_set set;
  int rc = resolve_set(job, &set);
  if (rc != CLI_EXIT_OK) return rc;
  tile_files *files = calloc((size_t)set.count, sizeof *files);
  if (!files) return cli_fail("bake", "out of memory");
  rc = tile_paths(job, &set, files);
  if (rc != CLI_EXIT_OK) {
    free_files(files, set.count);
    return rc;
  }
  if (job->opts.accuracy != NBRDF_BAKE_FAST && !job->opts.fit)
    fprintf(stderr,
            "nbrdf bake: note: --accuracy %s fits each of the %d tiles on its own (its own "
            "corrections%s; 'nbrdf fit' then --fit: one fit for the set)\n",
            nbrdf_bake_accuracy_name(job->opts.accuracy), set.count,
            job->opts.accuracy == NBRDF_BAKE_FITTED ? "" : " and decoder");

  cli_progress_start(job->ps);
  cli_cancel_watch();
  int baked = 0, skipped = 0, noted = 0;
  /* auto looks for a GPU at every bake (~0.7 s through Vulkan): once it has found none, the
   * other tiles go straight to the CPU, where auto would put them too. */
  nbrdf_device device = job->opts.device;
  for (int i = 0; i < set.count && rc == CLI_EXIT_OK; i++) {
    tile_progress tp = {job->ps, set.tiles[i], i + 1, set.count, &noted, 0};
    nbrdf_bake_inputs in = job->params->in;
    for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
      if (files[i].map[id]) in.param[id].path = files[i].map[id];
    if (*cli_cancel_flag()) { /* between two tiles */
      nbrdf_error err = {NBRDF_ERR_CANCELLED, "cancelled"};
      rc = tile_failed(job, &tp, NBRDF_ERR_CANCELLED, &err, baked + skipped);
      break;
    }
    char fp[32];
    fingerprint(job, &in, fp);
    if (!job->force && up_to_date(files[i].out, fp)) {
      skipped++;
      report_tile(job, &tp, files[i].out, NULL);
      continue;
    }
    nbrdf_bake_options o = tile_bake_options(job, &tp, fp, device);
    nbrdf_bake_report rep;
    nbrdf_error err = {0};
    nbrdf_status st = nbrdf_bake(job->model, &in, &o, files[i].out, &rep, &err);
    if (st != NBRDF_OK) {
      rc = tile_failed(job, &tp, st, &err, baked + skipped);
      break;
    }
    baked++;
    if (device == NBRDF_DEVICE_AUTO && !strcmp(rep.device, "cpu")) device = NBRDF_DEVICE_CPU;
    report_tile(job, &tp, files[i].out, &rep);
  }
  cli_cancel_unwatch();
  if (rc == CLI_EXIT_OK) {
    double seconds = cli_progress_seconds(job->ps);
    if (job->ps->json) {
      printf("{\"event\":\"done\",\"output\":");
      cli_json_string(stdout, job->out);
      printf(",\"tiles\":%d,\"baked\":%d,\"skipped\":%d,\"seconds\":%.2f}\n", set.count, baked,
             skipped, seconds);
    } else {
      printf("tile set %s: %d tile%s, %d baked, %d skipped (up to date), %.1f s\n", job->out,
             set.count, set.count == 1 ? "" : "s", baked, skipped, seconds);
    }
  }
  free_files(files, set.count);
  return rc;
}
