/* Linear scene radiance -> display-referred values through OpenColorIO, for
 * the renderer's PNG. With a config (the path given, else $OCIO) it is the
 * config's DisplayViewTransform from scene_linear to `display`/`view` (NULL:
 * the config's default display and its default view); without one, a
 * built-in sRGB display encoding (the IEC 61966-2-1 curve as OCIO's inverse
 * ExponentWithLinearTransform, gamma 2.4, offset 0.055). */
#ifndef NBRDF_EVAL_RENDER_VIEW_H
#define NBRDF_EVAL_RENDER_VIEW_H

#include <stddef.h>

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eval_view eval_view;

nbrdf_status eval_view_create(const char *config_path, const char *display, const char *view,
                              eval_view **out, nbrdf_error *err);
/* "sRGB (built in)", "sRGB / Film (config.ocio)", ... */
const char *eval_view_describe(const eval_view *v);
/* Converts n RGB triples in place (values are not clamped). */
nbrdf_status eval_view_apply(const eval_view *v, float *rgb, size_t n, nbrdf_error *err);
void eval_view_free(eval_view *v);

#ifdef __cplusplus
}
#endif
#endif
