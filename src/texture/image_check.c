#include "texture/image_check.h"

#include <stdio.h>
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
      uint64_t len = le32(b);
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

/* OpenEXRCore's reading of the header, which checks every attribute's
 * content against its declared size: OpenEXR 3.1's C++ reader does not (a
 * channel list is read to its end marker whatever its size says), so a
 * header the walk above accepts can still make it read a later size from the
 * wrong bytes (fuzz_param_map: a 1.9 GB allocation). */
static nbrdf_status check_exr_core(const char *path, nbrdf_error *err) {
  texture_exr_stream stream = {.fd = -1};
  nbrdf_status st = core_input_open(path, NBRDF_INPUT_ANY_SIZE, &stream.fd, NULL, err);
  if (st != NBRDF_OK) return st;
  exr_context_initializer_t init = texture_exr_initializer(&stream, 0);
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_read(&ctx, path, &init);
  if (rv != EXR_ERR_SUCCESS)
    st = texture_exr_fail(err, NBRDF_ERR_FORMAT, &stream, rv, path, "malformed OpenEXR header");
  else
    exr_finish(&ctx);
  close(stream.fd);
  return st;
}

nbrdf_status texture_image_check_structure(const char *path, uint64_t size, nbrdf_error *err) {
  if (size == 0) return core_fail(err, NBRDF_ERR_FORMAT, "%s: is empty (0 bytes)", path);
  FILE *f = fopen(path, "rb");
  if (!f) return core_fail(err, NBRDF_ERR_IO, "%s: cannot open", path);
  unsigned char magic[8] = {0};
  size_t got = fread(magic, 1, 8, f);
  nbrdf_status st = NBRDF_OK;
  if (got == 8 && !memcmp(magic, "\x89PNG\r\n\x1a\n", 8))
    st = check_png(f, path, size, err);
  else if (got == 8 && !memcmp(magic, "\x76\x2f\x31\x01", 4))
    st = check_exr(f, path, size, le32(magic + 4), err);
  fclose(f);
  if (st == NBRDF_OK && got == 8 && !memcmp(magic, "\x76\x2f\x31\x01", 4))
    st = check_exr_core(path, err);
  return st;
}
