/* Writing 8-bit RGB images as PNG for people to look at (lobe images, plots),
 * through OpenImageIO behind this C header (png_write_shim.cpp). */
#ifndef NBRDF_LOBE_PNG_WRITE_H
#define NBRDF_LOBE_PNG_WRITE_H

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Writes width×height pixels of 3 bytes (R, G, B), rows top to bottom, to
 * `path` as PNG. The file is written under a temporary name next to `path`
 * and renamed, so a failure never leaves a half-written image behind. */
nbrdf_status lobe_png_write_rgb8(const char *path, int width, int height, const unsigned char *rgb,
                                 nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
