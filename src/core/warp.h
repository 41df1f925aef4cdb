/* Warps from the unit square to directions, each with its density (solid angle). */
#ifndef NBRDF_CORE_WARP_H
#define NBRDF_CORE_WARP_H

#include "core/vec3.h"

/* Concentric map of the square onto the unit disk (Shirley & Chiu 1997). */
void core_warp_disk(double u1, double u2, double *x, double *y);
/* Cosine-weighted upper hemisphere; pdf = cos θ / π. */
vec3 core_warp_cosine_hemisphere(double u1, double u2);
double core_warp_cosine_hemisphere_pdf(vec3 w);
/* Uniform sphere; pdf = 1 / 4π. */
vec3 core_warp_uniform_sphere(double u1, double u2);
/* Uniform upper hemisphere; pdf = 1 / 2π. */
vec3 core_warp_uniform_hemisphere(double u1, double u2);

#endif
