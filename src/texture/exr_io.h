/* Glue between OpenEXRCore and nbrdf shared by the latent texture reader and
 * writer: file streams on our own descriptors (so that we, not the library,
 * decide where temporary files go and when they vanish), error messages
 * captured per handle, and compression names. */
#ifndef NBRDF_TEXTURE_EXR_IO_H
#define NBRDF_TEXTURE_EXR_IO_H

#include <openexr.h>

#include "core/output_file.h"
#include "nbrdf/status.h"
#include "texture/latent_exr.h"

/* The user data of every context we create. */
typedef struct texture_exr_stream {
  int fd;                 /* reading: the file; -1 when writing or reading memory */
  const unsigned char *mem; /* reading memory (fd = -1): mem_size bytes */
  uint64_t mem_size;
  core_output_file *out;  /* writing: the temporary file */
  char message[400];      /* the library's last error message */
} texture_exr_stream;

/* An initializer wired to `stream` (pread/pwrite, error capture, size
 * limits that keep a corrupted header from asking for absurd allocations). */
exr_context_initializer_t texture_exr_initializer(texture_exr_stream *stream, int for_write);

/* Fails with "<path>: <what>: <library message>". */
nbrdf_status texture_exr_fail(nbrdf_error *err, nbrdf_status status, const texture_exr_stream *s,
                              exr_result_t rv, const char *path, const char *what);

exr_compression_t texture_exr_compression(texture_latent_compression c);
/* Maps back; returns 0 for a compression that is not lossless. */
int texture_exr_compression_from(exr_compression_t c, texture_latent_compression *out);

#endif
