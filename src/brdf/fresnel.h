/* Fresnel reflectance: Schlick's approximation for the conductor, the exact
 * unpolarised dielectric formula for the coat. */
#ifndef NBRDF_BRDF_FRESNEL_H
#define NBRDF_BRDF_FRESNEL_H

#include "core/vec3.h"

/* F = R0 + (1 − R0)(1 − cos θd)^5 (Schlick 1994); cos θd is clamped to [0, 1]. */
static inline double brdf_fresnel_schlick(double r0, double cos_d) {
  double c = 1.0 - fmin(1.0, fmax(0.0, cos_d));
  double c2 = c * c;
  return r0 + (1.0 - r0) * (c2 * c2 * c);
}

/* Exact unpolarised Fresnel reflectance of a smooth interface with relative
 * IOR η = η_inside / η_outside (pbrt-v4 §9.3.5). cos_i > 0: light arrives from
 * the outside (upper) side; cos_i < 0: from the inside, i.e. with 1/η, where
 * beyond the critical angle it is totally reflected (returns 1). */
double brdf_fresnel_dielectric(double cos_i, double eta);

/* Refraction of ω (pointing away from the surface, either side) through the
 * microfacet normal m (upper hemisphere) of an interface with relative IOR
 * η (inside over outside). Writes the refracted direction (on the other side
 * of m) and etap = η_transmitted / η_incident; returns 0 on total internal
 * reflection. (pbrt-v4, eq. 9.19 form.) */
int brdf_fresnel_refract(vec3 w, vec3 m, double eta, vec3 *wt, double *etap);

/* Mirror reflection of ω about m. */
static inline vec3 brdf_fresnel_reflect(vec3 w, vec3 m) {
  return v3_sub(v3_scale(m, 2.0 * v3_dot(w, m)), w);
}

#endif
