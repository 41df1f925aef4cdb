/* A walk over the structure of PNG and OpenEXR files before OpenImageIO
 * opens them: libpng and OpenEXR's C++ header reader allocate whatever a
 * chunk or attribute claims (fuzz_param_map found 200-byte files that make
 * them ask for 1 to 2 GB) before finding the file too short. Here every
 * chunk or header attribute must fit in the file; BMP headers must describe a
 * valid file (OpenImageIO's reader trusts them). Other formats pass unchecked. */
#ifndef NBRDF_TEXTURE_IMAGE_CHECK_H
#define NBRDF_TEXTURE_IMAGE_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* `size`: the file's size in bytes (from stat). Messages name the file. */
nbrdf_status texture_image_check_structure(const char *path, uint64_t size, nbrdf_error *err);

/* The same walk over `size` bytes at `data`; `label` names them in messages. */
nbrdf_status texture_image_check_memory(const char *label, const void *data, size_t size,
                                        nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
