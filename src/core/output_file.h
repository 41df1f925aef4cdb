/* Every file nbrdf writes goes through here, so that the same guarantees hold
 * for textures, weights, bundles, checkpoints, logs, images and reports:
 *
 * - whole or absent: the bytes go to an unnamed file (Linux O_TMPFILE) in the
 *   destination's directory, linked and renamed into place only on commit; a
 *   crash or SIGKILL leaves nothing. Where the file system has no O_TMPFILE the
 *   temporary file is named ".<name>.<8 hex>.tmp" and held under flock(); a
 *   later output into the same directory removes such files of ours that are
 *   unlocked and older than the process by 2 s (what a killed writer left).
 * - a place that can take it: an output's folder must exist and be writable (on a
 *   read-only file system that is what is said) and its name fit NAME_MAX, checked by
 *   core_output_check before any work.
 * - never an input: a destination that is the same file (device and inode,
 *   so symlinks, "../" and hard links are caught) as one of the given inputs
 *   is refused, as is a directory.
 * - never a special file: an existing destination that is not a regular file
 *   (a FIFO, a device such as /dev/null, also through a symlink) is refused,
 *   since a rename would replace the node.
 * - read-only stays: an existing destination without write permission (mode
 *   bits checked too, as root ignores them) is refused, not replaced.
 * - an existing writable destination keeps its permission bits (and, where
 *   the process may, its owner and group).
 *
 * docs/RELIABILITY.md ("Outputs and signals") states this for users. */
#ifndef NBRDF_CORE_OUTPUT_FILE_H
#define NBRDF_CORE_OUTPUT_FILE_H

#include <stddef.h>

#include "nbrdf/status.h"

typedef struct core_output_file {
  char *path;         /* the destination */
  char *temp_path;    /* the named temporary file, or NULL for an unnamed (O_TMPFILE) one */
  char proc_path[32]; /* "/proc/self/fd/N" of an unnamed temporary file */
  int fd;             /* open for writing until commit or abort */
  int keep_mode;      /* the destination existed: its mode and owner are carried over */
} core_output_file;

/* core_output_file_open_flags: use a named temporary file even where O_TMPFILE works
 * (tests of the fallback). The environment variable NBRDF_OUTPUT_NAMED_TEMP=1 does the
 * same for a whole process (shell tests, diagnosis on unusual file systems). */
#define NBRDF_OUTPUT_NAMED_TEMP 1

/* Checks `path` as a destination without creating anything: refuses a directory,
 * a non-regular file, a read-only file, and one of the `n_inputs` paths (NULL
 * entries and paths that do not exist are skipped). A missing `path` is fine.
 * The message names the output and, when it is one, the input. */
nbrdf_status core_output_check(const char *path, const char *const *inputs, int n_inputs,
                               nbrdf_error *err);

/* Checks `path` (core_output_check) and creates the temporary file (mode 0666
 * less the umask, or the existing destination's). */
nbrdf_status core_output_file_open(core_output_file *f, const char *path, const char *const *inputs,
                                   int n_inputs, nbrdf_error *err);
nbrdf_status core_output_file_open_flags(core_output_file *f, const char *path,
                                         const char *const *inputs, int n_inputs, int flags,
                                         nbrdf_error *err);
/* A name by which another writer (OpenImageIO) can open the temporary file for
 * writing: "/proc/self/fd/N" or the named temporary file. `f->fd` stays open. */
const char *core_output_file_name(const core_output_file *f);
/* Writes `n` bytes at `offset` of the temporary file. */
nbrdf_status core_output_file_pwrite(core_output_file *f, const void *data, size_t n,
                                     long long offset, nbrdf_error *err);
/* Flushes the temporary file to disk and puts it in place of the destination
 * (checked again: it may have become a special file meanwhile). On failure the
 * temporary file is removed. Either way `f` is released. */
nbrdf_status core_output_file_commit(core_output_file *f, nbrdf_error *err);
/* The outputs of one command, all or none: every file is flushed and its destination
 * checked before the first is put in place; on any failure every temporary file is removed
 * (and a new file already placed, in the rare case of a later rename failing). Either way
 * every `files[i]` is released. */
nbrdf_status core_output_file_commit_all(core_output_file *files, int n, nbrdf_error *err);
/* Closes and removes the temporary file and releases `f`. Safe to call on a
 * file that was never opened, or already committed or aborted. */
void core_output_file_abort(core_output_file *f);

/* The whole of `data` as the file `path` (open, write, commit). */
nbrdf_status core_output_file_write_all(const char *path, const void *data, size_t n,
                                        const char *const *inputs, int n_inputs, nbrdf_error *err);

#endif
