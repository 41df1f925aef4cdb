/* Variance of reflected-radiance estimators under competing sampling
 * strategies (issue 5, the paper's Fig. 6): for a BRDF f and a fixed ωo,
 *
 *   L(ωo) = ∫ f(ωi, ωo) L_env(ωi) cos θi dωi ≈ (1/N) Σ f L_env cos θi / p(ωi),
 *
 * with ωi drawn by
 *   proxy   the Eq. 6 proxy (σ, w) of the latent (src/model/proxy.h), used
 *           with ωo as the given direction (the BRDF is reciprocal);
 *   cosine  cosine-weighted hemisphere;
 *   ggx     visible normals of the top layer's GGX (α1) seen from ωo,
 *           reflected about the microfacet normal;
 *   mix     one-sample MIS of proxy and cosine (balance heuristic, half each:
 *           the density is the mean of both).
 * A draw that lands at or below the horizon contributes 0 (the estimator stays
 * unbiased: the density reported is that of the valid draws).
 *
 * The variance is measured, not modelled: `reps` independent repetitions of
 * an N-sample estimate, for each N of a list (the first N of each
 * repetition's samples), their sample variance over the repetitions. */
#ifndef NBRDF_EVAL_RADIANCE_VARIANCE_H
#define NBRDF_EVAL_RADIANCE_VARIANCE_H

#include <stdint.h>

#include "core/vec3.h"
#include "lobe/lobe.h"

typedef enum bench_is_strategy {
  BENCH_IS_PROXY = 0,
  BENCH_IS_COSINE,
  BENCH_IS_GGX,
  BENCH_IS_MIX,
  BENCH_IS_COUNT
} bench_is_strategy;

/* What the strategies need to know about a BRDF. */
typedef struct bench_is_lobe {
  double sigma, w; /* proxy of Eq. 6 */
  double alpha1;   /* GGX roughness of the top layer */
} bench_is_lobe;

const char *bench_is_strategy_name(bench_is_strategy s);

/* Draws ωi for ωo (z > 0) from u ∈ [0, 1)³; returns its density per unit solid
 * angle, or 0 for a draw at or below the horizon (then *wi is unset). */
double bench_is_sample(bench_is_strategy s, const bench_is_lobe *lobe, vec3 wo, const double u[3],
                       vec3 *wi);
/* The density bench_is_sample draws ωi with (0 at or below the horizon). */
double bench_is_pdf(bench_is_strategy s, const bench_is_lobe *lobe, vec3 wo, vec3 wi);

/* Radiance arriving from ωi (shading frame, z up). */
typedef double (*bench_is_radiance_fn)(void *user, vec3 wi);

#define BENCH_IS_MAX_N 8

typedef struct bench_is_setup {
  lobe_fn brdf; /* f(ωi, ωo) without cosine, batched */
  void *brdf_user;
  bench_is_radiance_fn radiance;
  void *radiance_user;
  int reps;               /* independent repetitions (>= 2) */
  int n_counts;           /* entries of counts, 1..BENCH_IS_MAX_N */
  int counts[BENCH_IS_MAX_N]; /* samples per estimate; the largest sets the draws */
  uint64_t seed;
} bench_is_setup;

typedef struct bench_is_result {
  double mean[BENCH_IS_COUNT];                /* over all reps × max N samples */
  double var[BENCH_IS_COUNT][BENCH_IS_MAX_N]; /* of the N-sample estimate, per counts[k] */
  double lost[BENCH_IS_COUNT];                /* fraction of draws below the horizon */
  double radiance;                           /* inverse-variance weighted mean of the means */
} bench_is_result;

/* Runs every strategy for one BRDF and ωo; `stream` separates cases (each
 * strategy uses its own PCG32 stream derived from it). One call of the BRDF
 * callback per strategy with all valid draws. */
nbrdf_status bench_is_variance(const bench_is_setup *setup, const bench_is_lobe *lobe, vec3 wo,
                               uint64_t stream, bench_is_result *out, nbrdf_error *err);

#endif
