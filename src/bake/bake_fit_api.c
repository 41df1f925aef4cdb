/* nbrdf/fit.h: a fit over the tiles of a set, kept in a .nbfit file, and the
 * checks a bake with it makes (the model, the options, its inputs). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bake/bake_fit_file.h"
#include "bake/bake_sources.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/output_file.h"
#include "core/progress.h"
#include "model/material.h"
#include "nbrdf/fit.h"
#include "nn/safetensors.h"

/* ---- the inputs a fit records ---- */

/* FNV-1a 64 of the file's bytes (nn_st_fnv1a64, the checksum of models and decoders). */
static nbrdf_status file_hash(const char *path, uint64_t *hash, nbrdf_error *err) {
  int fd = -1;
  nbrdf_status st = core_input_open(path, NBRDF_INPUT_ANY_SIZE, &fd, NULL, err);
  if (st != NBRDF_OK) return st;
  unsigned char buf[1 << 16];
  uint64_t h = NBRDF_ST_FNV1A64_INIT;
  for (;;) {
    ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0) {
      st = core_fail(err, NBRDF_ERR_IO, "%s: cannot be read to hash it", path);
      break;
    }
    if (n == 0) break;
    h = nn_st_fnv1a64(h, buf, (size_t)n);
  }
  close(fd);
  *hash = h;
  return st;
}

/* The fewest significant digits that read back as `x` (as people typed it: 1.6, not
 * 1.60000002); 9 always do. */
static void shortest(float x, char *out, size_t cap) {
  for (int digits = 6; digits <= 9; digits++) {
    snprintf(out, cap, "%.*g", digits, x);
    if (strtof(out, NULL) == x) return;
  }
}

/* One parameter's input as a fit records it: a map by its content hash and the
 * way it is read (colour space, remap), a constant by its value. */
static nbrdf_status input_entry(int id, const nbrdf_bake_param *p, char *out, size_t cap,
                                nbrdf_error *err) {
  if (!p->path) {
    char v[3][32];
    for (int c = 0; c < 3; c++)
      shortest(p->value[c], v[c], sizeof v[c]);
    if (p->channels == 3)
      snprintf(out, cap, "constant %s,%s,%s", v[0], v[1], v[2]);
    else
      snprintf(out, cap, "constant %s", v[0]);
    return NBRDF_OK;
  }
  uint64_t h = 0;
  nbrdf_status st = file_hash(p->path, &h, err);
  if (st != NBRDF_OK) return st;
  const int colour = id == NBRDF_BAKE_R0 || id == NBRDF_BAKE_ALBEDO;
  char remap[64] = "";
  if (p->remap) snprintf(remap, sizeof remap, " remap=%.9g..%.9g", p->lo, p->hi);
  snprintf(out, cap, "map fnv1a64=%016" PRIx64 " read=%s%s", h,
           colour ? (p->colour_space ? p->colour_space : "srgb") : "data", remap);
  return NBRDF_OK;
}

/* Whether `entry` is one of the lines of `list`. */
static int listed(const char *list, const char *entry) {
  size_t n = strlen(entry);
  for (const char *s = list; s && *s;) {
    const char *e = strchr(s, '\n');
    size_t len = e ? (size_t)(e - s) : strlen(s);
    if (len == n && !memcmp(s, entry, n)) return 1;
    s = e ? e + 1 : s + len;
  }
  return 0;
}

/* Appends `entry` to the list of one parameter unless it is there. */
static nbrdf_status record(char **list, const char *entry, nbrdf_error *err) {
  if (listed(*list, entry)) return NBRDF_OK;
  size_t had = *list ? strlen(*list) : 0, n = strlen(entry);
  char *grown = realloc(*list, had + n + 2);
  if (!grown) return core_fail(err, NBRDF_ERR_MEMORY, "fit: out of memory");
  if (had) grown[had++] = '\n';
  memcpy(grown + had, entry, n + 1);
  *list = grown;
  return NBRDF_OK;
}

/* ---- the fit ---- */

static nbrdf_status check_run_args(const nbrdf_model *model, const nbrdf_bake_inputs *tiles,
                                   size_t n_tiles, const nbrdf_bake_options *o, const char *path,
                                   nbrdf_error *err) {
  if (!model || !tiles || !n_tiles || !path || !*path)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "fit: model, at least one set of inputs and an output path are required");
  if (n_tiles > 1000000)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "fit: %zu sets of inputs; at most 1000000", n_tiles);
  if (o->fit) return core_fail(err, NBRDF_ERR_ARGUMENT, "fit: options.fit must be NULL");
  if (o->accuracy == NBRDF_BAKE_FAST || o->accuracy == NBRDF_BAKE_AUTO)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "fit: accuracy is fitted, specialised or compact (fast has nothing to fit; "
                     "a fit holds one level, so auto is the bake's)");
  for (size_t i = 1; i < n_tiles; i++)
    if (tiles[i].resample != tiles[0].resample)
      return core_fail(err, NBRDF_ERR_ARGUMENT,
                       "fit: the sets of inputs 1 and %zu are resampled differently", i + 1);
  return nbrdf_bake_options_check(model, o, err);
}

/* Opens one tile's sources and sizes its scene as nbrdf_bake does. */
static nbrdf_status open_scene(const nbrdf_bake_inputs *in, texture_param_source **src,
                               bake_scene *sc, nbrdf_error *err) {
  nbrdf_status st = bake_open_sources(in, src, err);
  int W = 0, H = 0, rgb = 0;
  if (st == NBRDF_OK)
    st = texture_param_sources_common_size(src, NBRDF_BAKE_PARAM_COUNT, &W, &H, err);
  if (st == NBRDF_OK && W == 0) {
    W = in->width ? in->width : 1;
    H = in->height ? in->height : 1;
  }
  for (int id = 0; st == NBRDF_OK && id < NBRDF_BAKE_PARAM_COUNT; id++)
    rgb |= texture_param_source_channels(src[id]) == 3;
  *sc = (bake_scene){src, W, H, rgb ? 3 : 1};
  return st;
}

/* The files an output must not replace: every map of every tile and the bundle's files. */
static const char **input_paths(const nbrdf_model *model, const nbrdf_bake_inputs *tiles,
                                size_t n_tiles, int *n) {
  const char *const *files;
  int nf = nbrdf_model_files(model, &files);
  const char **paths = malloc(sizeof *paths * ((size_t)nf + n_tiles * NBRDF_BAKE_PARAM_COUNT));
  *n = 0;
  if (!paths) return NULL;
  for (int i = 0; i < nf; i++)
    paths[(*n)++] = files[i];
  for (size_t t = 0; t < n_tiles; t++)
    for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++)
      if (tiles[t].param[id].path) paths[(*n)++] = tiles[t].param[id].path;
  return paths;
}

static void fill_info(const nbrdf_fit *f, nbrdf_fit_info *info) {
  memset(info, 0, sizeof *info);
  info->accuracy = f->accuracy;
  info->tiles = f->tiles;
  info->distinct = f->r.distinct;
  info->fitted_tuples = f->r.fitted;
  info->heldout_tuples = f->r.heldout;
  info->heldout_error = f->r.heldout_error;
  info->heldout_error_fast = f->r.heldout_error_fast;
  info->budget = f->r.budget;
  memcpy(info->model_checksum, f->model_checksum, sizeof info->model_checksum);
  memcpy(info->decoder_checksum, f->decoder_checksum, sizeof info->decoder_checksum);
  memcpy(info->file_checksum, f->file_checksum, sizeof info->file_checksum);
}

/* The fit proper: sources of every tile open at once (bake_accuracy_fit gathers
 * across them), then the inputs recorded and the file written. */
static nbrdf_status fit_tiles(const nbrdf_model *model, const nbrdf_bake_inputs *tiles,
                              size_t n_tiles, const nbrdf_bake_options *o, nbrdf_fit *f,
                              nbrdf_error *err) {
  texture_param_source **src = calloc(n_tiles * NBRDF_BAKE_PARAM_COUNT, sizeof *src);
  bake_scene *scenes = calloc(n_tiles, sizeof *scenes);
  nbrdf_status st = NBRDF_OK;
  if (!src || !scenes) st = core_fail(err, NBRDF_ERR_MEMORY, "fit: out of memory");
  for (size_t t = 0; st == NBRDF_OK && t < n_tiles; t++)
    st = open_scene(&tiles[t], src + t * NBRDF_BAKE_PARAM_COUNT, &scenes[t], err);
  core_ticker ticker;
  core_ticker_init(&ticker, o->progress, o->user, o->cancel);
  if (st == NBRDF_OK) st = bake_accuracy_fit(model, scenes, n_tiles, o, &ticker, &f->r, err);
  for (size_t i = 0; src && i < n_tiles * NBRDF_BAKE_PARAM_COUNT; i++)
    texture_param_source_free(src[i]);
  free(src);
  free(scenes);
  return st;
}

nbrdf_status nbrdf_fit_run(const nbrdf_model *model, const nbrdf_bake_inputs *tiles,
                           size_t n_tiles, const nbrdf_bake_options *options, const char *path,
                           nbrdf_fit_info *info, nbrdf_error *err) {
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  if (options) o = *options;
  nbrdf_status st = check_run_args(model, tiles, n_tiles, &o, path, err);
  if (st != NBRDF_OK) return st;
  int n_inputs = 0;
  const char **inputs = input_paths(model, tiles, n_tiles, &n_inputs);
  if (!inputs) return core_fail(err, NBRDF_ERR_MEMORY, "fit: out of memory");
  /* Refused before the work rather than after it. */
  st = core_output_check(path, inputs, n_inputs, err);
  nbrdf_fit f;
  memset(&f, 0, sizeof f);
  f.accuracy = o.accuracy, f.roughness = o.roughness, f.range = o.range;
  f.resample = tiles[0].resample, f.quantise_bits = o.quantise_bits, f.tiles = (int)n_tiles;
  snprintf(f.model_checksum, sizeof f.model_checksum, "%s", nbrdf_model_checksum(model));
  nbrdf_decoder_info own;
  nbrdf_model_own_decoder(model, &own);
  snprintf(f.base_decoder, sizeof f.base_decoder, "%s", own.checksum);
  char entry[256];
  for (size_t t = 0; st == NBRDF_OK && t < n_tiles; t++)
    for (int id = 0; st == NBRDF_OK && id < NBRDF_BAKE_PARAM_COUNT; id++) {
      st = input_entry(id, &tiles[t].param[id], entry, sizeof entry, err);
      if (st == NBRDF_OK) st = record(&f.inputs[id], entry, err);
    }
  if (st == NBRDF_OK) st = fit_tiles(model, tiles, n_tiles, &o, &f, err);
  if (st == NBRDF_OK) st = bake_fit_decoder_checksum(&f.r, f.decoder_checksum, err);
  /* A cancel during the last steps still leaves no file. */
  if (st == NBRDF_OK && o.cancel && *o.cancel)
    st = core_fail(err, NBRDF_ERR_CANCELLED, "fit: cancelled before the file was written");
  if (st == NBRDF_OK) st = bake_fit_file_write(&f, path, inputs, n_inputs, err);
  if (st == NBRDF_OK && info) fill_info(&f, info);
  free(inputs);
  bake_fit_release(&f);
  return st;
}

nbrdf_status nbrdf_fit_open(const char *path, nbrdf_fit **out, nbrdf_error *err) {
  if (!path || !out) return core_fail(err, NBRDF_ERR_ARGUMENT, "fit: NULL argument");
  *out = NULL;
  nbrdf_fit *f = calloc(1, sizeof *f);
  if (!f) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  nbrdf_status st = bake_fit_file_read(path, f, err);
  if (st != NBRDF_OK) {
    free(f);
    return st;
  }
  /* Every texture baked with it names the fit (the tiles of a set: the same). */
  size_t len = strlen(f->r.attribute);
  snprintf(f->r.attribute + len, sizeof f->r.attribute - len, "; fit=%s", f->file_checksum);
  *out = f;
  return NBRDF_OK;
}

void nbrdf_fit_destroy(nbrdf_fit *fit) {
  if (!fit) return;
  bake_fit_release(fit);
  free(fit);
}

void nbrdf_fit_describe(const nbrdf_fit *fit, nbrdf_fit_info *info) { fill_info(fit, info); }

/* ---- a bake with it ---- */

static nbrdf_status differs(const nbrdf_fit *f, const char *what, const char *fitted,
                            const char *now, nbrdf_error *err) {
  return core_fail(err, NBRDF_ERR_MISMATCH,
                   "%s: fitted with %s %s, but this bake has %s %s: bake with the fit's, or fit "
                   "again",
                   f->path, what, fitted, what, now);
}

nbrdf_status nbrdf_fit_check(const nbrdf_fit *f, const nbrdf_model *model,
                             const nbrdf_bake_inputs *in, const nbrdf_bake_options *options,
                             nbrdf_error *err) {
  if (!f || !model || !in) return core_fail(err, NBRDF_ERR_ARGUMENT, "fit: NULL argument");
  nbrdf_bake_options o = NBRDF_BAKE_OPTIONS_DEFAULT;
  if (options) o = *options;
  if (strcmp(f->model_checksum, nbrdf_model_checksum(model)))
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "%s: fitted with the bundle of checksum %s, not this one (%s): bake with "
                     "that bundle, or fit again with this one",
                     f->path, f->model_checksum, nbrdf_model_checksum(model));
  nbrdf_decoder_info own;
  nbrdf_model_own_decoder(model, &own);
  if (strcmp(f->base_decoder, own.checksum))
    return differs(f, "the decoder", f->base_decoder[0] ? f->base_decoder : "(the bundle's)",
                   own.checksum[0] ? own.checksum : "(the bundle's)", err);
  if (o.accuracy != NBRDF_BAKE_FAST && o.accuracy != f->accuracy)
    return differs(f, "accuracy", nbrdf_bake_accuracy_name(f->accuracy),
                   nbrdf_bake_accuracy_name(o.accuracy), err);
  if (o.roughness != f->roughness)
    return differs(f, "roughness", model_roughness_name(f->roughness),
                   model_roughness_name(o.roughness), err);
  if (o.range != f->range)
    return differs(f, "range", f->range == NBRDF_RANGE_REFUSE ? "refuse" : "clamp",
                   o.range == NBRDF_RANGE_REFUSE ? "refuse" : "clamp", err);
  if (o.quantise_bits != f->quantise_bits) {
    char a[16], b[16];
    snprintf(a, sizeof a, "%d", f->quantise_bits);
    snprintf(b, sizeof b, "%d", o.quantise_bits);
    return differs(f, "quantise bits", f->quantise_bits ? a : "off", o.quantise_bits ? b : "off",
                   err);
  }
  if (in->resample != f->resample)
    return differs(f, "resample", f->resample ? "bilinear" : "none",
                   in->resample ? "bilinear" : "none", err);
  char entry[256];
  for (int id = 0; id < NBRDF_BAKE_PARAM_COUNT; id++) {
    const nbrdf_bake_param *p = &in->param[id];
    nbrdf_status st = input_entry(id, p, entry, sizeof entry, err);
    if (st != NBRDF_OK) return st;
    if (listed(f->inputs[id], entry)) continue;
    /* Refused rather than warned about: its tuples may be ones the fit never saw, whose
     * correction would be carried from the nearest fitted ones. */
    if (p->path)
      return core_fail(err, NBRDF_ERR_MISMATCH,
                       "%s: the %s map %s (%s) is not among the inputs the fit was made from: "
                       "fit again with it",
                       f->path, model_material_param_name(id), p->path, entry);
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "%s: the %s %s is not among the inputs the fit was made from: fit again "
                     "with it",
                     f->path, model_material_param_name(id), entry);
  }
  return NBRDF_OK;
}
