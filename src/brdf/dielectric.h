/* GGX rough dielectric interface (Walter et al. 2007): reflection and
 * transmission, exact Fresnel, from either side. Upper side = outside,
 * eta = η_inside / η_outside. eta == 1 is an invisible, index-matched
 * interface: a Dirac pass-through (eval and pdf are 0, sample returns
 * wi = −wo with weight 1 and BSDF_DELTA). */
#ifndef NBRDF_BRDF_DIELECTRIC_H
#define NBRDF_BRDF_DIELECTRIC_H

#include "brdf/bsdf.h"

/* Reflection: D G2 F / (4 |cos θo cos θi|) (Walter eq. 20).
 * Transmission: D G2 (1 − F) |wi·m| |wo·m| / (|cos θo cos θi| (wi·m + wo·m/η')²)
 * (Walter eq. 21 with η' = η_wi / η_wo), divided by η'² in radiance mode. */
double brdf_bsdf_dielectric_eval(const brdf_bsdf_dielectric *d, vec3 wo, vec3 wi,
                                 brdf_bsdf_mode mode);
/* Density of wi from brdf_bsdf_dielectric_sample(wo, ·, flags): VNDF of wo times the
 * Jacobian of the reflected (1 / 4|wo·m|) or refracted (|wi·m| / (wi·m + wo·m/η')²,
 * Walter eq. 17) direction, times the probability of choosing the lobe (R or
 * T over what `flags` allow). Independent of the transport mode. */
double brdf_bsdf_dielectric_pdf(const brdf_bsdf_dielectric *d, vec3 wo, vec3 wi, int flags);
/* Samples a visible normal of wo, then reflection or refraction by Fresnel
 * (restricted to `flags`). uc picks the lobe, (u1, u2) the normal. */
int brdf_bsdf_dielectric_sample(const brdf_bsdf_dielectric *d, vec3 wo, brdf_bsdf_mode mode,
                                int flags, double uc, double u1, double u2, brdf_bsdf_sample *s);
/* Transmission out of the coat for the layered walk's exit: returns
 * f(ws, wi) for ws inside (z < 0) and wi outside, and writes the density with
 * which brdf_bsdf_dielectric_sample(wi, ·, BSDF_TRANSMISSION) draws ws — the pdf of
 * the exit strategy, evaluated with one half vector and one Fresnel term. */
double brdf_bsdf_dielectric_exit(const brdf_bsdf_dielectric *d, vec3 ws, vec3 wi,
                                 brdf_bsdf_mode mode, double *pdf_from_wi);
/* The same, drawing its random numbers from rng (the lobe number only when
 * both lobes are allowed). */
int brdf_bsdf_dielectric_sample_rng(const brdf_bsdf_dielectric *d, vec3 wo, brdf_bsdf_mode mode,
                                    int flags, core_rng *rng, brdf_bsdf_sample *s);

#endif
