/* Colour conversion of colour data (R0 and A maps) to linear, through
 * OpenColorIO 2.1 behind a C interface.
 *
 * Colour space names, looked up in this order:
 *  1. the OCIO config at `config_path`, or at $OCIO when config_path is
 *     NULL: a colour space of that config (or a role, or an alias),
 *     converted to the config's scene_linear role;
 *  2. built in: "srgb" / "sRGB" (the IEC 61966-2-1 curve, as an OCIO
 *     ExponentWithLinearTransform, gamma 2.4, offset 0.055; OCIO 2.1 has no
 *     built-in configs) and "linear" / "raw" / "data" (no conversion).
 * Non-colour data (alpha, eta, sigma_t) never goes through here. */
#ifndef NBRDF_TEXTURE_OCIO_SHIM_H
#define NBRDF_TEXTURE_OCIO_SHIM_H

#include <stddef.h>

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct texture_colour_xform texture_colour_xform;

nbrdf_status texture_colour_xform_create(const char *colour_space, const char *config_path,
                                       texture_colour_xform **out, nbrdf_error *err);
/* 1 when the conversion does nothing ("linear", "raw"). */
int texture_colour_xform_is_identity(const texture_colour_xform *x);
/* "sRGB (built in) -> linear", "ACEScg (config.ocio) -> scene_linear", ... */
const char *texture_colour_xform_describe(const texture_colour_xform *x);
/* Converts n RGB triples in place. Safe from several threads at once. */
nbrdf_status texture_colour_xform_apply_rgb(const texture_colour_xform *x, float *rgb, size_t n,
                                            nbrdf_error *err);
/* Converts n grey values in place: each goes through as (v, v, v) (OCIO
 * refuses one-channel images) and the mean of the result comes back. */
nbrdf_status texture_colour_xform_apply_grey(const texture_colour_xform *x, float *v, size_t n,
                                             nbrdf_error *err);
void texture_colour_xform_free(texture_colour_xform *x);

#ifdef __cplusplus
}
#endif
#endif
