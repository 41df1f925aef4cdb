/* GGX rough conductor with Schlick Fresnel (DESIGN.md "Physical conventions").
 * A BRDF of its upper side: every function returns 0 / fails when wo or wi is
 * not strictly above the surface. */
#ifndef NBRDF_BRDF_CONDUCTOR_H
#define NBRDF_BRDF_CONDUCTOR_H

#include "brdf/bsdf.h"

/* f = D(h) G2(wo, wi) F(wo·h) / (4 cos θo cos θi), h = (wo + wi)/|wo + wi|
 * (Walter et al. 2007, eq. 20). */
double brdf_bsdf_conductor_eval(const brdf_bsdf_conductor *c, vec3 wo, vec3 wi);
/* Visible-normal sampling: p(wi) = D_wo(h) / (4 wo·h) = G1(wo) D(h) / (4 cos θo). */
double brdf_bsdf_conductor_pdf(const brdf_bsdf_conductor *c, vec3 wo, vec3 wi);
/* Both at once (one half vector and one D). */
double brdf_bsdf_conductor_eval_pdf(const brdf_bsdf_conductor *c, vec3 wo, vec3 wi, double *pdf);
/* weight = F G2 / G1(wo) ≤ 1. */
int brdf_bsdf_conductor_sample(const brdf_bsdf_conductor *c, vec3 wo, double u1, double u2,
                               brdf_bsdf_sample *s);
int brdf_bsdf_conductor_sample_rng(const brdf_bsdf_conductor *c, vec3 wo, core_rng *rng,
                                   brdf_bsdf_sample *s);

#endif
