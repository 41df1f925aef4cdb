#include "texture/image_check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"
#include "core/input_file.h"
#include "texture/exr_io.h"

static uint32_t be32(const unsigned char *b) {
  return (uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | b[3];
}
static uint32_t le32(const unsigned char *b) {
  return (uint32_t)b[3] << 24 | (uint32_t)b[2] << 16 | (uint32_t)b[1] << 8 | b[0];
}

/* PNG: signature, then chunks of length, type, data, CRC up to IEND. */
static nbrdf_status check_png(FILE *f, const char *path, uint64_t size, nbrdf_error *err) {
  uint64_t pos = 8;
  for (;;) {
    unsigned char head[8];
    if (fseek(f, (long)pos, SEEK_SET) != 0 || fread(head, 1, 8, f) != 8)
      return core_fail(err, NBRDF_ERR_FORMAT, "%s: truncated PNG (no IEND chunk)", path);
    uint64_t len = be32(head);
    if (len > 0x7fffffffu || len + 12 > size - pos)
      return core_fail(err, NBRDF_ERR_FORMAT,
                       "%s: PNG chunk '%.4s' at byte %llu claims %llu bytes; the file has %llu",
                       path, (const char *)head + 4, (unsigned long long)pos,
                       (unsigned long long)len, (unsigned long long)(size - pos));
    if (!memcmp(head + 4, "IEND", 4)) return NBRDF_OK;
    pos += len + 12;
  }
}

/* OpenEXR: magic, version, then headers of attributes (name NUL, type NUL,
 * int32 size, value) each ending with an empty name; a multi-part file has
 * several headers and an empty one after them. */
/* A NUL-terminated name of at most `max` characters: OpenEXR's reader stops
 * at the limit without looking for the NUL, so a longer name would make it
 * read the following bytes as the type and size this walk did not check. */
static int read_name(FILE *f, char name[256], int max, uint64_t *pos) {
  int n = 0, c;
  while ((c = fgetc(f)) > 0 && n < max)
    name[n++] = (char)c;
  name[n] = '\0';
  *pos += (uint64_t)n + 1;
  return c == 0;
}

/* The size OpenEXR's C++ reader assumes for an attribute of a fixed-size type, whatever
 * the header declares (0: a type of variable size). A box2i declared as 7 bytes makes it
 * read 16 and take the next attribute's size from the wrong bytes (fuzz_param_map: a
 * 1.9 GB allocation for a 639-byte file that OpenEXRCore's header check accepts). */
static uint64_t exr_fixed_size(const char *type) {
  static const struct {
    const char *type;
    uint64_t size;
  } fixed[] = {{"box2i", 16}, {"box2f", 16}, {"int", 4},     {"float", 4},  {"double", 8},
               {"v2i", 8},    {"v2f", 8},    {"v2d", 16},    {"v3i", 12},   {"v3f", 12},
               {"v3d", 24},   {"m33f", 36},  {"m33d", 72},   {"m44f", 64},  {"m44d", 128},
               {"compression", 1}, {"lineOrder", 1}, {"envmap", 1}, {"deepImageState", 1},
               {"chromaticities", 32}, {"tiledesc", 9}, {"rational", 8}, {"keycode", 28},
               {"timecode", 8}};
  for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
    if (!strcmp(type, fixed[i].type)) return fixed[i].size;
  return 0;
}

static nbrdf_status check_exr(FILE *f, const char *path, uint64_t size, unsigned flags,
                              nbrdf_error *err) {
  const int multipart = (flags & 0x1000u) != 0;
  const int max_name = flags & 0x400u ? 255 : 31; /* the "long names" bit */
  uint64_t pos = 8;
  for (;;) {
    int attrs = 0;
    for (;; attrs++) {
      char name[256], type[256];
      unsigned char b[4];
      if (!read_name(f, name, max_name, &pos) ||
          (name[0] && !read_name(f, type, max_name, &pos)))
        return core_fail(err, NBRDF_ERR_FORMAT,
                         "%s: OpenEXR header truncated or malformed (a name of more than %d "
                         "characters, or no end)",
                         path, max_name);
      if (!name[0]) break;
      if (fread(b, 1, 4, f) != 4)
        return core_fail(err, NBRDF_ERR_FORMAT, "%s: OpenEXR header truncated", path);
      pos += 4;
      uint64_t len = le32(b), fixed = exr_fixed_size(type);
      if (fixed && len != fixed)
        return core_fail(err, NBRDF_ERR_FORMAT,
                         "%s: OpenEXR attribute '%s' of type %s declares %llu bytes, expected %llu",
                         path, name, type, (unsigned long long)len, (unsigned long long)fixed);
      if (len > 0x7fffffffu || len > size - pos)
        return core_fail(err, NBRDF_ERR_FORMAT,
                         "%s: OpenEXR attribute '%s' claims %llu bytes; the file has %llu left",
                         path, name, (unsigned long long)len, (unsigned long long)(size - pos));
      pos += len;
      if (fseek(f, (long)pos, SEEK_SET) != 0)
        return core_fail(err, NBRDF_ERR_IO, "%s: cannot seek", path);
    }
    /* One header, or a multi-part file's headers up to an empty one. */
    if (!multipart || attrs == 0) return NBRDF_OK;
  }
}

/* Decodes one chunk with OpenEXRCore into `scratch` (floats, every channel). */
static exr_result_t decode_chunk(exr_context_t ctx, const exr_chunk_info_t *ci,
                                 exr_decode_pipeline_t *dec, int *ready, float **scratch,
                                 size_t *cap) {
  exr_result_t rv =
      *ready ? exr_decoding_update(ctx, 0, ci, dec) : exr_decoding_initialize(ctx, 0, ci, dec);
  if (rv) return rv;
  *ready = 1;
  size_t texels = (size_t)ci->width * (size_t)ci->height, need = texels * dec->channel_count;
  if (need > *cap) {
    float *p = realloc(*scratch, need * sizeof(float));
    if (!p) return EXR_ERR_OUT_OF_MEMORY;
    *scratch = p;
    *cap = need;
  }
  for (int k = 0; k < dec->channel_count; k++) {
    exr_coding_channel_info_t *ch = &dec->channels[k];
    ch->decode_to_ptr = (uint8_t *)(*scratch + (size_t)k * texels);
    ch->user_bytes_per_element = 4;
    ch->user_data_type = EXR_PIXEL_FLOAT;
    ch->user_pixel_stride = 4;
    ch->user_line_stride = 4 * ci->width;
  }
  rv = exr_decoding_choose_default_routines(ctx, 0, dec);
  return rv ? rv : exr_decoding_run(ctx, 0, dec);
}

/* Every chunk of level 0 of the first part decodes to its full size. OpenEXR 3.1's C++
 * reader (behind OpenImageIO) can return a damaged ZIP chunk's rows without an error,
 * partly unwritten: fuzz_param_map found maps that baked different texels from run to run
 * (valgrind: uninitialised memory from its decompressor). OpenEXRCore checks each chunk's
 * unpacked size, so a damaged map is refused here before anything reads it. */
static nbrdf_status check_exr_chunks(exr_context_t ctx, texture_exr_stream *stream,
                                     const char *path, nbrdf_error *err) {
  exr_storage_t storage;
  exr_attr_box2i_t dw;
  exr_result_t rv = exr_get_storage(ctx, 0, &storage);
  if (!rv) rv = exr_get_data_window(ctx, 0, &dw);
  if (rv) return texture_exr_fail(err, NBRDF_ERR_FORMAT, stream, rv, path, "header");
  if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
    return NBRDF_OK; /* deep data: OpenImageIO refuses it as a map anyway */
  exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
  int ready = 0;
  float *scratch = NULL;
  size_t cap = 0;
  char where[96] = "";
  if (storage == EXR_STORAGE_SCANLINE) {
    int32_t lines = 1;
    rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    for (int64_t y = dw.min.y; !rv && y <= dw.max.y; y += lines > 0 ? lines : 1) {
      exr_chunk_info_t ci;
      snprintf(where, sizeof where, "scanline chunk at row %lld", (long long)(y - dw.min.y));
      rv = exr_read_scanline_chunk_info(ctx, 0, (int)y, &ci);
      if (!rv) rv = decode_chunk(ctx, &ci, &dec, &ready, &scratch, &cap);
    }
  } else {
    int32_t tw = 0, th = 0, lw = 0, lh = 0;
    rv = exr_get_tile_sizes(ctx, 0, 0, 0, &tw, &th);
    if (!rv) rv = exr_get_level_sizes(ctx, 0, 0, 0, &lw, &lh);
    for (int ty = 0; !rv && tw > 0 && th > 0 && ty < (lh + th - 1) / th; ty++)
      for (int tx = 0; !rv && tx < (lw + tw - 1) / tw; tx++) {
        exr_chunk_info_t ci;
        snprintf(where, sizeof where, "tile (%d, %d)", tx, ty);
        rv = exr_read_tile_chunk_info(ctx, 0, tx, ty, 0, 0, &ci);
        if (!rv) rv = decode_chunk(ctx, &ci, &dec, &ready, &scratch, &cap);
      }
  }
  if (ready) exr_decoding_destroy(ctx, &dec);
  free(scratch);
  if (rv == EXR_ERR_OUT_OF_MEMORY) return core_fail(err, NBRDF_ERR_MEMORY, "%s: out of memory", path);
  if (rv) {
    char what[160];
    snprintf(what, sizeof what, "damaged %s", where);
    return texture_exr_fail(err, NBRDF_ERR_FORMAT, stream, rv, path, what);
  }
  return NBRDF_OK;
}

/* OpenEXRCore's reading of the header, which checks every attribute's
 * content against its declared size: OpenEXR 3.1's C++ reader does not (a
 * channel list is read to its end marker whatever its size says), so a
 * header the walk above accepts can still make it read a later size from the
 * wrong bytes (fuzz_param_map: a 1.9 GB allocation); then every chunk. */
static nbrdf_status check_exr_core(const char *path, const void *data, size_t size,
                                   nbrdf_error *err) {
  texture_exr_stream stream = {.fd = -1, .mem = data, .mem_size = size};
  nbrdf_status st = NBRDF_OK;
  if (!data) st = core_input_open(path, NBRDF_INPUT_ANY_SIZE, &stream.fd, NULL, err);
  if (st != NBRDF_OK) return st;
  exr_context_initializer_t init = texture_exr_initializer(&stream, 0);
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_read(&ctx, path, &init);
  if (rv != EXR_ERR_SUCCESS) {
    st = texture_exr_fail(err, NBRDF_ERR_FORMAT, &stream, rv, path, "malformed OpenEXR header");
  } else {
    st = check_exr_chunks(ctx, &stream, path, err);
    exr_finish(&ctx);
  }
  if (stream.fd >= 0) close(stream.fd);
  return st;
}

static uint16_t le16(const unsigned char *b) { return (uint16_t)(b[1] << 8 | b[0]); }

/* BMP: the file header, an info header OpenImageIO's reader knows, and the combinations of
 * bit depth and compression the format defines, with the palette and (uncompressed) pixels
 * inside the file. OpenImageIO 2.4's reader trusts them: a 75-byte file declaring 24-bit
 * texels with 8-bit run-length compression crashed it (SIGSEGV, fuzz_param_map). */
static nbrdf_status check_bmp(FILE *f, const char *path, uint64_t size, nbrdf_error *err) {
  unsigned char h[54];
  if (fseek(f, 0, SEEK_SET) != 0 || fread(h, 1, sizeof h, f) != sizeof h)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: truncated BMP header", path);
  uint32_t offset = le32(h + 10), info = le32(h + 14), compression = le32(h + 30);
  int32_t width = (int32_t)le32(h + 18), height = (int32_t)le32(h + 22);
  unsigned planes = le16(h + 26), bpp = le16(h + 28);
  uint64_t colours = le32(h + 46);
  if (info != 40 && info != 52 && info != 56 && info != 108 && info != 124)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s: BMP info header of %u bytes", path, info);
  if (width < 1 || height == 0 || height == INT32_MIN || planes != 1)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: BMP of %dx%d texels and %u planes", path, width,
                     height, planes);
  int ok = (compression == 0 && (bpp == 1 || bpp == 4 || bpp == 8 || bpp == 16 || bpp == 24 ||
                                 bpp == 32)) ||
           (compression == 1 && bpp == 8) || (compression == 2 && bpp == 4) ||
           (compression == 3 && (bpp == 16 || bpp == 32));
  if (!ok)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: BMP of %u bits per texel with compression %u (not a valid pair)", path,
                     bpp, compression);
  uint64_t palette = bpp <= 8 ? (colours ? colours : 1ull << bpp) : 0;
  if (bpp <= 8 && colours > (1ull << bpp))
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: BMP palette of %llu colours for %u bits", path,
                     (unsigned long long)colours, bpp);
  if (offset > size || 14ull + info + 4 * palette > offset)
    return core_fail(err, NBRDF_ERR_FORMAT,
                     "%s: BMP texels at byte %u overlap its headers or lie past the end (%llu bytes)",
                     path, offset, (unsigned long long)size);
  uint64_t rows = height < 0 ? (uint64_t)(-(int64_t)height) : (uint64_t)height;
  /* OpenImageIO 2.4 decodes a run-length image whole inside open(), before the shim can bound
   * its size: a 201-byte RLE4 file claiming 3x687865853 texels allocated 2 GB
   * (fuzz_param_map). A two-byte packet holds at most 255 texels, the bound the shim applies
   * to every BMP after opening it. */
  if ((compression == 1 || compression == 2) && (uint64_t)width * rows > 128 * size)
    return core_fail(err, NBRDF_ERR_FORMAT, "%s: a BMP image of %dx%d texels cannot fit in %llu bytes",
                     path, width, height, (unsigned long long)size);
  if (compression == 0 || compression == 3) {
    uint64_t stride = ((uint64_t)width * bpp + 31) / 32 * 4;
    if (stride * rows > size - offset)
      return core_fail(err, NBRDF_ERR_FORMAT, "%s: BMP of %dx%d texels needs %llu bytes; %llu follow",
                       path, width, height, (unsigned long long)(stride * rows),
                       (unsigned long long)(size - offset));
  }
  return NBRDF_OK;
}

/* OpenImageIO's BMP reader takes the OS/2 signatures as well as "BM", with the same header
 * after them: a 150-byte file starting "BA" and declaring a 51712x38403 run-length image
 * allocated 2 GB before the shim could bound it (fuzz_param_map). */
static int bmp_magic(const unsigned char *m) {
  static const char *const sig[] = {"BM", "BA", "CI", "CP", "IC", "PT"};
  for (size_t i = 0; i < sizeof sig / sizeof sig[0]; i++)
    if (!memcmp(m, sig[i], 2)) return 1;
  return 0;
}

/* `data` NULL: the file at `path`, else `size` bytes at `data` (`path` labels them). */
static nbrdf_status check(const char *path, const void *data, uint64_t size, nbrdf_error *err) {
  if (size == 0) return core_fail(err, NBRDF_ERR_FORMAT, "%s: is empty (0 bytes)", path);
  FILE *f = data ? fmemopen((void *)data, (size_t)size, "rb") : fopen(path, "rb");
  if (!f) return core_fail(err, NBRDF_ERR_IO, "%s: cannot open", path);
  unsigned char magic[8] = {0};
  size_t got = fread(magic, 1, 8, f);
  nbrdf_status st = NBRDF_OK;
  if (got == 8 && !memcmp(magic, "\x89PNG\r\n\x1a\n", 8))
    st = check_png(f, path, size, err);
  else if (got == 8 && !memcmp(magic, "\x76\x2f\x31\x01", 4))
    st = check_exr(f, path, size, le32(magic + 4), err);
  else if (got >= 2 && bmp_magic(magic))
    st = check_bmp(f, path, size, err);
  fclose(f);
  if (st == NBRDF_OK && got == 8 && !memcmp(magic, "\x76\x2f\x31\x01", 4))
    st = check_exr_core(path, data, (size_t)size, err);
  return st;
}

nbrdf_status texture_image_check_structure(const char *path, uint64_t size, nbrdf_error *err) {
  return check(path, NULL, size, err);
}

nbrdf_status texture_image_check_memory(const char *label, const void *data, size_t size,
                                        nbrdf_error *err) {
  if (size && !data) return core_fail(err, NBRDF_ERR_ARGUMENT, "%s: NULL data", label);
  return check(label, size ? data : "", size, err);
}
