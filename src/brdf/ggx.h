/* GGX / Trowbridge–Reitz microfacet distribution, isotropic, with roughness α
 * used directly (no remapping). Shading frame z-up; microfacet normals m are
 * always taken in the upper hemisphere, and directions may lie on either side
 * (a dielectric is seen from below by its flipped normals, so Λ uses |cos θ|).
 *
 * The one-line functions are inline because the layered random walk calls
 * them several times per vertex. */
#ifndef NBRDF_BRDF_GGX_H
#define NBRDF_BRDF_GGX_H

#include "core/vec3.h"

/* D(m) = α² / (π (α² cos²θm + sin²θm)²)   (Walter et al. 2007, eq. 33, with
 * the denominator multiplied through by α⁴ so that α → 0 loses no precision).
 * ∫ D(m) cos θm dm = 1 over the upper hemisphere. */
static inline double brdf_ggx_d(double alpha, vec3 m) {
  if (m.z <= 0.0) return 0.0;
  double a2 = alpha * alpha;
  double t = a2 * m.z * m.z + (m.x * m.x + m.y * m.y);
  if (t <= 0.0) return 0.0;
  return a2 / (M_PI * t * t);
}

/* Smith Λ(ω) = (√(1 + α² tan²θ) − 1) / 2 (Heitz 2014, eq. 72), written as
 * x / (2 (1 + √(1 + x))) with x = α² tan²θ so that small x keeps its digits.
 * Infinite for a direction in the surface plane. */
static inline double brdf_ggx_lambda(double alpha, vec3 w) {
  double z2 = w.z * w.z;
  double s2 = w.x * w.x + w.y * w.y;
  if (s2 <= 0.0) return 0.0;
  if (z2 <= 0.0) return INFINITY;
  double x = alpha * alpha * s2 / z2;
  return 0.5 * x / (1.0 + sqrt(1.0 + x));
}

/* Smith masking G1(ω) = 1 / (1 + Λ(ω)). */
static inline double brdf_ggx_g1(double alpha, vec3 w) {
  return 1.0 / (1.0 + brdf_ggx_lambda(alpha, w));
}

/* Height-correlated masking-shadowing G2(ωo, ωi) = 1 / (1 + Λ(ωo) + Λ(ωi))
 * (Heitz 2014, eq. 99). The same form is used for transmission, as pbrt-v4
 * does; Heitz's exact height-correlated transmission form would be the Beta
 * function B(1 + Λ(ωo), 1 + Λ(ωi)), which differs only where both directions
 * are grazing on a rough interface. */
static inline double brdf_ggx_g2(double alpha, vec3 wo, vec3 wi) {
  return 1.0 / (1.0 + brdf_ggx_lambda(alpha, wo) + brdf_ggx_lambda(alpha, wi));
}

/* Density of visible normals D_ω(m) = G1(ω) max(0, ω·m) D(m) / |cos θω|
 * (Heitz 2018, eq. 1), for ω on either side: seen from below, the visible
 * normals are those with ω·m < 0 (the surface's flipped microfacets). */
static inline double brdf_ggx_vndf_pdf(double alpha, vec3 w, vec3 m) {
  double wm = v3_dot(w, m);
  if (w.z < 0.0) wm = -wm;
  if (wm <= 0.0 || w.z == 0.0) return 0.0;
  return brdf_ggx_g1(alpha, w) * wm * brdf_ggx_d(alpha, m) / fabs(w.z);
}

/* Samples a visible normal m (upper hemisphere) for ω on either side, with
 * density brdf_ggx_vndf_pdf. The spherical-cap construction of Dupuy & Benyoub 2023
 * draws exactly Heitz 2018's distribution with fewer operations. Returns 0
 * when the draw degenerates to a normal in the surface plane (measure zero). */
int brdf_ggx_sample_vndf(double alpha, vec3 w, double u1, double u2, vec3 *m);

/* The same from a point (x, y) uniform in the unit disk, r2 = x² + y²: the
 * radius² gives the cap's height, the direction its azimuth (no sin/cos). */
int brdf_ggx_sample_vndf_disk(double alpha, vec3 w, double x, double y, double r2, vec3 *m);

#endif
