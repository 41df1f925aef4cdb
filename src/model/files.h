/* Small file helpers of the bundle code: whole-file reads, atomic text writes. */
#ifndef NBRDF_MODEL_FILES_H
#define NBRDF_MODEL_FILES_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/status.h"

/* Reads a whole regular file of at most max_bytes (and 2 GiB) into a malloc'd
 * buffer with a NUL after its last byte; messages start with the path. */
nbrdf_status model_read_file(const char *path, uint64_t max_bytes, char **bytes, size_t *size,
                             nbrdf_error *err);

/* model.json is a page of text; anything much larger is not one. */
#define MODEL_JSON_MAX ((uint64_t)16 << 20)

/* Writes `text` to dir/file through a temporary file in dir, synced, then renamed. */
nbrdf_status model_write_text_file(const char *dir, const char *file, const char *text,
                                   nbrdf_error *err);

/* Creates a folder and its missing parents (mode 0777 before umask). */
nbrdf_status model_make_dirs(const char *dir, nbrdf_error *err);

#endif
