/* nbrdf_bake: the stages of a bake in order (sources -> plan/fit -> per-band
 * evaluate -> write -> audit), the accuracy level supplying what differs
 * (bake_level.h); progress over all of them. */
#include "nbrdf/bake.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_accuracy.h"
#include "bake/bake_auto.h"
#include "bake/bake_band.h"
#include "bake/bake_device.h"
#include "bake/bake_fit_file.h"
#include "bake/bake_level.h"
#include "bake/bake_range.h"
#include "core/error.h"
#include "core/progress.h"
#include "model/audit_slopes.h"
#include "model/bundle.h"
#include "model/material.h"
#include "texture/latent_exr.h"

/* Texels per band: big enough that the networks run on full batches, small
 * enough that band buffers stay far below the writer's tile rows. */
#define BAND_TEXELS 65536
/* The largest width and height of a latent texture (latent_exr_write.c). */
#define TEXTURE_SIZE_MAX NBRDF_BAKE_SIZE_MAX

static void append(char *buf, size_t cap, const char *text) {
  size_t len = strlen(buf);
  if (len + 1 < cap) snprintf(buf + len, cap - len, "%s", text);
}

/* Progress in rows, fractional inside a band: the band's own ticks cover
 * BAKE_BAND_FRACTION of it, the writer the rest (docs/BAKE.md, "Progress"). */
typedef struct bake_progress {
  core_ticker ticker;
  int y, rows, height;
  double fraction; /* of the current band, for the writer's ticks */
} bake_progress;

static int band_tick(void *user, double fraction) {
  bake_progress *p = user;
  p->fraction = fraction;
  return core_ticker_tick(&p->ticker, "bake", p->y + p->rows * fraction, p->height, 0);
}

/* The energy audit of the current band (bake_audit.h), as its own stage. */
static int audit_tick(void *user, double fraction) {
  bake_progress *p = user;
  p->fraction = fraction;
  return core_ticker_tick(&p->ticker, "audit", p->y + p->rows * fraction, p->height, 0);
}

static int writer_tick(void *user) {
  bake_progress *p = user;
  return core_ticker_tick(&p->ticker, "bake", p->y + p->rows * p->fraction, p->height, 0);
}

/* Level-0 rows handed to the writer at a time, so that cancel is seen
 * between them too (the writer encodes a row of tiles when one is full and
 * checks between groups of tiles itself). */
#define WRITE_ROWS 8

/* The sources stage's result: what the texture is made of and how it is stored. */
typedef struct bake_texture {
  int width, height, rgb;
  /* Every file the bake reads: the maps and the bundle's files (no output may replace them). */
  const char *inputs[NBRDF_BAKE_PARAM_COUNT + 8];
  int n_inputs;
  char sources[4096], settings[512];
  texture_latent_layout layout; /* of the band's texels (the bundle's latents) */
  texture_latent_compression compression;
} bake_texture;

static nbrdf_status describe(const nbrdf_model *model, texture_param_source **src,
                             const nbrdf_bake_inputs *in, const nbrdf_bake_options *o,
                             bake_texture *t, nbrdf_error *err) {
  int W, H;
  nbrdf_status st = texture_param_sources_common_size(src, NBRDF_BAKE_PARAM_COUNT, &W, &H, err);
  if (st != NBRDF_OK) return st;
  if (W == 0) { /* every input a constant */
    W = in->width ? in->width : 1;
    H = in->height ? in->height : 1;
  }
  /* The texture's limit (latent_exr_write.c), refused here so that the
   * message names the map that is too large rather than the output. */
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT && (W > TEXTURE_SIZE_MAX || H > TEXTURE_SIZE_MAX);
       id++) {
    texture_param_map *m = texture_param_source_get_map(src[id]);
    const texture_param_map_info *mi = m ? texture_param_map_get_info(m) : NULL;
    if (mi && (mi->width > TEXTURE_SIZE_MAX || mi->height > TEXTURE_SIZE_MAX))
      return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                       "%s: %s is %dx%d; a texture is at most %dx%d texels",
                       model_material_param_name(id), texture_param_map_path(m), mi->width,
                       mi->height, TEXTURE_SIZE_MAX, TEXTURE_SIZE_MAX);
  }
  t->width = W, t->height = H, t->rgb = 0;
  const char *const *model_files;
  t->n_inputs = nbrdf_model_files(model, &model_files);
  for (int i = 0; i < t->n_inputs; i++)
    t->inputs[i] = model_files[i];
  t->sources[0] = '\0';
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    t->rgb |= texture_param_source_channels(src[id]) == 3;
    texture_param_map *m = texture_param_source_get_map(src[id]);
    if (m) t->inputs[t->n_inputs++] = texture_param_map_path(m);
    if (id) append(t->sources, sizeof t->sources, "; ");
    append(t->sources, sizeof t->sources, texture_param_source_describe(src[id]));
  }
  t->layout = (texture_latent_layout){nbrdf_model_latent_dim(model),
                                      t->rgb ? NBRDF_COLOUR_RGB : NBRDF_COLOUR_MONO, 1};
  static const texture_latent_compression compression[4] = {NBRDF_LATENT_ZIP, NBRDF_LATENT_PIZ,
                                                            NBRDF_LATENT_RLE, NBRDF_LATENT_NONE};
  t->compression = compression[o->compression];
  char quant[16] = "off";
  if (o->quantise_bits) snprintf(quant, sizeof quant, "%d", o->quantise_bits);
  snprintf(t->settings, sizeof t->settings,
           "storage=%s; compression=%s; tile=%d; mipLevels=%s; roughness=%s; range=%s; "
           "proxyMips=predicted; quantise=%s",
           o->storage == NBRDF_BAKE_FLOAT ? "float" : "half",
           texture_latent_compression_name(t->compression), o->tile_size,
           o->mip_levels == 1 ? "1" : "full", model_roughness_name(o->roughness),
           o->range == NBRDF_RANGE_REFUSE ? "refuse" : "clamp", quant);
  return NBRDF_OK;
}

/* The audit stage: warnings (the level's, the energy audit) and the report; values outside
 * the trained range were reported before any work (bake_range.h). */
static void audit(const bake_texture *t, const bake_level *level, const bake_fit_result *fit,
                  const bake_evaluate *ev, const bake_band *band, const model_gpu *gpu,
                  const nbrdf_bake_options *o, nbrdf_bake_report *rep) {
  level->audit(o, fit, ev, rep);
  char audit_msg[768];
  bake_audit_message(&band->audit, t->rgb, audit_msg, sizeof audit_msg);
  if (audit_msg[0] && o->warning) o->warning(o->user, audit_msg);
  if (band->audit.audited > 1 && !model_audit_slopes(ev->stored_model) &&
      nbrdf_model_is_trained(ev->stored_model) && o->warning) {
    snprintf(audit_msg, sizeof audit_msg,
             "energy audit: bundle '%s' carries no audit slopes, so each of its %zu distinct "
             "tuples was measured (%.2f CPU-s); `nbrdf bundle audit-slopes DIR` measures them "
             "once for the bundle",
             nbrdf_model_name(ev->stored_model), band->audit.audited, band->audit.seconds);
    o->warning(o->user, audit_msg);
  }
  if (!rep) return;
  rep->width = t->width, rep->height = t->height;
  rep->colour_channels = t->rgb ? 3 : 1;
  rep->brdfs = (size_t)t->width * t->height * (t->rgb ? 3 : 1);
  snprintf(rep->device, sizeof rep->device, "%s", gpu ? gpu_context_name(gpu->ctx) : "cpu");
  rep->evaluated = band->evaluated;
  rep->reused = band->reused;
  rep->audited = band->audit.audited;
  rep->max_albedo = band->audit.audited ? band->audit.worst : NAN;
  rep->audit_measured = band->audit.measured;
  rep->audit_seconds = band->audit.seconds;
  rep->clamped = 0;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    rep->clamped += band->clamped[id];
}

/* The per-band evaluate stage streamed into the write stage, then the audit
 * stage: bands of rows through bake_band.c (the level's evaluate stage `ev`),
 * stored as the level stores them, into the latent EXR writer. */
static nbrdf_status evaluate_and_write(const bake_texture *t, const bake_level *level,
                                       const bake_fit_result *fit, const char *accuracy_attr,
                                       bake_evaluate *ev,
                                       texture_param_source **src, const nbrdf_bake_options *o,
                                       const char *out_path, bake_progress *prog,
                                       nbrdf_bake_report *rep, nbrdf_error *err) {
  const int W = t->width, H = t->height;
  /* A model with a decoder of its own (nbrdf_model_with_decoder) makes a
   * texture that carries it: version 2; else exactly version 1. */
  nbrdf_decoder_info own;
  nbrdf_model_own_decoder(ev->stored_model, &own);
  texture_latent_meta meta = {nbrdf_model_name(ev->model),
                              nbrdf_model_checksum(ev->model),
                              t->sources,
                              t->settings,
                              own.bytes,
                              own.size,
                              accuracy_attr[0] ? accuracy_attr : NULL,
                              o->inputs};
  texture_latent_exr_options wo = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  wo.storage = o->storage == NBRDF_BAKE_FLOAT ? NBRDF_LATENT_FLOAT : NBRDF_LATENT_HALF;
  wo.tile_size = o->tile_size;
  wo.compression = t->compression;
  wo.mip_levels = o->mip_levels;
  wo.mip_row = ev->mip_row;
  wo.mip_row_user = ev;
  wo.tick = writer_tick;
  wo.tick_user = prog;
  wo.max_albedo_attr = o->energy_audit > 0;

  int band_rows = BAND_TEXELS / W;
  if (band_rows < 1) band_rows = 1;
  if (band_rows > H) band_rows = H;
  size_t texel_floats = (size_t)texture_latent_channel_count(&ev->stored);
  size_t work_floats = (size_t)texture_latent_channel_count(&ev->work);
  float *texels = malloc(sizeof(float) * work_floats * (size_t)band_rows * W);
  /* The band's texels (work layout) are stored into `out` (the same buffer
   * where the level stores them as they are). */
  float *out =
      ev->stores_work ? texels : malloc(sizeof(float) * texel_floats * (size_t)band_rows * W);
  if (!texels || !out) {
    if (out != texels) free(out);
    free(texels);
    return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for a band");
  }

  texture_latent_writer *writer = NULL;
  nbrdf_status st = texture_latent_writer_create(&writer, out_path, W, H, &ev->stored, &meta, &wo,
                                                 t->inputs, t->n_inputs, err);
  bake_band band;
  /* One band: nothing to carry over, so no cache memory. */
  size_t cache_max = band_rows < H ? o->tuple_cache : 0;
  bake_band_init(&band, ev->model, src, &ev->work, W, o->roughness, o->range, cache_max,
                 o->quantise_bits);
  float take_hi[NBRDF_BAKE_PARAM_COUNT];
  bake_taken_ranges(ev->model, o->accuracy, band.take, take_hi);
  band.tick = band_tick;
  band.audit_tick = audit_tick;
  band.tick_user = prog;
  bake_audit_init(&band.audit, o->energy_audit);
  band.audit_model = ev->stored_model;
  band.audit.compact = ev->compact;
  band.correct = ev->correct;
  model_gpu *gpu = NULL;
  if (st == NBRDF_OK) st = bake_device_open(ev->model, ev->stored_model, o, &gpu, err);
  band.gpu = gpu;
  band.audit.gpu_decoder = gpu ? gpu->decoder : NULL;
  for (int y = 0; st == NBRDF_OK && y < H; y += band_rows) {
    int rows = H - y < band_rows ? H - y : band_rows;
    prog->y = y, prog->rows = rows, prog->fraction = 0.0;
    if (core_ticker_tick(&prog->ticker, "bake", y, H, y == 0)) {
      st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled at row %d of %d", y, H);
      break;
    }
    st = bake_band_run(&band, y, rows, texels, err);
    if (st == NBRDF_OK) ev->store(ev, texels, out, (size_t)rows * W);
    for (int j = 0; st == NBRDF_OK && j < rows; j += WRITE_ROWS) {
      int n = rows - j < WRITE_ROWS ? rows - j : WRITE_ROWS;
      prog->fraction = BAKE_BAND_FRACTION + (1.0 - BAKE_BAND_FRACTION) * j / rows;
      if (j && writer_tick(prog)) {
        st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled at row %d of %d", y + j, H);
        break;
      }
      st = texture_latent_writer_write_rows(writer, out + (size_t)j * W * texel_floats, n, err);
    }
  }
  if (st == NBRDF_OK && core_ticker_tick(&prog->ticker, "bake", H, H, 1))
    st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled before the file was complete");
  if (st == NBRDF_OK) {
    if (band.audit.audited) texture_latent_writer_set_max_albedo(writer, (float)band.audit.worst);
    st = texture_latent_writer_finish(writer, err);
    writer = NULL;
  }
  texture_latent_writer_abort(writer);
  if (st == NBRDF_OK) audit(t, level, fit, ev, &band, gpu, o, rep);
  bake_band_free(&band);
  model_gpu_close(gpu);
  if (out != texels) free(out);
  free(texels);
  return st;
}

/* The header's nbrdf:accuracy: the fit's, led by the texture's level; after a fallback or
 * an auto choice also what was asked for and what came of it. */
static void accuracy_attribute(const bake_fit_result *fit, nbrdf_bake_accuracy requested,
                               nbrdf_bake_accuracy texture, int fell_back,
                               const bake_auto_outcome *au, char *buf, size_t cap) {
  const char *rest = fit->attribute;
  if (!strncmp(rest, "level=", 6)) {
    const char *semi = strstr(rest, "; ");
    rest = semi ? semi + 2 : "";
  }
  buf[0] = '\0';
  if (!fell_back && requested != NBRDF_BAKE_AUTO) {
    snprintf(buf, cap, "%s", fit->attribute);
    return;
  }
  snprintf(buf, cap, "level=%s; requested=%s", nbrdf_bake_accuracy_name(texture),
           nbrdf_bake_accuracy_name(requested));
  if (au) {
    char d[384];
    bake_auto_describe(au, d, sizeof d);
    append(buf, cap, "; ");
    append(buf, cap, d);
  }
  if (fell_back) append(buf, cap, "; fellBack=1");
  if (fell_back && bake_fit_creates_energy(fit)) append(buf, cap, "; fellBackFor=energy");
  if (rest[0]) {
    append(buf, cap, "; ");
    append(buf, cap, rest);
  } else {
    char d[128];
    snprintf(d, sizeof d, "; heldout=%zu; fastError=%.4f", fit->heldout,
             fit->heldout_error_fast);
    append(buf, cap, d);
  }
}

/* What the report says beyond the texture's level: the request, a fallback, auto's tries. */
static void report_choice(const bake_fit_result *fit, nbrdf_bake_accuracy requested,
                          int fell_back, const bake_auto_outcome *au, nbrdf_bake_report *rep) {
  rep->requested = requested;
  rep->fell_back = fell_back;
  if (fell_back || (au && fit->heldout)) {
    rep->accuracy = fell_back ? NBRDF_BAKE_FAST : rep->accuracy;
    bake_fit_result_report(fit, rep);
  }
  if (!au) return;
  rep->max_error = 100.0 * au->max_error;
  rep->met = au->met;
  rep->tried = au->tried;
  for (int i = 0; i < au->tried; i++)
    rep->tried_level[i] = au->level[i], rep->tried_error[i] = au->error[i];
  rep->suggested_budget = au->suggested_budget;
}

/* sources (opened by the caller; described here) -> plan/fit -> per-band
 * evaluate -> write -> audit, each accuracy level supplying its stages
 * (bake_level.h). */
static nbrdf_status run(const nbrdf_model *model, texture_param_source **src,
                        const nbrdf_bake_inputs *in, const nbrdf_bake_options *o,
                        const char *out_path, nbrdf_bake_report *rep, nbrdf_error *err) {
  bake_texture t;
  nbrdf_status st = describe(model, src, in, o, &t, err);
  if (st != NBRDF_OK) return st;
  bake_progress prog = {.height = t.height};
  core_ticker_init(&prog.ticker, o->progress, o->user, o->cancel);
  /* Plan and fit before any file exists. */
  bake_scene scene = {src, t.width, t.height, t.rgb ? 3 : 1};
  /* A fit made before (nbrdf/fit.h) replaces the plan/fit stage. */
  bake_fit_result own;
  memset(&own, 0, sizeof own);
  const bake_fit_result *fit = o->fit ? &o->fit->r : &own;
  bake_auto_outcome au;
  const int is_auto = o->accuracy == NBRDF_BAKE_AUTO && !o->fit;
  nbrdf_bake_accuracy chosen = o->accuracy;
  if (is_auto) {
    st = bake_auto_choose(model, &scene, 1, o, &prog.ticker, &own, &au, err);
    chosen = au.chosen;
    if (st == NBRDF_OK && !au.met && o->warning) {
      char msg[640];
      bake_auto_message(&au, msg, sizeof msg);
      o->warning(o->user, msg);
    }
  } else if (!o->fit) {
    st = bake_level_of(o->accuracy)->fit(model, &scene, 1, o, &prog.ticker, &own, err);
  }
  /* A level worse than fast where the held-out check looked (grazing θi, off-plane
   * azimuths) is not baked: fast is (auto never chooses one). */
  const int fell_back = st == NBRDF_OK && chosen != NBRDF_BAKE_FAST && !o->no_fallback &&
                        bake_fit_worse_than_fast(fit);
  nbrdf_bake_options lo = *o;
  lo.accuracy = fell_back ? NBRDF_BAKE_FAST : chosen;
  /* Fast after a fitting level was asked for (a fallback, auto's choice): the range check
   * let alpha below the trained range through as the fitting levels take it, and the range
   * report said fast bakes it as the trained minimum; anything the policy refuses was
   * refused then, so clamping here moves only those. */
  if (lo.accuracy == NBRDF_BAKE_FAST && bake_level_fits_alpha(o->accuracy))
    lo.range = NBRDF_RANGE_CLAMP;
  if (fell_back && o->warning) {
    char why[640], msg[896];
    bake_fit_worse_message(fit, chosen, why, sizeof why);
    /* The lobe error may improve with more budget; energy created by the fine-tune is a
     * property of the level at that roughness (docs/BAKE.md, "Sharp coats"). */
    const int lobe = fit->heldout_error > fit->heldout_error_fast;
    snprintf(msg, sizeof msg, "%s: baked at fast instead; %s%g s)%s", why,
             lobe ? "give it a larger --budget (this one: " : "(budget ", fit->budget,
             bake_fit_creates_energy(fit) ? "; --no-fallback keeps the level's texture anyway"
                                          : "");
    o->warning(o->user, msg);
  }
  char attr[1024];
  accuracy_attribute(fit, o->accuracy == NBRDF_BAKE_AUTO ? NBRDF_BAKE_AUTO : chosen,
                     lo.accuracy, fell_back, is_auto ? &au : NULL, attr, sizeof attr);
  const bake_level *level = bake_level_of(lo.accuracy);
  bake_evaluate ev = {0};
  if (st == NBRDF_OK) st = level->evaluate_open(model, fit, &t.layout, t.width, &ev, err);
  if (st == NBRDF_OK)
    st = evaluate_and_write(&t, level, fit, attr, &ev, src, &lo, out_path, &prog, rep, err);
  if (st == NBRDF_OK && rep)
    report_choice(fit, o->accuracy == NBRDF_BAKE_AUTO ? NBRDF_BAKE_AUTO : chosen, fell_back,
                  is_auto ? &au : NULL, rep);
  bake_evaluate_close(&ev);
  bake_fit_result_free(&own);
  return st;
}

nbrdf_status nbrdf_bake_options_check(const nbrdf_model *model, const nbrdf_bake_options *options,
                                      nbrdf_error *err) {
  if (!model) return core_fail(err, NBRDF_ERR_ARGUMENT, "bake: the model is required");
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  if (options) o = *options;
  if (o.mip_levels != 0 && o.mip_levels != 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "bake: mip_levels is 0 (full chain) or 1 (level 0 only), not %d",
                     o.mip_levels);
  if ((unsigned)o.compression > NBRDF_BAKE_UNCOMPRESSED)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "bake: unknown compression %d", (int)o.compression);
  if (o.quantise_bits != 0 && (o.quantise_bits < 2 || o.quantise_bits > 16))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "bake: quantise_bits is 0 (off) or 2..16, not %d",
                     o.quantise_bits);
  if ((unsigned)o.accuracy > NBRDF_BAKE_AUTO)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "bake: accuracy is fast, fitted, specialised, compact or auto (0 to 4), not %d",
                     (int)o.accuracy);
  if (o.accuracy == NBRDF_BAKE_AUTO) {
    if (!(o.max_error > 0.0 && o.max_error <= 1000.0))
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "bake: auto needs max_error, the held-out lobe error to meet in percent "
                       "(0, 1000], not %g",
                       o.max_error);
    if (o.fit)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "bake: auto chooses a level; a fit made before has its own");
    /* Auto climbs from fitted: its budget must at least afford that. */
    o.accuracy = NBRDF_BAKE_FITTED;
  }
  if ((unsigned)o.device > NBRDF_DEVICE_GPU)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "bake: device is cpu, auto or gpu (0 to 2), not %d",
                     (int)o.device);
  if (!isfinite(o.budget) || o.budget < 0.0)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "bake: budget is a number of seconds > 0 (0: the level's default), not %g",
                     o.budget);
  if (o.accuracy != NBRDF_BAKE_FAST) return bake_accuracy_check(model, &o, err);
  return NBRDF_OK;
}

nbrdf_status nbrdf_bake(const nbrdf_model *model, const nbrdf_bake_inputs *inputs,
                        const nbrdf_bake_options *options, const char *out_path,
                        nbrdf_bake_report *report, nbrdf_error *err) {
  if (!model || !inputs || !out_path || !*out_path)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "bake: model, inputs and output path are required");
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  if (options) o = *options;
  /* Options first: a budget too small is refused before the maps are read. */
  nbrdf_status st = nbrdf_bake_options_check(model, &o, err);
  if (st != NBRDF_OK) return st;
  if (st == NBRDF_OK && o.fit) st = nbrdf_fit_check(o.fit, model, inputs, &o, err);
  if (st != NBRDF_OK) return st;
  if (o.fit) o.accuracy = o.fit->accuracy;
  if (report) memset(report, 0, sizeof *report);
  texture_param_source *src[NBRDF_BAKE_PARAM_COUNT] = {0};
  st = bake_open_sources(inputs, src, err);
  if (st == NBRDF_OK) st = bake_range_check(model, src, &o, err);
  if (st == NBRDF_OK) st = run(model, src, inputs, &o, out_path, report, err);
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    texture_param_source_free(src[id]);
  return st;
}
