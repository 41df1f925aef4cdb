/* Physical ground truth: analytic GGX rough conductor and dielectric, and the
 * layered BRDF of Fan et al. 2022 (Fig. 9) by an unbiased position-free Monte
 * Carlo random walk (Guo et al. 2018).
 *
 * Conventions (docs/ARCHITECTURE.md, "Physical conventions"):
 * - shading frame z-up; directions are unit vectors pointing away from the
 *   surface; BRDF queries take ωi and ωo on the upper hemisphere (z > 0);
 * - values are f(ωi, ωo) WITHOUT the cosine factor, per colour channel;
 * - GGX roughness α is used directly (no remapping), height-correlated Smith
 *   masking-shadowing, Schlick Fresnel for conductors, exact unpolarised
 *   Fresnel for dielectrics; η is the coat's IOR relative to the outside.
 *
 * Handles are immutable after creation and may be used from several threads
 * at once. Stochastic evaluations are deterministic for a given seed whatever
 * the number of threads: query k of a batch always uses random stream k.
 *
 * The layered BRDF of model.h's example, estimated with 1024 random walks:
 * Example (tests/docs compiles it):
 *   nbrdf_error err;
 *   nbrdf_brdf *bottom = NULL, *coated = NULL;
 *   nbrdf_query q = {{0.0, 0.0, 1.0}, {0.6, 0.0, 0.8}};
 *   nbrdf_eval_options opts = NBRDF_EVAL_OPTIONS_DEFAULT;
 *   double f, f_stderr;
 *   nbrdf_status st = nbrdf_brdf_create_conductor(0.3, 0.9, &bottom, &err);
 *   if (st == NBRDF_OK) st = nbrdf_brdf_create_layered(0.2, 1.5, 0.8, 1.0, bottom, &coated, &err);
 *   if (st == NBRDF_OK) st = nbrdf_brdf_eval(coated, 1, &q, &opts, &f, &f_stderr, &err);
 *   if (st != NBRDF_OK) fprintf(stderr, "brdf: %s\n", err.message);
 *   nbrdf_brdf_destroy(coated);
 *   nbrdf_brdf_destroy(bottom);
 */
#ifndef NBRDF_BRDF_H
#define NBRDF_BRDF_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct nbrdf_brdf nbrdf_brdf;

/* Ranges the ground truth accepts (wider than the networks' trained ranges;
 * anything else — NaN, Inf, out of range — fails with NBRDF_ERR_ARGUMENT and a
 * message naming the parameter). */
#define NBRDF_GT_ALPHA_MIN 1e-3
#define NBRDF_GT_ALPHA_MAX 1.0
#define NBRDF_GT_ETA_MIN 1.0 /* η = 1 is an index-matched (invisible) interface */
#define NBRDF_GT_ETA_MAX 4.0
#define NBRDF_GT_SIGMA_T_MAX 1000.0

/* Rough conductor: GGX(α) with Schlick Fresnel F = R0 + (1 − R0)(1 − cos θd)^5.
 * α ∈ [1e-3, 1], R0 ∈ [0, 1]. */
nbrdf_status nbrdf_brdf_create_conductor(double alpha, double r0, nbrdf_brdf **out,
                                         nbrdf_error *err);

/* Rough dielectric interface seen from above (Walter et al. 2007): as a BRDF
 * query, its reflection lobe only. α ∈ [1e-3, 1], η ∈ [1, 4]. */
nbrdf_status nbrdf_brdf_create_dielectric(double alpha, double eta, nbrdf_brdf **out,
                                          nbrdf_error *err);

/* Layered BRDF: rough dielectric top (α1, η) over a homogeneous slab of unit
 * thickness, optical depth σT ∈ [0, 1000], single-scattering albedo A ∈ [0, 1],
 * isotropic phase function, over `bottom` (any BRDF of this library, layered
 * ones included: 3 layers and more by nesting). The new handle keeps its own
 * copy of `bottom`; the caller may destroy `bottom` afterwards. */
nbrdf_status nbrdf_brdf_create_layered(double alpha1, double eta, double albedo,
                                       double sigma_t, const nbrdf_brdf *bottom,
                                       nbrdf_brdf **out, nbrdf_error *err);

void nbrdf_brdf_destroy(nbrdf_brdf *brdf);

/* True when evaluation is a Monte Carlo estimate (layered BRDFs). */
int nbrdf_brdf_is_stochastic(const nbrdf_brdf *brdf);

/* A direction pair; both unit vectors with z > 0 (z ≤ 0 is rejected). */
typedef struct nbrdf_query {
  double wi[3];
  double wo[3];
} nbrdf_query;

typedef struct nbrdf_eval_options {
  uint64_t seed;   /* stochastic BRDFs: base seed; query k uses stream k */
  int spp;         /* random walks per query for stochastic BRDFs (>= 1) */
  int threads;     /* 0 = all available cores (OpenMP) */
} nbrdf_eval_options;

#define NBRDF_EVAL_OPTIONS_DEFAULT {0u, 1024, 0}

/* Evaluates query k with brdfs[k] for k < n (the same handle may repeat).
 * f[k] is f(ωi, ωo) without cosine; f_stderr (may be NULL) receives the
 * standard error of the mean over the spp walks (0 for analytic BRDFs;
 * +Inf when spp = 1, since one walk cannot estimate its own spread).
 * `options` may be NULL (NBRDF_EVAL_OPTIONS_DEFAULT). Every query is checked
 * before any is evaluated; a bad one fails naming its index ("query 3: wi
 * ... has z <= 0"). A dielectric evaluates its reflection lobe only. */
nbrdf_status nbrdf_brdf_eval_many(size_t n, const nbrdf_brdf *const *brdfs,
                                  const nbrdf_query *queries,
                                  const nbrdf_eval_options *options, double *f,
                                  double *f_stderr, nbrdf_error *err);

/* The same for one BRDF and n queries. */
nbrdf_status nbrdf_brdf_eval(const nbrdf_brdf *brdf, size_t n, const nbrdf_query *queries,
                             const nbrdf_eval_options *options, double *f, double *f_stderr,
                             nbrdf_error *err);

/* Importance sampling for renderers: draws ωo for ωi (z > 0) with the random
 * stream (seed, index) and returns `weight`, an unbiased estimate of
 * f(ωi, ωo) cos θo / p(ωo), so that E[weight · g(ωo)] = ∫ f g cos θo dωo.
 * A path that leaves no outgoing direction (absorbed) returns weight 0 and
 * ωo = (0, 0, 1). */
nbrdf_status nbrdf_brdf_sample(const nbrdf_brdf *brdf, const double wi[3], uint64_t seed,
                               uint64_t index, double wo[3], double *weight, nbrdf_error *err);

/* Directional albedo ρ(θi) = ∫ f(ωi, ωo) cos θo dωo estimated with `samples`
 * draws of nbrdf_brdf_sample (θi in radians), with its standard error. */
nbrdf_status nbrdf_brdf_albedo(const nbrdf_brdf *brdf, double theta_i, int samples,
                               uint64_t seed, double *rho, double *rho_stderr, nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
