/* Lobe images as a PNG for people to look at: one row per θi, with columns
 * reference | approximation | difference. */
#ifndef NBRDF_LOBE_LOBE_PNG_H
#define NBRDF_LOBE_LOBE_PNG_H

#include "nbrdf/status.h"

/* `ref` and `approx` hold n_images lobe images of res×res (lobe/lobe.h layout);
 * `approx` may be NULL for a single column. Each row is scaled by the maximum
 * of its reference image and shown with a gamma of 1/2.2 in the viridis colour
 * map; the difference approx − ref uses the same scale, red where the
 * approximation is higher, blue where it is lower. Pixels are magnified
 * `zoom` times (1..16). */
nbrdf_status lobe_write_png(const char *path, int res, int n_images, const double *ref,
                            const double *approx, int zoom, nbrdf_error *err);

#endif
