/* Writing 8-bit RGB images as PNG for people to look at (lobe images, plots),
 * through OpenImageIO behind this C header (png_write_shim.cpp). */
#ifndef NBRDF_LOBE_PNG_WRITE_H
#define NBRDF_LOBE_PNG_WRITE_H

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#include "core/output_file.h" /* C linkage for the C++ shim too */

/* Writes width×height pixels of 3 bytes (R, G, B), rows top to bottom, to
 * `path` as PNG. The file is written under a temporary name next to `path`
 * and renamed, so a failure never leaves a half-written image behind. */
nbrdf_status lobe_png_write_rgb8(const char *path, int width, int height, const unsigned char *rgb,
                                 nbrdf_error *err);
/* The same into the open temporary file `f`, which the caller commits (with a command's
 * other outputs: core_output_file_commit_all) or aborts. */
nbrdf_status lobe_png_write_rgb8_to(core_output_file *f, int width, int height,
                                    const unsigned char *rgb, nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
