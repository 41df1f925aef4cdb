/* Measures the energy audit's slopes for a bundle's own weights (`nbrdf bundle
 * audit-slopes`, docs/BAKE.md "Slopes"): how far the audit's value (the largest
 * decoded albedo over its angles, bake_albedo_precise) moves per unit of each
 * normalised parameter, per region of (alpha1, alpha2) and direction. Base
 * tuples are drawn over the whole range, stratified over the regions, and from the clearcoat
 * family (alpha1 at the range's low end, eta 1.45, albedo 0.8, sigma_t 1; alpha2
 * and r0 drawn); from each base, steps of 1/32 to 1/4 along every parameter.
 * A step that changes the audit's value by Δ over Δu needs the slope
 * (Δ - BAKE_AUDIT_NOISE) / |Δu| in its own direction and (-Δ - BAKE_AUDIT_NOISE)
 * / |Δu| in the other, in every region it spans; a region's entry is its largest
 * need times 1.5, at least a third of the parameter's largest in that direction
 * over all regions and at least 0.25 (64 bases a region
 * miss steeper spots: with 1.25 and no floor a cell member of another draw
 * exceeded its bound); a region no step reached gets the parameter's largest.
 * Deterministic by seed (up to the BLAS's rounding). */
#ifndef NBRDF_BAKE_AUDIT_SLOPES_H
#define NBRDF_BAKE_AUDIT_SLOPES_H

#include <stddef.h>
#include <stdint.h>

#include "bake/bake_audit.h"
#include "bake/bake_tuple.h"

typedef struct bake_audit_slopes_options {
  int bases;       /* over the whole range (4096: 64 a region) */
  int sharp_bases; /* of the clearcoat family (256) */
  uint64_t seed;   /* 11 */
  nbrdf_progress_fn progress; /* stage "audit slopes", done/total bases; nonzero: cancel */
  void *user;
} bake_audit_slopes_options;

#define BAKE_AUDIT_SLOPES_OPTIONS_DEFAULT {4096, 256, 11, NULL, NULL}

/* Steps per base along each parameter: 1/32, 1/16, 1/8, 1/4. */
#define BAKE_AUDIT_SLOPES_STEPS 4

/* What the measurement saw, for the bench that checks it (bench_audit_margin.c):
 * per base, `per` tuples (the base, BAKE_AUDIT_SLOPES_STEPS steps along each
 * parameter, one random member of the base's audit cell), bases first over the
 * whole range then of the clearcoat family. */
typedef struct bake_audit_slopes_draws {
  size_t n_bases, n_sharp; /* the first n_bases - n_sharp are whole-range ones */
  int per;
  bake_tuple *t; /* [n_bases · per] */
  double *u;     /* their normalised parameters [n_bases · per × 6] */
  double *value; /* the audit's value of each */
  float *lat;    /* their latents [n_bases · per × D] */
  float *sigma;  /* their proxies' sigma */
  double need[NBRDF_BAKE_PARAM_COUNT]; /* the largest need of each parameter, either way */
  size_t need_at[NBRDF_BAKE_PARAM_COUNT], need_step[NBRDF_BAKE_PARAM_COUNT]; /* its pair */
} bake_audit_slopes_draws;

/* Measures the table [BAKE_AUDIT_REGIONS][BAKE_AUDIT_REGIONS][6][BAKE_AUDIT_DIRS]
 * into `table`;
 * `draws` (may be NULL) receives what was measured (free with
 * bake_audit_slopes_draws_free). */
nbrdf_status bake_audit_slopes_measure(const nbrdf_model *model,
                                       const bake_audit_slopes_options *o, double *table,
                                       bake_audit_slopes_draws *draws, nbrdf_error *err);

void bake_audit_slopes_draws_free(bake_audit_slopes_draws *d);

#endif
