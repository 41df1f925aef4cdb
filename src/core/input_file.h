/* Opening files that a command reads: only regular files, and no larger than
 * a bound checked before anything is allocated. A FIFO or a device given as
 * a map, a texture or a bundle file would block the open, or never end, or
 * make a reader allocate what the device claims; a directory would fail
 * later with a misleading format message. Messages name the file and say
 * what it is ("maps/a.png: is a directory, not a file"). */
#ifndef NBRDF_CORE_INPUT_FILE_H
#define NBRDF_CORE_INPUT_FILE_H

#include <stdint.h>

#include "nbrdf/status.h"

/* No size bound beyond what the reader itself checks. */
#define NBRDF_INPUT_ANY_SIZE UINT64_MAX

/* Opens `path` for reading (O_CLOEXEC, blocking reads), refusing anything
 * but a regular file (symlinks followed) and files of more than max_bytes.
 * A FIFO is opened without blocking, so that the refusal is immediate.
 * Sets *fd and *size (either may be NULL: a NULL fd closes the file). */
nbrdf_status core_input_open(const char *path, uint64_t max_bytes, int *fd, uint64_t *size,
                             nbrdf_error *err);

/* For an input read once, from start to end, and never sought or re-read (the
 * CSV of `eval --in`): a regular file as above, or a FIFO or pipe (`--in
 * <(cmd)`, a named FIFO), which is opened blocking: like `cat`, it waits for a
 * writer. Directories and devices stay refused (a device never ends). Inputs
 * that are sought, re-read, sized before reading or opened by a library by name
 * (maps, textures, bundle files, data sets) keep core_input_open. */
nbrdf_status core_input_open_stream(const char *path, int *fd, nbrdf_error *err);

/* The same refusals for readers that open the file by name themselves
 * (OpenImageIO): stat(2) only, nothing is opened. */
nbrdf_status core_input_check(const char *path, uint64_t max_bytes, uint64_t *size,
                              nbrdf_error *err);

#endif
