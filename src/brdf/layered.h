/* The layered BSDF of Fan et al. 2022, Fig. 9: a rough dielectric top (α1, η)
 * over a homogeneous slab of unit thickness (optical depth σT, single-
 * scattering albedo A, isotropic phase) over any bottom BSDF of the library.
 *
 * Both estimators are position-free random walks in depth only (Guo et al.
 * 2018): the slab is laterally infinite and homogeneous, so a path is fully
 * described by its depth z ∈ [0, 1] (0 at the top) and direction. Throughput
 * is kept in double (long walks in bright media underflow in float), and
 * walks end by Russian roulette only — no depth cap, which would truncate
 * thick bright media. Reflects on its upper side only. */
#ifndef NBRDF_BRDF_LAYERED_H
#define NBRDF_BRDF_LAYERED_H

#include "brdf/bsdf.h"

/* One random walk's unbiased estimate of the light that enters through the
 * top and leaves towards wi: f(wo, wi) minus the top interface's own
 * reflection. Next-event estimation through the exit interface at every
 * medium and bottom vertex, combined by MIS with phase / bottom sampling. */
double brdf_bsdf_layered_walk(const brdf_bsdf_layered *l, vec3 wo, vec3 wi, brdf_bsdf_mode mode,
                              core_rng *rng);

/* Unbiased estimate of f(wo, wi): the top's reflection (exact) + one walk. */
double brdf_bsdf_layered_eval(const brdf_bsdf_layered *l, vec3 wo, vec3 wi, brdf_bsdf_mode mode,
                              core_rng *rng);

/* Stochastic sampling for renderers: a walk from wo that ends when it leaves
 * through the top (returns 1 with s->weight an unbiased estimate of
 * f |cos θi| / p) or is absorbed (returns 0). s->pdf is p̃ (bsdf.h). */
int brdf_bsdf_layered_sample(const brdf_bsdf_layered *l, vec3 wo, brdf_bsdf_mode mode,
                             core_rng *rng, brdf_bsdf_sample *s);

/* p̃(wo, wi): a deterministic stand-in for the sampler's density, for MIS
 * weights only (see bsdf.h). */
double brdf_bsdf_layered_pdf(const brdf_bsdf_layered *l, vec3 wo, vec3 wi);

#endif
