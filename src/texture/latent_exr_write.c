/* Streaming writer of latent textures (docs/LATENT-TEXTURE.md). */
#include <inttypes.h>
#include <fcntl.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"
#include "nbrdf/nbrdf.h"
#include "nn/safetensors.h"
#include "texture/exr_io.h"
#include "texture/latent_exr.h"
#include "texture/mip_chain.h"

#define HALF_MAX 65504.0f
/* Tiles compressed at once (one encode pipeline each, ~3 tiles of memory). */
#define MAX_PIPES 16
/* Rows of tiles smaller than this are compressed on one thread: waking (and
 * then spinning down) the OpenMP team costs more than it saves on the small
 * coarse levels. */
#define PARALLEL_MIN_BYTES ((size_t)1 << 20)

struct texture_latent_writer {
  core_output_file out;
  texture_exr_stream stream;
  exr_context_t exr;
  int part;
  texture_latent_layout layout;
  texture_latent_exr_options opts;
  int channels; /* floats per texel */
  int width, height, levels, tile;
  int lw[NBRDF_MIP_MAX_LEVELS], lh[NBRDF_MIP_MAX_LEVELS];
  /* band[l]: the tile row of level l being filled, tile * lw[l] texels. */
  float *band[NBRDF_MIP_MAX_LEVELS];
  texture_mip_builder *mip;
  int *logical; /* logical index of each EXR channel, in the file's (sorted) order */
  int exr_channels;
  exr_encode_pipeline_t enc[MAX_PIPES];
  int enc_ready[MAX_PIPES];
  int pipes;
  int64_t chunks_written;
  int failed;
  float max_albedo; /* NBRDF_ATTR_MAX_ALBEDO, patched in at finish */
};

static void destroy_pipes(texture_latent_writer *w) {
  for (int i = 0; i < MAX_PIPES; i++)
    if (w->enc_ready[i]) exr_encoding_destroy(w->exr, &w->enc[i]);
  memset(w->enc_ready, 0, sizeof w->enc_ready);
}

/* Tears down after an error or a cancel: the temporary file disappears at once. */
static void discard(texture_latent_writer *w) {
  destroy_pipes(w);
  if (w->exr) exr_finish(&w->exr);
  w->exr = NULL;
  core_output_file_abort(&w->out);
  w->failed = 1;
}

static void release(texture_latent_writer *w) {
  for (int l = 0; l < NBRDF_MIP_MAX_LEVELS; l++)
    free(w->band[l]);
  texture_mip_builder_free(w->mip);
  free(w->logical);
  free(w);
}

/* Chunks are written after compression, in tile order, by the caller:
 * compression runs in parallel, writing does not, so the file's bytes do not
 * depend on the number of threads. */
static exr_result_t defer_write(exr_encode_pipeline_t *pipe) {
  (void)pipe;
  return EXR_ERR_SUCCESS;
}

/* Prepares pipeline `slot` to encode tile (tx, ty) of `level`. */
static nbrdf_status prepare_tile(texture_latent_writer *w, int slot, int level, int tx, int ty,
                                 nbrdf_error *err) {
  exr_chunk_info_t cinfo;
  exr_result_t rv = exr_write_tile_chunk_info(w->exr, w->part, tx, ty, level, level, &cinfo);
  if (rv != EXR_ERR_SUCCESS)
    return texture_exr_fail(err, NBRDF_ERR_INTERNAL, &w->stream, rv, w->out.path, "tile layout");
  /* OpenEXRCore 3.1.5 sizes edge tiles of levels > 0 against level 0
   * (ECOSYSTEM-NOTES.md): size the chunk by the level's own edge. */
  int T = w->tile, lw = w->lw[level];
  int tw = lw - tx * T < T ? lw - tx * T : T;
  int th = w->lh[level] - ty * T < T ? w->lh[level] - ty * T : T;
  size_t bytes = w->opts.storage == NBRDF_LATENT_HALF ? 2 : 4;
  cinfo.width = tw;
  cinfo.height = th;
  cinfo.unpacked_size = (uint64_t)tw * (uint64_t)th * (uint64_t)w->exr_channels * bytes;

  exr_encode_pipeline_t *enc = &w->enc[slot];
  rv = w->enc_ready[slot] ? exr_encoding_update(w->exr, w->part, &cinfo, enc)
                          : exr_encoding_initialize(w->exr, w->part, &cinfo, enc);
  if (rv != EXR_ERR_SUCCESS)
    return texture_exr_fail(err, NBRDF_ERR_INTERNAL, &w->stream, rv, w->out.path, "encoder set-up");
  w->enc_ready[slot] = 1;
  const float *origin = w->band[level] + (size_t)tx * T * w->channels;
  for (int k = 0; k < enc->channel_count; k++) {
    exr_coding_channel_info_t *ch = &enc->channels[k];
    ch->user_bytes_per_element = 4;
    ch->user_data_type = EXR_PIXEL_FLOAT; /* the library converts to half */
    ch->user_pixel_stride = (int32_t)(w->channels * sizeof(float));
    ch->user_line_stride = (int32_t)((size_t)lw * w->channels * sizeof(float));
    ch->encode_from_ptr = (const uint8_t *)(origin + w->logical[k]);
  }
  rv = exr_encoding_choose_default_routines(w->exr, w->part, enc);
  if (rv != EXR_ERR_SUCCESS)
    return texture_exr_fail(err, NBRDF_ERR_INTERNAL, &w->stream, rv, w->out.path, "encoder");
  enc->yield_until_ready_fn = NULL;
  enc->write_fn = defer_write;
  return NBRDF_OK;
}

/* Encodes and writes the row ty of tiles of `level` (band[level] holds it). */
static nbrdf_status write_tile_row(texture_latent_writer *w, int level, int ty, nbrdf_error *err) {
  int tiles_x = (w->lw[level] + w->tile - 1) / w->tile;
  int rows = w->lh[level] - ty * w->tile < w->tile ? w->lh[level] - ty * w->tile : w->tile;
  size_t row_bytes =
      (size_t)w->lw[level] * rows * w->channels * (w->opts.storage == NBRDF_LATENT_HALF ? 2 : 4);
  int pipes = row_bytes >= PARALLEL_MIN_BYTES ? w->pipes : 1;
  char what[80];
  for (int g0 = 0; g0 < tiles_x; g0 += pipes) {
    if (w->opts.tick && w->opts.tick(w->opts.tick_user))
      return core_fail(err, NBRDF_ERR_CANCELLED, "%s: cancelled while writing level %d",
                       w->out.path, level);
    int n = tiles_x - g0 < pipes ? tiles_x - g0 : pipes;
    for (int i = 0; i < n; i++) {
      nbrdf_status st = prepare_tile(w, i, level, g0 + i, ty, err);
      if (st != NBRDF_OK) return st;
    }
    exr_result_t rv[MAX_PIPES];
#pragma omp parallel for num_threads(n) schedule(static, 1) if (n > 1)
    for (int i = 0; i < n; i++)
      rv[i] = exr_encoding_run(w->exr, w->part, &w->enc[i]);
    for (int i = 0; i < n; i++) {
      const exr_encode_pipeline_t *enc = &w->enc[i];
      /* A chunk that does not shrink is stored raw (packed size = unpacked
       * size). OpenEXRCore 3.1.5 then reports the raw size but leaves the
       * compressor's output in compressed_buffer (a 16x2 tile of noise came
       * back as zlib bytes read as halves): write the packed data ourselves. */
      const void *data = enc->compressed_buffer;
      uint64_t bytes = enc->compressed_bytes;
      if (bytes >= enc->packed_bytes) {
        data = enc->packed_buffer;
        bytes = enc->packed_bytes;
      }
      if (rv[i] == EXR_ERR_SUCCESS)
        rv[i] = exr_write_tile_chunk(w->exr, w->part, g0 + i, ty, level, level, data, bytes);
      if (rv[i] != EXR_ERR_SUCCESS) {
        snprintf(what, sizeof what, "writing tile (%d, %d) of level %d", g0 + i, ty, level);
        return texture_exr_fail(err, NBRDF_ERR_IO, &w->stream, rv[i], w->out.path, what);
      }
      w->chunks_written++;
    }
  }
  return NBRDF_OK;
}

/* The mip builder's sink: row y of `level` goes into that level's band; a
 * full band (or the level's last row) is written out as a row of tiles. */
static nbrdf_status on_row(void *user, int level, int y, float *row, nbrdf_error *err) {
  texture_latent_writer *w = user;
  int lw = w->lw[level];
  if (level > 0 && w->opts.mip_row) {
    nbrdf_status st = w->opts.mip_row(w->opts.mip_row_user, level, y, row, lw, err);
    if (st != NBRDF_OK) return st;
  }
  size_t n = (size_t)lw * w->channels;
  memcpy(w->band[level] + (size_t)(y % w->tile) * n, row, n * sizeof(float));
  if (y % w->tile != w->tile - 1 && y != w->lh[level] - 1) return NBRDF_OK;
  return write_tile_row(w, level, y / w->tile, err);
}

static nbrdf_status check_args(int width, int height, const texture_latent_layout *layout,
                               const texture_latent_exr_options *o, const texture_latent_meta *meta,
                               const char *path, nbrdf_error *err) {
  if (meta && meta->decoder &&
      (meta->decoder_size < 1 || meta->decoder_size > NBRDF_DECODER_BYTES_MAX))
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: an embedded decoder of %zu bytes; it must have 1 byte to %zu MiB", path,
                     meta->decoder_size, NBRDF_DECODER_BYTES_MAX >> 20);
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: size %dx%d is outside 1..65536", path, width,
                     height);
  nbrdf_status st = texture_latent_layout_check(layout, err);
  if (st != NBRDF_OK) {
    core_error_prefix(err, "%s: ", path);
    return st;
  }
  if (o->tile_size < 8 || o->tile_size > 1024)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: tile size %d is outside 8..1024", path,
                     o->tile_size);
  size_t bytes = o->storage == NBRDF_LATENT_FLOAT ? 4 : 2;
  if ((size_t)o->tile_size * o->tile_size * texture_latent_channel_count(layout) * bytes >
      NBRDF_LATENT_MAX_TILE_BYTES)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: %dx%d tiles of %d channels exceed %u MiB", path,
                     o->tile_size, o->tile_size, texture_latent_channel_count(layout),
                     NBRDF_LATENT_MAX_TILE_BYTES >> 20);
  if (o->mip_levels != 0 && o->mip_levels != 1)
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: mip levels %d: OpenEXR stores either the full chain (0) or "
                     "level 0 alone (1)",
                     path, o->mip_levels);
  if (o->storage != NBRDF_LATENT_HALF && o->storage != NBRDF_LATENT_FLOAT)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: unknown storage %d", path, (int)o->storage);
  if ((unsigned)o->compression > NBRDF_LATENT_NONE)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: unknown compression %d", path,
                     (int)o->compression);
  return NBRDF_OK;
}

/* Declares the part, its channels and attributes, and writes the header. */
static exr_result_t define_header(texture_latent_writer *w, const texture_latent_meta *meta) {
  exr_context_t c = w->exr;
  exr_result_t rv = exr_add_part(c, "", EXR_STORAGE_TILED, &w->part);
  int p = w->part;
  if (!rv)
    rv = exr_initialize_required_attr_simple(c, p, w->width, w->height,
                                             texture_exr_compression(w->opts.compression));
  if (!rv)
    rv = exr_set_tile_descriptor(c, p, (uint32_t)w->tile, (uint32_t)w->tile,
                                 w->levels > 1 ? EXR_TILE_MIPMAP_LEVELS : EXR_TILE_ONE_LEVEL,
                                 EXR_TILE_ROUND_DOWN);
  /* Coarse levels complete while finer ones are still being written, so
   * tiles of several levels interleave: only RANDOM_Y allows that. */
  if (!rv) rv = exr_set_lineorder(c, p, EXR_LINEORDER_RANDOM_Y);
  exr_pixel_type_t type = w->opts.storage == NBRDF_LATENT_HALF ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
  char name[32];
  for (int i = 0; !rv && i < w->channels; i++) {
    texture_latent_channel_name(&w->layout, i, name, sizeof name);
    rv = exr_add_channel(c, p, name, type, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
  }
  char writer[64];
  snprintf(writer, sizeof writer, "nbrdf %s", nbrdf_version());
  const texture_latent_meta none = {0};
  if (!meta) meta = &none;
#define STR(s) ((s) ? (s) : "")
  /* Without a decoder of its own the file is exactly a version-1 file. */
  int version = meta->decoder ? NBRDF_LATENT_FORMAT_OWN_DECODER : NBRDF_LATENT_FORMAT_V1;
  if (!rv) rv = exr_attr_set_int(c, p, NBRDF_ATTR_FORMAT_VERSION, version);
  if (!rv) rv = exr_attr_set_int(c, p, NBRDF_ATTR_LATENT_DIM, w->layout.latent_dim);
  if (!rv)
    rv = exr_attr_set_string(c, p, NBRDF_ATTR_COLOUR_MODE,
                             texture_colour_mode_name(w->layout.colour));
  if (!rv) rv = exr_attr_set_int(c, p, NBRDF_ATTR_PROXY, w->layout.proxy);
  if (!rv) rv = exr_attr_set_string(c, p, NBRDF_ATTR_MODEL_NAME, STR(meta->model_name));
  if (!rv) rv = exr_attr_set_string(c, p, NBRDF_ATTR_MODEL_CHECKSUM, STR(meta->model_checksum));
  if (!rv) rv = exr_attr_set_string(c, p, NBRDF_ATTR_SOURCES, STR(meta->sources));
  if (!rv) rv = exr_attr_set_string(c, p, NBRDF_ATTR_SETTINGS, STR(meta->settings));
  if (!rv) rv = exr_attr_set_string(c, p, NBRDF_ATTR_MIP_FILTER, NBRDF_MIP_FILTER_BOX);
  if (!rv) rv = exr_attr_set_string(c, p, NBRDF_ATTR_WRITER, writer);
  if (!rv && meta->decoder) {
    /* An opaque attribute: readers that do not know the type keep (or drop)
     * the bytes without interpreting them. check_args bounded the size. */
    char sum[17];
    snprintf(sum, sizeof sum, "%016" PRIx64,
             nn_st_fnv1a64(NBRDF_ST_FNV1A64_INIT, meta->decoder, meta->decoder_size));
    rv = exr_attr_set_user(c, p, NBRDF_ATTR_DECODER, NBRDF_DECODER_ATTR_TYPE,
                           (int32_t)meta->decoder_size, meta->decoder);
    if (!rv) rv = exr_attr_set_string(c, p, NBRDF_ATTR_DECODER_CHECKSUM, sum);
  }
  if (!rv && w->opts.max_albedo_attr) rv = exr_attr_set_float(c, p, NBRDF_ATTR_MAX_ALBEDO, -1.0f);
  if (!rv && meta->accuracy) rv = exr_attr_set_string(c, p, NBRDF_ATTR_ACCURACY, meta->accuracy);
  if (!rv && meta->inputs) rv = exr_attr_set_string(c, p, NBRDF_ATTR_INPUTS, meta->inputs);
#undef STR
  if (!rv) rv = exr_write_header(c);
  return rv;
}

/* Maps the file's channel order to logical indices and checks that the
 * library's level sizes agree with ours (mip_chain.h). */
static nbrdf_status check_layout(texture_latent_writer *w, nbrdf_error *err) {
  const exr_attr_chlist_t *list = NULL;
  int32_t lx = 0, ly = 0;
  exr_result_t rv = exr_get_channels(w->exr, w->part, &list);
  if (!rv) rv = exr_get_tile_levels(w->exr, w->part, &lx, &ly);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_INTERNAL, &w->stream, rv, w->out.path, "header");
  if (lx != w->levels || list->num_channels != w->channels)
    return core_fail(err, NBRDF_ERR_INTERNAL, "%s: OpenEXR made %d levels and %d channels",
                     w->out.path, lx, list->num_channels);
  w->exr_channels = list->num_channels;
  w->logical = malloc(sizeof(int) * (size_t)list->num_channels);
  if (!w->logical) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", w->out.path);
  for (int k = 0; k < list->num_channels; k++)
    w->logical[k] = texture_latent_channel_index(&w->layout, list->entries[k].name.str);
  for (int l = 0; l < w->levels; l++) {
    int32_t sx = 0, sy = 0;
    rv = exr_get_level_sizes(w->exr, w->part, l, l, &sx, &sy);
    if (rv || sx != w->lw[l] || sy != w->lh[l])
      return core_fail(err, NBRDF_ERR_INTERNAL, "%s: level %d is %dx%d in OpenEXR, %dx%d here",
                       w->out.path, l, sx, sy, w->lw[l], w->lh[l]);
  }
  return NBRDF_OK;
}

nbrdf_status texture_latent_writer_create(texture_latent_writer **out, const char *path, int width,
                                          int height, const texture_latent_layout *layout,
                                          const texture_latent_meta *meta,
                                          const texture_latent_exr_options *opts,
                                          const char *const *inputs, int n_inputs,
                                          nbrdf_error *err) {
  *out = NULL;
  const texture_latent_exr_options defaults = NBRDF_LATENT_EXR_OPTIONS_DEFAULT;
  if (!opts) opts = &defaults;
  if (!path) return core_fail(err, NBRDF_ERR_ARGUMENT, "output path is NULL");
  nbrdf_status st = check_args(width, height, layout, opts, meta, path, err);
  if (st != NBRDF_OK) return st;
  texture_latent_writer *w = calloc(1, sizeof *w);
  if (!w) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  w->out.fd = -1;
  w->layout = *layout;
  w->opts = *opts;
  w->channels = texture_latent_channel_count(layout);
  w->width = width;
  w->height = height;
  w->tile = opts->tile_size;
  w->levels = opts->mip_levels == 1 ? 1 : texture_mip_level_count(width, height);
  w->stream.fd = -1;
  w->stream.out = &w->out;
  w->max_albedo = -1.0f;
  w->pipes = omp_get_max_threads();
  if (w->pipes > MAX_PIPES) w->pipes = MAX_PIPES;
  if (w->pipes < 1) w->pipes = 1;
  for (int l = 0; l < w->levels; l++) {
    w->lw[l] = texture_mip_level_dim(width, l);
    w->lh[l] = texture_mip_level_dim(height, l);
    int rows = w->lh[l] < w->tile ? w->lh[l] : w->tile;
    w->band[l] = malloc((size_t)rows * (size_t)w->lw[l] * (size_t)w->channels * sizeof(float));
    if (!w->band[l]) {
      release(w);
      return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory for %d texel wide tiles", path,
                       width);
    }
  }
  st = core_output_file_open(&w->out, path, inputs, n_inputs, err);
  if (st != NBRDF_OK) {
    release(w);
    return st;
  }
  exr_context_initializer_t init = texture_exr_initializer(&w->stream, 1);
  exr_result_t rv = exr_start_write(&w->exr, path, EXR_WRITE_FILE_DIRECTLY, &init);
  if (!rv) rv = define_header(w, meta);
  if (rv) st = texture_exr_fail(err, NBRDF_ERR_IO, &w->stream, rv, path, "writing the header");
  if (st == NBRDF_OK) st = check_layout(w, err);
  if (st == NBRDF_OK)
    st = texture_mip_builder_create(width, height, w->channels, w->levels, on_row, w, &w->mip, err);
  if (st != NBRDF_OK) {
    discard(w);
    release(w);
    return st;
  }
  *out = w;
  return NBRDF_OK;
}

static nbrdf_status check_values(const texture_latent_writer *w, const float *texels, int rows,
                                 nbrdf_error *err) {
  int y0 = texture_mip_builder_rows(w->mip);
  float limit = w->opts.storage == NBRDF_LATENT_HALF ? HALF_MAX : INFINITY;
  size_t n = (size_t)rows * w->width * w->channels;
  for (size_t i = 0; i < n; i++) {
    float v = texels[i];
    if (isfinite(v) && fabsf(v) <= limit) continue;
    size_t texel = i / (size_t)w->channels;
    char name[32];
    texture_latent_channel_name(&w->layout, (int)(i % (size_t)w->channels), name, sizeof name);
    int x = (int)(texel % (size_t)w->width), y = y0 + (int)(texel / (size_t)w->width);
    if (!isfinite(v))
      return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: texel (%d, %d) %s is %s", w->out.path, x, y,
                       name, isnan(v) ? "NaN" : "infinite");
    return core_fail(err, NBRDF_ERR_ARGUMENT,
                     "%s: texel (%d, %d) %s = %g exceeds the half range; store as float",
                     w->out.path, x, y, name, (double)v);
  }
  return NBRDF_OK;
}

nbrdf_status texture_latent_writer_write_rows(texture_latent_writer *w, const float *texels,
                                              int rows, nbrdf_error *err) {
  if (w->failed)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "latent writer already failed; abort it");
  int done = texture_mip_builder_rows(w->mip);
  nbrdf_status st = NBRDF_OK;
  if (rows < 0 || rows > w->height - done)
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "%s: %d rows after %d of %d", w->out.path, rows, done,
                   w->height);
  if (st == NBRDF_OK) st = check_values(w, texels, rows, err);
  size_t row_floats = (size_t)w->width * w->channels;
  for (int j = 0; st == NBRDF_OK && j < rows; j++)
    st = texture_mip_builder_push_row(w->mip, texels + (size_t)j * row_floats, err);
  if (st != NBRDF_OK) discard(w);
  return st;
}

void texture_latent_writer_set_max_albedo(texture_latent_writer *w, float value) {
  if (w && isfinite(value)) w->max_albedo = value;
}

/* Overwrites the placeholder value of NBRDF_ATTR_MAX_ALBEDO in the header
 * already on disk: the attribute is "name\0float\0", a 4-byte size and the
 * little-endian float (OpenEXR's header layout), found in the header bytes. */
static nbrdf_status patch_max_albedo(texture_latent_writer *w, nbrdf_error *err) {
  static const char key[] = NBRDF_ATTR_MAX_ALBEDO "\0float\0\4\0\0\0";
  const size_t klen = sizeof key - 1, cap = (size_t)1 << 20;
  unsigned char *buf = malloc(cap);
  if (!buf) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", w->out.path);
  /* The temporary file's descriptor is write-only: read it through its name. */
  int rfd = open(core_output_file_name(&w->out), O_RDONLY | O_CLOEXEC);
  ssize_t got = rfd >= 0 ? pread(rfd, buf, cap, 0) : -1;
  if (rfd >= 0) close(rfd);
  nbrdf_status st = core_fail(err, NBRDF_ERR_INTERNAL, "%s: %s not found in the header",
                              w->out.path, NBRDF_ATTR_MAX_ALBEDO);
  for (ssize_t i = 0; got > 0 && i + (ssize_t)klen + 4 <= got; i++) {
    if (memcmp(buf + i, key, klen) != 0) continue;
    uint32_t bits;
    memcpy(&bits, &w->max_albedo, 4);
    unsigned char le[4] = {(unsigned char)bits, (unsigned char)(bits >> 8),
                           (unsigned char)(bits >> 16), (unsigned char)(bits >> 24)};
    st = core_output_file_pwrite(&w->out, le, 4, (long long)(i + (ssize_t)klen), err);
    break;
  }
  free(buf);
  return st;
}

nbrdf_status texture_latent_writer_finish(texture_latent_writer *w, nbrdf_error *err) {
  nbrdf_status st = NBRDF_OK;
  if (w->failed)
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "latent writer already failed; nothing written");
  int done = st == NBRDF_OK ? texture_mip_builder_rows(w->mip) : 0;
  if (st == NBRDF_OK && done != w->height)
    st = core_fail(err, NBRDF_ERR_ARGUMENT, "%s: only %d of %d rows were written", w->out.path,
                   done, w->height);
  int32_t chunks = 0;
  if (st == NBRDF_OK && (exr_get_chunk_count(w->exr, w->part, &chunks) != EXR_ERR_SUCCESS ||
                         chunks != w->chunks_written))
    st = core_fail(err, NBRDF_ERR_INTERNAL, "%s: %lld of %d tiles written", w->out.path,
                   (long long)w->chunks_written, chunks);
  if (st == NBRDF_OK) {
    destroy_pipes(w);
    exr_result_t rv = exr_finish(&w->exr);
    w->exr = NULL;
    if (rv != EXR_ERR_SUCCESS)
      st = texture_exr_fail(err, NBRDF_ERR_IO, &w->stream, rv, w->out.path, "finishing");
  }
  if (st == NBRDF_OK && w->opts.max_albedo_attr) st = patch_max_albedo(w, err);
  if (st == NBRDF_OK)
    st = core_output_file_commit(&w->out, err);
  else if (!w->failed)
    discard(w);
  release(w);
  return st;
}

void texture_latent_writer_abort(texture_latent_writer *w) {
  if (!w) return;
  if (!w->failed) discard(w);
  release(w);
}
