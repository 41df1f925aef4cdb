/* nbrdf_bake: opens the six parameter sources, streams bands of rows through
 * bake_band.c into the latent EXR writer, and reports progress. */
#include "nbrdf/bake.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bake/bake_accuracy.h"
#include "bake/bake_band.h"
#include "bake/bake_device.h"
#include "core/error.h"
#include "core/number.h"
#include "core/progress.h"
#include "model/bundle.h"
#include "model/param_conventions.h"
#include "texture/latent_exr.h"

/* Texels per band: big enough that the networks run on full batches, small
 * enough that band buffers stay far below the writer's tile rows. */
#define BAND_TEXELS 65536
/* The largest width and height of a latent texture (latent_exr_write.c). */
#define TEXTURE_SIZE_MAX NBRDF_BAKE_SIZE_MAX

static const char *const param_names[NBRDF_BAKE_PARAM_COUNT] = {"alpha1", "eta",    "alpha2",
                                                                "r0",     "albedo", "sigma_t"};

static const char *const accuracy_names[4] = {"fast", "fitted", "specialised", "compact"};

const char *nbrdf_bake_accuracy_name(nbrdf_bake_accuracy a) {
  return (unsigned)a < 4 ? accuracy_names[a] : "unknown";
}

int nbrdf_bake_accuracy_parse(const char *name) {
  for (int k = 0; name && k < 4; k++)
    if (!strcmp(name, accuracy_names[k])) return k;
  return -1;
}

const char *nbrdf_bake_param_name(nbrdf_bake_param_id id) {
  return (unsigned)id < NBRDF_BAKE_PARAM_COUNT ? param_names[id] : "parameter";
}

void nbrdf_bake_param_constant(nbrdf_bake_param *p, float value) {
  p->path = NULL;
  p->value[0] = p->value[1] = p->value[2] = value;
  p->channels = 1;
}

nbrdf_status nbrdf_bake_param_parse(const char *name, const char *arg, nbrdf_bake_param *p,
                                    nbrdf_error *err) {
  if (!arg || !*arg) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: empty value", name);
  /* "v" or "v,v,v", each number as core/number.h reads it (white space
   * around it allowed, hex/inf/nan not). */
  float v[3];
  int n = 0, numbers = 1;
  for (const char *s = arg;; n++) {
    const char *comma = strchr(s, ',');
    size_t len = comma ? (size_t)(comma - s) : strlen(s);
    core_number_result r = n < 3 ? core_parse_float(s, len, &v[n]) : NBRDF_NUMBER_SYNTAX;
    if (r == NBRDF_NUMBER_OVERFLOW || r == NBRDF_NUMBER_UNDERFLOW)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "%s: '%.*s' %s as a float; write ./%s for a file of that name", name,
                       (int)len, s, core_number_problem(r), arg);
    if (r != NBRDF_NUMBER_OK) numbers = 0;
    if (!comma) break;
    s = comma + 1;
  }
  n++;
  if (numbers && (n == 1 || n == 3)) {
    p->path = NULL;
    p->channels = n;
    for (int c = 0; c < 3; c++)
      p->value[c] = v[n == 3 ? c : 0];
    return NBRDF_OK;
  }
  /* Not one or three numbers: a file, which must exist (so that a mistyped
   * value, "0x10" or "0.5,0.5", is not reported as a missing image). */
  struct stat sb;
  if (stat(arg, &sb) != 0 && errno == ENOENT)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: '%s' is neither a number (nor three, comma-separated) nor an "
                     "existing file",
                     name, arg);
  p->path = arg;
  return NBRDF_OK;
}

typedef struct mip_ctx {
  const nbrdf_model *model;
  const texture_latent_layout *layout;
  /* COMPACT: the basis, the bundle-latent layout and a row of it */
  const bake_compact *compact;
  const texture_latent_layout *work;
  float *work_row;
} mip_ctx;

/* The proxy of a mip texel is predicted from its averaged latents rather
 * than averaged itself (docs/LATENT-TEXTURE.md, "Mip levels"); a compact
 * texel's from the latent its averaged coordinates stand for. */
static nbrdf_status mip_row(void *user, int level, int y, float *row, int width, nbrdf_error *err) {
  (void)level, (void)y;
  const mip_ctx *m = user;
  if (!m->compact) return bake_proxy_from_latents(m->model, m->layout, row, (size_t)width, err);
  const int C = texture_latent_colours(m->layout);
  const int fin = texture_latent_channel_count(m->layout),
            fw = texture_latent_channel_count(m->work);
  float coords[BAKE_COMPACT_MAX_DIM], z[NBRDF_LATENT_MAX_DIM];
  for (int x = 0; x < width; x++)
    for (int c = 0; c < C; c++) {
      for (int j = 0; j < m->compact->dim; j++)
        coords[j] = row[x * fin + texture_latent_index_latent(m->layout, c, j)];
      bake_compact_expand(m->compact, coords, z);
      for (int d = 0; d < m->work->latent_dim; d++)
        m->work_row[x * fw + texture_latent_index_latent(m->work, c, d)] = z[d];
    }
  nbrdf_status st = bake_proxy_from_latents(m->model, m->work, m->work_row, (size_t)width, err);
  for (int x = 0; st == NBRDF_OK && x < width; x++)
    for (int c = 0; c < C; c++) {
      row[x * fin + texture_latent_index_sigma(m->layout, c)] =
          m->work_row[x * fw + texture_latent_index_sigma(m->work, c)];
      row[x * fin + texture_latent_index_w(m->layout, c)] =
          m->work_row[x * fw + texture_latent_index_w(m->work, c)];
    }
  return st;
}

static void append(char *buf, size_t cap, const char *text) {
  size_t len = strlen(buf);
  if (len + 1 < cap) snprintf(buf + len, cap - len, "%s", text);
}

static void warn_clamped(const bake_band *b, const nbrdf_bake_options *o) {
  if (!o->warning) return;
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    if (!b->clamped[id]) continue;
    char msg[512], what[64];
    snprintf(what, sizeof what, "%zu texel channel(s)", b->clamped[id]);
    bake_clamp_warning(msg, sizeof msg, param_names[id], b->lo, b->hi, id, what, 1);
    /* η = 1 (no coat) is the usual value below the range: say how to get it. */
    size_t len = strlen(msg);
    if (id == NBRDF_BAKE_ETA && b->lo[id] > 1.0f && len < sizeof msg)
      snprintf(msg + len, sizeof msg - len,
               " (a bundle whose base tables start at eta = 1, `nbrdf train tables --eta-min 1`, "
               "takes eta = 1, no coat, unclamped)");
    o->warning(o->user, msg);
  }
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

static nbrdf_status run(const nbrdf_model *model, texture_param_source **src,
                        const nbrdf_bake_inputs *in, const nbrdf_bake_options *o,
                        const char *out_path, nbrdf_bake_report *rep, nbrdf_error *err) {
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
                       "%s: %s is %dx%d; a texture is at most %dx%d texels", param_names[id],
                       texture_param_map_path(m), mi->width, mi->height, TEXTURE_SIZE_MAX,
                       TEXTURE_SIZE_MAX);
  }
  int rgb = 0;
  /* Every file the bake reads: the maps and the bundle's files (no output may replace them). */
  const char *inputs[NBRDF_BAKE_PARAM_COUNT + 8];
  const char *const *model_files;
  int n_inputs = nbrdf_model_files(model, &model_files);
  for (int i = 0; i < n_inputs; i++)
    inputs[i] = model_files[i];
  char sources[4096] = "";
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    rgb |= texture_param_source_channels(src[id]) == 3;
    texture_param_map *m = texture_param_source_get_map(src[id]);
    if (m) inputs[n_inputs++] = texture_param_map_path(m);
    if (id) append(sources, sizeof sources, "; ");
    append(sources, sizeof sources, texture_param_source_describe(src[id]));
  }
  texture_latent_layout layout = {nbrdf_model_latent_dim(model),
                                  rgb ? NBRDF_COLOUR_RGB : NBRDF_COLOUR_MONO, 1};
  static const texture_latent_compression compression[4] = {NBRDF_LATENT_ZIP, NBRDF_LATENT_PIZ,
                                                            NBRDF_LATENT_RLE, NBRDF_LATENT_NONE};
  texture_latent_compression comp = compression[o->compression];
  char quant[16] = "off", settings[512];
  if (o->quantise_bits) snprintf(quant, sizeof quant, "%d", o->quantise_bits);
  snprintf(settings, sizeof settings,
           "storage=%s; compression=%s; tile=%d; mipLevels=%s; roughness=%s; range=%s; "
           "proxyMips=predicted; quantise=%s",
           o->storage == NBRDF_BAKE_FLOAT ? "float" : "half", texture_latent_compression_name(comp),
           o->tile_size, o->mip_levels == 1 ? "1" : "full", model_roughness_name(o->roughness),
           o->range == NBRDF_RANGE_REFUSE ? "refuse" : "clamp", quant);
  bake_progress prog = {.height = H};
  core_ticker_init(&prog.ticker, o->progress, o->user, o->cancel);
  /* Above the fast level: ground truth and fit first, before any file exists. */
  bake_accuracy_result acc = {0};
  nbrdf_model *specialised = NULL, *compact = NULL;
  if (o->accuracy != NBRDF_BAKE_FAST) {
    bake_scene scene = {src, W, H, rgb ? 3 : 1};
    st = bake_accuracy_prepare(model, &scene, o, &prog.ticker, &acc, err);
    /* SPECIALISED: the fine-tuned decoder copy becomes the model's own
     * decoder, whose bytes the texture then carries (format version 2). */
    if (st == NBRDF_OK && acc.correction.decoder)
      st = model_with_decoder_net(model, acc.correction.decoder, &specialised, err);
    /* COMPACT: the texels are computed as SPECIALISED's, then stored in the
     * basis's coordinates; the texture carries the student. */
    if (st == NBRDF_OK && acc.compact.student)
      st = model_with_decoder_net(model, acc.compact.student, &compact, err);
    if (st != NBRDF_OK) {
      bake_accuracy_free(&acc);
      nbrdf_model_destroy(specialised);
      return st;
    }
    if (specialised) model = specialised;
  }
  const texture_latent_layout work = layout;
  if (compact) layout.latent_dim = acc.compact.dim;
  /* A model with a decoder of its own (nbrdf_model_with_decoder) makes a
   * texture that carries it: version 2; else exactly version 1. */
  nbrdf_decoder_info own;
  nbrdf_model_own_decoder(compact ? compact : model, &own);
  texture_latent_meta meta = {nbrdf_model_name(model), nbrdf_model_checksum(model), sources,
                            settings, own.bytes, own.size, NULL};
  if (o->accuracy != NBRDF_BAKE_FAST) meta.accuracy = acc.attribute;
  mip_ctx mctx = {model, &layout, compact ? &acc.compact : NULL, &work, NULL};
  texture_latent_exr_options wo = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  wo.storage = o->storage == NBRDF_BAKE_FLOAT ? NBRDF_LATENT_FLOAT : NBRDF_LATENT_HALF;
  wo.tile_size = o->tile_size;
  wo.compression = comp;
  wo.mip_levels = o->mip_levels;
  wo.mip_row = mip_row;
  wo.mip_row_user = &mctx;
  wo.tick = writer_tick;
  wo.tick_user = &prog;
  wo.max_albedo_attr = o->energy_audit > 0;

  int band_rows = BAND_TEXELS / W;
  if (band_rows < 1) band_rows = 1;
  if (band_rows > H) band_rows = H;
  size_t texel_floats = (size_t)texture_latent_channel_count(&layout);
  size_t work_floats = (size_t)texture_latent_channel_count(&work);
  float *texels = malloc(sizeof(float) * work_floats * (size_t)band_rows * W);
  /* COMPACT: the band's texels (bundle latents) are reduced into `out` */
  float *out = compact ? malloc(sizeof(float) * texel_floats * (size_t)band_rows * W) : texels;
  if (compact) mctx.work_row = malloc(sizeof(float) * work_floats * (size_t)W);
  if (!texels || !out || (compact && !mctx.work_row)) {
    bake_accuracy_free(&acc);
    nbrdf_model_destroy(specialised);
    nbrdf_model_destroy(compact);
    if (out != texels) free(out);
    free(texels);
    free(mctx.work_row);
    return core_fail(err, NBRDF_ERR_MEMORY, "bake: out of memory for a band");
  }

  texture_latent_writer *writer = NULL;
  st = texture_latent_writer_create(&writer, out_path, W, H, &layout, &meta, &wo, inputs, n_inputs,
                                    err);
  bake_band band;
  /* One band: nothing to carry over, so no cache memory. */
  size_t cache_max = band_rows < H ? o->tuple_cache : 0;
  bake_band_init(&band, model, src, &work, W, o->roughness, o->range, cache_max,
                 o->quantise_bits);
  band.tick = band_tick;
  band.audit_tick = audit_tick;
  band.tick_user = &prog;
  bake_audit_init(&band.audit, o->energy_audit);
  if (compact) band.audit_model = compact, band.audit.compact = &acc.compact;
  if (o->accuracy != NBRDF_BAKE_FAST) band.correct = &acc.correction;
  model_gpu *gpu = NULL;
  if (st == NBRDF_OK) st = bake_device_open(model, compact ? compact : model, o, &gpu, err);
  band.gpu = gpu;
  band.audit.gpu_decoder = gpu ? gpu->decoder : NULL;
  for (int y = 0; st == NBRDF_OK && y < H; y += band_rows) {
    int rows = H - y < band_rows ? H - y : band_rows;
    prog.y = y, prog.rows = rows, prog.fraction = 0.0;
    if (core_ticker_tick(&prog.ticker, "bake", y, H, y == 0)) {
      st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled at row %d of %d", y, H);
      break;
    }
    st = bake_band_run(&band, y, rows, texels, err);
    if (st == NBRDF_OK && compact)
      bake_compact_texels(&acc.compact, &work, texels, &layout, out, (size_t)rows * W);
    for (int j = 0; st == NBRDF_OK && j < rows; j += WRITE_ROWS) {
      int n = rows - j < WRITE_ROWS ? rows - j : WRITE_ROWS;
      prog.fraction = BAKE_BAND_FRACTION + (1.0 - BAKE_BAND_FRACTION) * j / rows;
      if (j && writer_tick(&prog)) {
        st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled at row %d of %d", y + j, H);
        break;
      }
      st = texture_latent_writer_write_rows(writer, out + (size_t)j * W * texel_floats, n, err);
    }
  }
  if (st == NBRDF_OK && core_ticker_tick(&prog.ticker, "bake", H, H, 1))
    st = core_fail(err, NBRDF_ERR_CANCELLED, "bake: cancelled before the file was complete");
  if (st == NBRDF_OK) {
    if (band.audit.audited) texture_latent_writer_set_max_albedo(writer, (float)band.audit.worst);
    st = texture_latent_writer_finish(writer, err);
    writer = NULL;
  }
  texture_latent_writer_abort(writer);
  if (st == NBRDF_OK) {
    warn_clamped(&band, o);
    /* A budget too small for the level can leave it worse than fast (a compact student
     * of few steps): say so rather than let the texture pass for the better one. */
    if (o->accuracy != NBRDF_BAKE_FAST && o->warning && acc.heldout_error > acc.heldout_error_fast) {
      char msg[512];
      snprintf(msg, sizeof msg,
               "the %s texture's held-out lobe error (%.2f %%) is above the fast level's "
               "(%.2f %%) on the same %zu tuples: give it a larger --budget (this one: %g s)",
               nbrdf_bake_accuracy_name(o->accuracy), 100.0 * acc.heldout_error,
               100.0 * acc.heldout_error_fast, acc.heldout, acc.budget);
      o->warning(o->user, msg);
    }
    char audit_msg[768];
    bake_audit_message(&band.audit, rgb, audit_msg, sizeof audit_msg);
    if (audit_msg[0] && o->warning) o->warning(o->user, audit_msg);
    if (rep) {
      rep->width = W, rep->height = H;
      rep->colour_channels = rgb ? 3 : 1;
      rep->brdfs = (size_t)W * H * (rgb ? 3 : 1);
      snprintf(rep->device, sizeof rep->device, "%s", gpu ? gpu_context_name(gpu->ctx) : "cpu");
      rep->evaluated = band.evaluated;
      rep->reused = band.reused;
      rep->audited = band.audit.audited;
      rep->max_albedo = band.audit.audited ? band.audit.worst : NAN;
      rep->clamped = 0;
      for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
        rep->clamped += band.clamped[id];
      if (o->accuracy != NBRDF_BAKE_FAST) {
        rep->accuracy = o->accuracy;
        rep->budget = acc.budget;
        rep->distinct = acc.distinct;
        rep->fitted_tuples = acc.fitted;
        rep->heldout_tuples = acc.heldout;
        rep->heldout_error = acc.heldout_error;
        rep->heldout_error_fast = acc.heldout_error_fast;
      }
      if (compact) {
        rep->compact_dim = acc.compact.dim;
        rep->decoder_macs = (long long)nbrdf_model_decoder_macs(compact);
        rep->compact_kept = acc.compact.kept;
      }
    }
  }
  bake_accuracy_free(&acc);
  bake_band_free(&band);
  model_gpu_close(gpu);
  nbrdf_model_destroy(specialised);
  nbrdf_model_destroy(compact);
  if (out != texels) free(out);
  free(texels);
  free(mctx.work_row);
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
  if ((unsigned)o.accuracy > NBRDF_BAKE_COMPACT)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "bake: accuracy is fast, fitted, specialised or compact (0 to 3), not %d",
                     (int)o.accuracy);
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
  if (report) memset(report, 0, sizeof *report);
  texture_param_source *src[NBRDF_BAKE_PARAM_COUNT] = {0};
  st = bake_open_sources(inputs, src, err);
  if (st == NBRDF_OK) st = run(model, src, inputs, &o, out_path, report, err);
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
    texture_param_source_free(src[id]);
  return st;
}
