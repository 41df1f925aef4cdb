/* Layered ground truth of a bake's selected tuples (the accuracy levels):
 * each tuple is a two-layer BRDF (dielectric coat (alpha1, eta) over a slab
 * (albedo, sigma_t) over a conductor (alpha2, r0)) evaluated with the random
 * walk of src/brdf. Tuple k always uses random streams k of the seed's
 * family, so the values are the same for any thread count.
 *
 * - Fit samples: the data-set generator's directions (train/dataset.h:
 *   incident directions stratified over [0°, 89°), half the outgoing ones
 *   importance-sampled, so sharp lobes and grazing angles are covered).
 * - Held-out lobes: the lobe images of docs/METRICS.md (θi 0°, 30°, 60°,
 *   80°) and two grazing ones (85°, 89°, where renders of sharp and low-IOR
 *   coats go wrong first) at a smaller resolution, for the error estimate of
 *   nbrdf verify's metric. The truth is computed with ωi at azimuth 0; the
 *   networks are asked at a seeded azimuth per image (bake_lobe_azimuth),
 *   ωi and ωo rotated together, which the isotropic truth does not see but
 *   the decoder does (it is not rotation-invariant by construction). */
#ifndef NBRDF_BAKE_BAKE_TRUTH_H
#define NBRDF_BAKE_BAKE_TRUTH_H

#include <stddef.h>
#include <stdint.h>

#include "bake/bake_tuple.h"
#include "core/progress.h"
#include "train/samples.h"

#define BAKE_LOBE_N_THETA 6
extern const double bake_lobe_theta_deg[BAKE_LOBE_N_THETA];

typedef struct bake_truth_settings {
  int incident, outgoing, sampled, spp; /* fit samples per tuple (train/dataset.h) */
  int lobe_res, lobe_walks;             /* held-out lobe images */
  uint64_t seed;
  /* Stage "ground truth", done/total in tuples (fit and held-out together:
   * `done0` of `total` before this call). */
  core_ticker *ticker;
  double done0, total;
  volatile sig_atomic_t *cancel; /* may be NULL */
} bake_truth_settings;

/* The parameters of tuple t as a two-layer BRDF. */
void bake_tuple_params(const bake_tuple *t, train_params *p);

/* Appends the fit samples of n tuples to `out` (one BRDF each, in order). */
nbrdf_status bake_truth_samples(const bake_tuple *t, size_t n, const bake_truth_settings *s,
                                train_samples *out, nbrdf_error *err);

/* Lobe images of n tuples: images[(k * BAKE_LOBE_N_THETA + i) * res * res]
 * (f cos θo, 0 outside the disk). Streams differ from the fit samples'. */
nbrdf_status bake_truth_lobes(const bake_tuple *t, size_t n, const bake_truth_settings *s,
                              double *images, nbrdf_error *err);

/* The azimuth (radians, [0, 2π)) at which the networks see image i of
 * held-out tuple k: ωi and every ωo of the image rotated by it about the
 * normal. Seeded, the same for every level of one bake. */
double bake_lobe_azimuth(uint64_t seed, size_t k, int i);

/* ωo of lobe pixel (row, col) (docs/METRICS.md); 0 outside the disk. */
int bake_lobe_pixel_wo(int res, int row, int col, float wo[3]);

#endif
