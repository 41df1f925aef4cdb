/* The renderer's environment light: procedural sky, a constant (furnace) or
 * a lat-long image, all importance-sampled the same way: a piecewise-
 * constant distribution over a lat-long table of luminance × sin θ (with a
 * floor, so every direction has a positive density). The table only shapes
 * the sampling; radiance is always evaluated from the source itself.
 *
 * Lat-long mapping (world y up): θ = acos(d.y), φ = atan2(d.x, −d.z);
 * s = φ / 2π + 0.5 (image column / width), t = θ / π (image row / height),
 * so the image's centre column looks at −z and its top row is the zenith. */
#ifndef NBRDF_RENDER_ENV_H
#define NBRDF_RENDER_ENV_H

#include "core/vec3.h"
#include "nbrdf/render.h"

typedef struct render_env render_env;

/* From the options' env, env_path, env_value and env_scale. */
nbrdf_status render_env_create(const nbrdf_render_options *opts, render_env **out,
                               nbrdf_error *err);
void render_env_free(render_env *env);

/* Radiance arriving from direction d (unit, pointing away from the scene). */
void render_env_radiance(const render_env *env, vec3 d, double rgb[3]);
/* Draws a direction from (u1, u2) ∈ [0, 1)²; returns its density per unit
 * solid angle (0: no sample, at a pole). */
double render_env_sample(const render_env *env, double u1, double u2, vec3 *d);
/* The density render_env_sample draws d with. */
double render_env_pdf(const render_env *env, vec3 d);

#endif
