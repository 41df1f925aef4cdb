/* Validating reader of latent textures (docs/LATENT-TEXTURE.md). Every
 * value taken from the file is checked before it sizes a buffer or an
 * index, so that damaged files fail with a message instead of a crash. */
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/input_file.h"
#include "nn/safetensors.h"
#include "texture/exr_io.h"
#include "texture/latent_exr.h"
#include "texture/mip_chain.h"

enum {
  S_MODEL,
  S_CHECKSUM,
  S_SOURCES,
  S_SETTINGS,
  S_FILTER,
  S_WRITER,
  S_ACCURACY,
  S_INPUTS,
  S_DECODER_SUM,
  S_COUNT
};

struct texture_latent_reader {
  char *path;
  texture_exr_stream stream;
  exr_context_t exr;
  texture_latent_info info;
  char *strings[S_COUNT];
  int lw[NBRDF_MIP_MAX_LEVELS], lh[NBRDF_MIP_MAX_LEVELS];
  const exr_attr_chlist_t *chlist;
  const char **logical_names; /* EXR name of each logical channel */
  const void *decoder;        /* version 2: the own decoder's bytes (the EXR context's) */
  float *scratch;
  size_t scratch_floats;
};

static nbrdf_status bad(nbrdf_error *err, const texture_latent_reader *r, const char *fmt,
                        const char *detail) {
  return core_fail(err, NBRDF_ERR_FORMAT, "%s: %s%s", r->path, fmt, detail ? detail : "");
}

static nbrdf_status get_int(texture_latent_reader *r, const char *name, int *out,
                            nbrdf_error *err) {
  int32_t v = 0;
  exr_result_t rv = exr_attr_get_int(r->exr, 0, name, &v);
  if (rv == EXR_ERR_NO_ATTR_BY_NAME)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: not an nbrdf latent texture (no %s attribute)",
                     r->path, name);
  if (rv != EXR_ERR_SUCCESS)
    return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, name);
  *out = v;
  return NBRDF_OK;
}

/* A string attribute, copied; absent ones read as "" unless required. */
static nbrdf_status get_string(texture_latent_reader *r, const char *name, int required, char **out,
                               nbrdf_error *err) {
  int32_t len = 0;
  const char *s = NULL;
  exr_result_t rv = exr_attr_get_string(r->exr, 0, name, &len, &s);
  if (rv == EXR_ERR_NO_ATTR_BY_NAME && !required) {
    s = "";
    len = 0;
  } else if (rv == EXR_ERR_NO_ATTR_BY_NAME) {
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: not an nbrdf latent texture (no %s attribute)",
                     r->path, name);
  } else if (rv != EXR_ERR_SUCCESS) {
    return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, name);
  }
  if (len < 0 || (len > 0 && !s)) return bad(err, r, "malformed attribute ", name);
  *out = strndup(s, (size_t)len);
  if (!*out) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", r->path);
  return NBRDF_OK;
}

static nbrdf_status check_structure(texture_latent_reader *r, nbrdf_error *err) {
  texture_latent_info *in = &r->info;
  int parts = 0;
  exr_storage_t storage;
  exr_result_t rv = exr_get_count(r->exr, &parts);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, "parts");
  if (parts != 1) return bad(err, r, "a latent texture has one part", NULL);
  rv = exr_get_storage(r->exr, 0, &storage);
  if (rv || storage != EXR_STORAGE_TILED)
    return bad(err, r, "not a tiled image (latent textures are tiled)", NULL);
  uint32_t tx = 0, ty = 0;
  exr_tile_level_mode_t mode;
  exr_tile_round_mode_t round;
  rv = exr_get_tile_descriptor(r->exr, 0, &tx, &ty, &mode, &round);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, "tiles");
  if (mode != EXR_TILE_MIPMAP_LEVELS && mode != EXR_TILE_ONE_LEVEL)
    return bad(err, r, "tiles are neither mip-mapped nor single-level", NULL);
  if (round != EXR_TILE_ROUND_DOWN) return bad(err, r, "mip levels are not rounded down", NULL);
  if (tx < 1 || ty < 1 || tx > 1024 || ty > 1024) return bad(err, r, "bad tile size", NULL);
  in->tile_width = (int)tx;
  in->tile_height = (int)ty;
  exr_attr_box2i_t dw;
  rv = exr_get_data_window(r->exr, 0, &dw);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, "data window");
  if (dw.min.x != 0 || dw.min.y != 0) return bad(err, r, "data window does not start at 0", NULL);
  if (dw.max.x < 0 || dw.max.y < 0 || dw.max.x > 65535 || dw.max.y > 65535)
    return bad(err, r, "bad data window", NULL);
  in->width = dw.max.x + 1;
  in->height = dw.max.y + 1;
  int32_t lx = 0, ly = 0;
  rv = exr_get_tile_levels(r->exr, 0, &lx, &ly);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, "levels");
  int expect = mode == EXR_TILE_ONE_LEVEL ? 1 : texture_mip_level_count(in->width, in->height);
  if (lx != expect || ly != expect) return bad(err, r, "unexpected number of mip levels", NULL);
  in->levels = expect;
  for (int l = 0; l < expect; l++) {
    int32_t sx = 0, sy = 0;
    rv = exr_get_level_sizes(r->exr, 0, l, l, &sx, &sy);
    r->lw[l] = texture_mip_level_dim(in->width, l);
    r->lh[l] = texture_mip_level_dim(in->height, l);
    if (rv || sx != r->lw[l] || sy != r->lh[l]) return bad(err, r, "bad mip level size", NULL);
  }
  exr_compression_t comp;
  rv = exr_get_compression(r->exr, 0, &comp);
  if (rv || !texture_exr_compression_from(comp, &in->compression))
    return bad(err, r, "latents must be stored with lossless compression", NULL);
  return NBRDF_OK;
}

/* Version 2: the own decoder's bytes, present, of the right type and size,
 * and matching their checksum (the safetensors inside are parsed when a
 * model is made of them, latent_decoder.c). */
static nbrdf_status read_decoder(texture_latent_reader *r, nbrdf_error *err) {
  texture_latent_info *in = &r->info;
  const char *type = NULL;
  int32_t size = 0;
  const void *bytes = NULL;
  exr_result_t rv = exr_attr_get_user(r->exr, 0, NBRDF_ATTR_DECODER, &type, &size, &bytes);
  if (rv == EXR_ERR_NO_ATTR_BY_NAME)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: format version %d says the texture carries its own decoder, but the "
                     "%s attribute is missing: a tool that copies only the attributes it knows "
                     "(oiiotool, for one) dropped it. Re-bake the texture, or copy the file "
                     "byte for byte (cp) instead of through an image tool",
                     r->path, in->format_version, NBRDF_ATTR_DECODER);
  if (rv != EXR_ERR_SUCCESS)
    return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, NBRDF_ATTR_DECODER);
  if (!type || strcmp(type, NBRDF_DECODER_ATTR_TYPE) != 0)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: attribute %s has type '%s', expected '%s'",
                     r->path, NBRDF_ATTR_DECODER, type ? type : "?", NBRDF_DECODER_ATTR_TYPE);
  if (size < 1 || (size_t)size > NBRDF_DECODER_BYTES_MAX || !bytes)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: the embedded decoder has %d bytes; expected 1 byte to %zu MiB", r->path,
                     (int)size, NBRDF_DECODER_BYTES_MAX >> 20);
  nbrdf_status st = get_string(r, NBRDF_ATTR_DECODER_CHECKSUM, 1, &r->strings[S_DECODER_SUM], err);
  if (st != NBRDF_OK) return st;
  char sum[17];
  snprintf(sum, sizeof sum, "%016" PRIx64,
           nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, bytes, (size_t)size));
  if (strcmp(sum, r->strings[S_DECODER_SUM]) != 0)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: the embedded decoder is damaged: its %d bytes have checksum %s, the "
                     "header records %.20s",
                     r->path, (int)size, sum, r->strings[S_DECODER_SUM]);
  r->decoder = bytes;
  in->decoder_size = (size_t)size;
  in->decoder_checksum = r->strings[S_DECODER_SUM];
  return NBRDF_OK;
}

static nbrdf_status read_attributes(texture_latent_reader *r, nbrdf_error *err) {
  texture_latent_info *in = &r->info;
  nbrdf_status st = get_int(r, NBRDF_ATTR_FORMAT_VERSION, &in->format_version, err);
  if (st != NBRDF_OK) return st;
  if (in->format_version > NBRDF_LATENT_FORMAT_VERSION)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: latent texture format version %d is newer than this nbrdf reads "
                     "(%d); update nbrdf",
                     r->path, in->format_version, NBRDF_LATENT_FORMAT_VERSION);
  if (in->format_version < 1)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: bad format version %d", r->path,
                     in->format_version);
  char *mode = NULL;
  st = get_int(r, NBRDF_ATTR_LATENT_DIM, &in->layout.latent_dim, err);
  if (st == NBRDF_OK) st = get_int(r, NBRDF_ATTR_PROXY, &in->layout.proxy, err);
  if (st == NBRDF_OK) st = get_string(r, NBRDF_ATTR_COLOUR_MODE, 1, &mode, err);
  if (st != NBRDF_OK) return st;
  int known = texture_colour_mode_parse(mode, &in->layout.colour);
  free(mode);
  if (!known) return bad(err, r, "unknown colour mode", NULL);
  st = texture_latent_layout_check(&in->layout, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", r->path);
    if (err) err->status = NBRDF_ERR_FORMAT;
    return NBRDF_ERR_FORMAT;
  }
  in->channels = texture_latent_channel_count(&in->layout);
  static const char *const names[S_DECODER_SUM] = {NBRDF_ATTR_MODEL_NAME, NBRDF_ATTR_MODEL_CHECKSUM,
                                             NBRDF_ATTR_SOURCES,    NBRDF_ATTR_SETTINGS,
                                             NBRDF_ATTR_MIP_FILTER, NBRDF_ATTR_WRITER,
                                             NBRDF_ATTR_ACCURACY,   NBRDF_ATTR_INPUTS};
  for (int i = 0; st == NBRDF_OK && i < S_DECODER_SUM; i++)
    st = get_string(r, names[i], i == S_MODEL || i == S_CHECKSUM, &r->strings[i], err);
  if (st != NBRDF_OK) return st;
  in->model_name = r->strings[S_MODEL];
  in->model_checksum = r->strings[S_CHECKSUM];
  in->sources = r->strings[S_SOURCES];
  in->settings = r->strings[S_SETTINGS];
  in->mip_filter = r->strings[S_FILTER];
  in->writer = r->strings[S_WRITER];
  /* Optional (older bakes lack it); a negative value: the audit did not run. */
  float a = -1.0f;
  in->max_albedo = exr_attr_get_float(r->exr, 0, NBRDF_ATTR_MAX_ALBEDO, &a) == EXR_ERR_SUCCESS &&
                           isfinite(a) && a >= 0.0f
                       ? (double)a
                       : NAN;
  in->accuracy = r->strings[S_ACCURACY];
  in->inputs = r->strings[S_INPUTS];
  if (in->format_version < NBRDF_LATENT_FORMAT_OWN_DECODER) {
    /* Version 1 has no decoder of its own (attributes of that name are not its). */
    r->strings[S_DECODER_SUM] = strdup("");
    in->decoder_checksum = r->strings[S_DECODER_SUM];
    return in->decoder_checksum ? NBRDF_OK
                                : core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", r->path);
  }
  return read_decoder(r, err);
}

/* Every logical channel must be present, full resolution, half or float. */
static nbrdf_status map_channels(texture_latent_reader *r, nbrdf_error *err) {
  exr_result_t rv = exr_get_channels(r->exr, 0, &r->chlist);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, "channels");
  int n = r->info.channels;
  r->logical_names = calloc((size_t)n, sizeof(char *));
  if (!r->logical_names) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", r->path);
  int any_half = 0;
  for (int k = 0; k < r->chlist->num_channels; k++) {
    const exr_attr_chlist_entry_t *e = &r->chlist->entries[k];
    if (!e->name.str) return bad(err, r, "unnamed channel", NULL);
    int i = texture_latent_channel_index(&r->info.layout, e->name.str);
    if (i < 0) continue; /* other channels are allowed and ignored */
    if (e->x_sampling != 1 || e->y_sampling != 1)
      return bad(err, r, "subsampled channel ", e->name.str);
    if (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT)
      return bad(err, r, "channel is neither half nor float: ", e->name.str);
    any_half |= e->pixel_type == EXR_PIXEL_HALF;
    r->logical_names[i] = e->name.str;
  }
  uint64_t tile_bytes = 0;
  for (int k = 0; k < r->chlist->num_channels; k++)
    tile_bytes += r->chlist->entries[k].pixel_type == EXR_PIXEL_HALF ? 2 : 4;
  tile_bytes *= (uint64_t)r->info.tile_width * (uint64_t)r->info.tile_height;
  if (tile_bytes > NBRDF_LATENT_MAX_TILE_BYTES) return bad(err, r, "tiles are too large", NULL);
  for (int i = 0; i < n; i++)
    if (!r->logical_names[i]) {
      char name[32];
      texture_latent_channel_name(&r->info.layout, i, name, sizeof name);
      return bad(err, r, "missing channel ", name);
    }
  r->info.storage = any_half ? NBRDF_LATENT_HALF : NBRDF_LATENT_FLOAT;
  return NBRDF_OK;
}

nbrdf_status texture_latent_reader_open(texture_latent_reader **out, const char *path,
                                        nbrdf_error *err) {
  *out = NULL;
  if (!path) return core_fail(err, NBRDF_ERR_ARGUMENT, "latent texture path is NULL");
  texture_latent_reader *r = calloc(1, sizeof *r);
  if (!r || !(r->path = strdup(path))) {
    free(r);
    return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  }
  uint64_t file_size = 0;
  nbrdf_status st = core_input_open(path, NBRDF_INPUT_ANY_SIZE, &r->stream.fd, &file_size, err);
  if (st == NBRDF_OK) {
    r->info.file_size = (int64_t)file_size;
    exr_context_initializer_t init = texture_exr_initializer(&r->stream, 0);
    exr_result_t rv = exr_start_read(&r->exr, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
      r->exr = NULL;
      st = texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, path,
                            "not a readable OpenEXR file");
    }
  }
  if (st == NBRDF_OK) st = check_structure(r, err);
  if (st == NBRDF_OK) st = read_attributes(r, err);
  if (st == NBRDF_OK) st = map_channels(r, err);
  if (st != NBRDF_OK) {
    texture_latent_reader_close(r);
    return st;
  }
  *out = r;
  return NBRDF_OK;
}

const texture_latent_info *texture_latent_reader_info(const texture_latent_reader *r) {
  return &r->info;
}
const char *texture_latent_reader_path(const texture_latent_reader *r) { return r->path; }
const void *texture_latent_reader_decoder(const texture_latent_reader *r, size_t *size) {
  *size = r->decoder ? r->info.decoder_size : 0;
  return r->decoder;
}

nbrdf_status texture_latent_reader_level_size(const texture_latent_reader *r, int level, int *width,
                                              int *height, nbrdf_error *err) {
  if (level < 0 || level >= r->info.levels)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: level %d outside 0..%d", r->path, level,
                     r->info.levels - 1);
  *width = r->lw[level];
  *height = r->lh[level];
  return NBRDF_OK;
}

void texture_latent_reader_close(texture_latent_reader *r) {
  if (!r) return;
  if (r->exr) exr_finish(&r->exr);
  if (r->stream.fd >= 0) close(r->stream.fd);
  for (int i = 0; i < S_COUNT; i++)
    free(r->strings[i]);
  free(r->logical_names);
  free(r->scratch);
  free(r->path);
  free(r);
}

/* For each channel of the file, its position among the `n` requested names
 * (or -1). */
static nbrdf_status request_slots(const texture_latent_reader *r, const char *const *names, int n,
                                  int *slot, nbrdf_error *err) {
  int count = r->chlist->num_channels;
  for (int k = 0; k < count; k++)
    slot[k] = -1;
  for (int j = 0; j < n; j++) {
    int k = 0;
    while (k < count && (!names[j] || strcmp(r->chlist->entries[k].name.str, names[j]) != 0))
      k++;
    if (k == count)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: no channel '%s'", r->path,
                       names[j] ? names[j] : "(null)");
    if (slot[k] >= 0)
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: channel '%s' requested twice", r->path,
                       names[j]);
    if (r->chlist->entries[k].pixel_type == EXR_PIXEL_UINT ||
        r->chlist->entries[k].x_sampling != 1 || r->chlist->entries[k].y_sampling != 1)
      return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: channel '%s' is not a plain float image",
                       r->path, names[j]);
    slot[k] = j;
  }
  return NBRDF_OK;
}

/* Decodes tile (tx, ty) of `level` into r->scratch (tile width x height
 * texels of n floats). */
static nbrdf_status decode_tile(texture_latent_reader *r, exr_decode_pipeline_t *dec, int *ready,
                                const int *slot, int n, int level, int tx, int ty, int tw, int th,
                                nbrdf_error *err) {
  char where[96];
  snprintf(where, sizeof where, "tile (%d, %d) of level %d", tx, ty, level);
  exr_chunk_info_t ci;
  exr_result_t rv = exr_read_tile_chunk_info(r->exr, 0, tx, ty, level, level, &ci);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, where);
  if (ci.width != tw || ci.height != th)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: %s is %dx%d, expected %dx%d", r->path, where,
                     ci.width, ci.height, tw, th);
  if (ci.data_offset > (uint64_t)r->info.file_size ||
      ci.packed_size > (uint64_t)r->info.file_size - ci.data_offset)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: %s lies past the end of the file (truncated?)",
                     r->path, where);
  rv = *ready ? exr_decoding_update(r->exr, 0, &ci, dec)
              : exr_decoding_initialize(r->exr, 0, &ci, dec);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, where);
  *ready = 1;
  if (dec->channel_count != r->chlist->num_channels)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: %s has %d channels, the header %d", r->path, where,
                     dec->channel_count, r->chlist->num_channels);
  for (int k = 0; k < dec->channel_count; k++) {
    exr_coding_channel_info_t *ch = &dec->channels[k];
    int j = slot[k];
    ch->decode_to_ptr = j < 0 ? NULL : (uint8_t *)(r->scratch + j);
    ch->user_bytes_per_element = 4;
    ch->user_data_type = EXR_PIXEL_FLOAT;
    ch->user_pixel_stride = (int32_t)(n * sizeof(float));
    ch->user_line_stride = (int32_t)((size_t)tw * n * sizeof(float));
  }
  rv = exr_decoding_choose_default_routines(r->exr, 0, dec);
  if (!rv) rv = exr_decoding_run(r->exr, 0, dec);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, &r->stream, rv, r->path, where);
  return NBRDF_OK;
}

nbrdf_status texture_latent_reader_read_channels(texture_latent_reader *r, int level, int x, int y,
                                                 int w, int h, const char *const *names, int n,
                                                 float *out, nbrdf_error *err) {
  int lw = 0, lh = 0;
  nbrdf_status st = texture_latent_reader_level_size(r, level, &lw, &lh, err);
  if (st != NBRDF_OK) return st;
  if (x < 0 || y < 0 || w < 1 || h < 1 || w > lw - x || h > lh - y)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: rectangle %dx%d at (%d, %d) lies outside level %d (%dx%d)", r->path, w, h,
                     x, y, level, lw, lh);
  if (n < 1 || n > 65536)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: %d channels requested", r->path, n);
  int *slot = malloc(sizeof(int) * (size_t)r->chlist->num_channels);
  if (!slot) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", r->path);
  st = request_slots(r, names, n, slot, err);
  int T = r->info.tile_width, U = r->info.tile_height;
  size_t need = (size_t)T * (size_t)U * (size_t)n;
  if (st == NBRDF_OK && need > r->scratch_floats) {
    free(r->scratch);
    r->scratch = malloc(need * sizeof(float));
    r->scratch_floats = r->scratch ? need : 0;
    if (!r->scratch) st = core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", r->path);
  }
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int ready = 0;
  for (int ty = y / U; st == NBRDF_OK && ty <= (y + h - 1) / U; ty++) {
    for (int tx = x / T; st == NBRDF_OK && tx <= (x + w - 1) / T; tx++) {
      int tw = lw - tx * T < T ? lw - tx * T : T, th = lh - ty * U < U ? lh - ty * U : U;
      st = decode_tile(r, &dec, &ready, slot, n, level, tx, ty, tw, th, err);
      if (st != NBRDF_OK) break;
      /* Copy the part of the tile that overlaps the rectangle. */
      int x0 = tx * T > x ? tx * T : x, x1 = tx * T + tw < x + w ? tx * T + tw : x + w;
      int y0 = ty * U > y ? ty * U : y, y1 = ty * U + th < y + h ? ty * U + th : y + h;
      for (int yy = y0; yy < y1; yy++)
        memcpy(out + ((size_t)(yy - y) * w + (size_t)(x0 - x)) * n,
               r->scratch + ((size_t)(yy - ty * U) * tw + (size_t)(x0 - tx * T)) * n,
               (size_t)(x1 - x0) * n * sizeof(float));
    }
  }
  if (ready) exr_decoding_destroy(r->exr, &dec);
  free(slot);
  return st;
}

nbrdf_status texture_latent_reader_read(texture_latent_reader *r, int level, int x, int y, int w,
                                        int h, float *out, nbrdf_error *err) {
  return texture_latent_reader_read_channels(r, level, x, y, w, h, r->logical_names,
                                             r->info.channels, out, err);
}

nbrdf_status texture_latent_check_model(const texture_latent_info *info, const char *path,
                                        const char *model_name, const char *model_checksum,
                                        nbrdf_error *err) {
  if (model_checksum && strcmp(info->model_checksum, model_checksum) != 0)
    return core_fail(err, NBRDF_ERR_MISMATCH,
                     "%s: baked with model '%s' (checksum %s), not with '%s' (checksum %s): decode it "
                     "with the bundle of that checksum (`nbrdf bundle info DIR` prints one's)",
                     path, info->model_name, info->model_checksum, model_name ? model_name : "?",
                     model_checksum);
  if (model_name && strcmp(info->model_name, model_name) != 0)
    return core_fail(err, NBRDF_ERR_MISMATCH, "%s: baked with model '%s', not '%s'", path,
                     info->model_name, model_name);
  return NBRDF_OK;
}
