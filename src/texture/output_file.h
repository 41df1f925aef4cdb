/* An output written to a temporary file beside its destination and renamed
 * into place only when complete, so that a failed or cancelled write never
 * leaves a half-written file and never replaces a good one. */
#ifndef NBRDF_TEXTURE_OUTPUT_FILE_H
#define NBRDF_TEXTURE_OUTPUT_FILE_H

#include <stddef.h>

#include "nbrdf/status.h"

typedef struct nbrdf_output_file {
  char *path;      /* the destination */
  char *temp_path; /* ".<name>.<random>.tmp" in the destination's directory */
  int fd;          /* open for writing; a writer that reopens the temporary file by its
                      name (OpenImageIO) closes it and sets -1 */
} nbrdf_output_file;

/* Creates the temporary file (mode 0666 less the umask). Refuses a
 * destination that is a directory, or that is the same file as one of the
 * `n_inputs` paths (compared by device and inode, so links and relative
 * paths are caught). */
nbrdf_status nbrdf_output_file_open(nbrdf_output_file *f, const char *path,
                                    const char *const *inputs, int n_inputs, nbrdf_error *err);
/* Writes `n` bytes at `offset` of the temporary file. */
nbrdf_status nbrdf_output_file_pwrite(nbrdf_output_file *f, const void *data, size_t n,
                                      long long offset, nbrdf_error *err);
/* Flushes the temporary file to disk (when fd is still open) and renames it over the destination.
 * On failure the temporary file is removed. Either way `f` is released. */
nbrdf_status nbrdf_output_file_commit(nbrdf_output_file *f, nbrdf_error *err);
/* Closes and removes the temporary file and releases `f`. Safe to call on a
 * file that was never opened, or already committed or aborted. */
void nbrdf_output_file_abort(nbrdf_output_file *f);

#endif
