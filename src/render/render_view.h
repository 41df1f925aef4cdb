/* Linear scene radiance -> display-referred values through OpenColorIO, for
 * the renderer's PNG. With a config (the path given, else $OCIO) it is the
 * config's DisplayViewTransform from scene_linear to `display`/`view` (NULL:
 * the config's default display and its default view); without one, a
 * built-in sRGB display encoding (the IEC 61966-2-1 curve as OCIO's inverse
 * ExponentWithLinearTransform, gamma 2.4, offset 0.055). */
#ifndef NBRDF_RENDER_RENDER_VIEW_H
#define NBRDF_RENDER_RENDER_VIEW_H

#include <stddef.h>

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct render_view render_view;

nbrdf_status render_view_create(const char *config_path, const char *display, const char *view,
                                render_view **out, nbrdf_error *err);
/* "sRGB (built in)", "sRGB / Film (config.ocio)", ... */
const char *render_view_describe(const render_view *v);
/* Converts n RGB triples in place (values are not clamped). */
nbrdf_status render_view_apply(const render_view *v, float *rgb, size_t n, nbrdf_error *err);
void render_view_free(render_view *v);

#ifdef __cplusplus
}
#endif
#endif
