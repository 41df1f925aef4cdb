#include "texture/exr_io.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"

static void on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  void *user = NULL;
  if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user) return;
  texture_exr_stream *s = user;
  snprintf(s->message, sizeof s->message, "%s", msg ? msg : exr_get_default_error_message(code));
}

/* A writing context reports errors from inside calls that hold its lock (exr_write_header
 * among them), and exr_get_user_data takes that lock: on_error deadlocked on the first failed
 * write (a full disk). write_fn records its own message instead; the library's other write
 * errors fall back to the message of their code. */
static void on_write_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
  (void)ctxt, (void)code, (void)msg;
}

static int64_t read_fn(exr_const_context_t ctxt, void *user, void *buffer, uint64_t sz,
                       uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  texture_exr_stream *s = user;
  if (s->mem) {
    uint64_t n = offset < s->mem_size ? s->mem_size - offset : 0;
    if (n > sz) n = sz;
    if (n) memcpy(buffer, s->mem + offset, n);
    return (int64_t)n;
  }
  uint64_t done = 0;
  while (done < sz) {
    ssize_t r = pread(s->fd, (char *)buffer + done, sz - done, (off_t)(offset + done));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) {
      error_cb(ctxt, EXR_ERR_READ_IO, "read failed: %s", strerror(errno));
      return -1;
    }
    if (r == 0) break; /* end of file: the library reports the short read */
    done += (uint64_t)r;
  }
  return (int64_t)done;
}

static int64_t size_fn(exr_const_context_t ctxt, void *user) {
  (void)ctxt;
  texture_exr_stream *s = user;
  if (s->mem) return (int64_t)s->mem_size;
  struct stat st;
  return fstat(s->fd, &st) == 0 ? (int64_t)st.st_size : -1;
}

static int64_t write_fn(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t sz,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
  texture_exr_stream *s = user;
  nbrdf_error e;
  if (core_output_file_pwrite(s->out, buffer, sz, (long long)offset, &e) != NBRDF_OK) {
    if (!s->message[0]) snprintf(s->message, sizeof s->message, "%.399s", e.message);
    error_cb(ctxt, EXR_ERR_WRITE_IO, "%s", e.message);
    return -1;
  }
  return (int64_t)sz;
}

exr_context_initializer_t texture_exr_initializer(texture_exr_stream *stream, int for_write) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = on_error;
  init.user_data = stream;
  if (for_write) {
    init.error_handler_fn = on_write_error;
    init.write_fn = write_fn;
  } else {
    init.read_fn = read_fn;
    init.size_fn = size_fn;
    /* Chunk-table reconstruction scans damaged files for chunks; a latent
     * texture with a damaged table is better refused with a clear error. */
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
  }
  /* A latent texture is at most 64k texels on a side; tiles at most 1024. */
  init.max_image_width = init.max_image_height = 65536;
  init.max_tile_width = init.max_tile_height = 1024;
  return init;
}

nbrdf_status texture_exr_fail(nbrdf_error *err, nbrdf_status status, const texture_exr_stream *s,
                              exr_result_t rv, const char *path, const char *what) {
  const char *msg = s && s->message[0] ? s->message : exr_get_default_error_message(rv);
  return core_fail(err, status, "%s: %s: %s", path, what, msg);
}

exr_compression_t texture_exr_compression(texture_latent_compression c) {
  switch (c) {
  case NBRDF_LATENT_ZIP:
    return EXR_COMPRESSION_ZIP;
  case NBRDF_LATENT_PIZ:
    return EXR_COMPRESSION_PIZ;
  case NBRDF_LATENT_ZIPS:
    return EXR_COMPRESSION_ZIPS;
  case NBRDF_LATENT_RLE:
    return EXR_COMPRESSION_RLE;
  case NBRDF_LATENT_NONE:
    return EXR_COMPRESSION_NONE;
  }
  return EXR_COMPRESSION_LAST_TYPE;
}

int texture_exr_compression_from(exr_compression_t c, texture_latent_compression *out) {
  switch (c) {
  case EXR_COMPRESSION_ZIP:
    *out = NBRDF_LATENT_ZIP;
    return 1;
  case EXR_COMPRESSION_PIZ:
    *out = NBRDF_LATENT_PIZ;
    return 1;
  case EXR_COMPRESSION_ZIPS:
    *out = NBRDF_LATENT_ZIPS;
    return 1;
  case EXR_COMPRESSION_RLE:
    *out = NBRDF_LATENT_RLE;
    return 1;
  case EXR_COMPRESSION_NONE:
    *out = NBRDF_LATENT_NONE;
    return 1;
  default:
    return 0;
  }
}

static const char *const compression_names[] = {"zip", "piz", "zips", "rle", "none"};

const char *texture_latent_compression_name(texture_latent_compression c) {
  return (unsigned)c < 5 ? compression_names[c] : "unknown";
}

int texture_latent_compression_parse(const char *name, texture_latent_compression *out) {
  for (int i = 0; name && i < 5; i++)
    if (strcmp(name, compression_names[i]) == 0) {
      *out = (texture_latent_compression)i;
      return 1;
    }
  return 0;
}

const char *texture_latent_storage_name(texture_latent_storage s) {
  return s == NBRDF_LATENT_FLOAT ? "float" : "half";
}
