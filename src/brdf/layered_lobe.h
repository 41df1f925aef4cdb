/* Whole-lobe estimation of a layered BRDF: for a fixed ωi, every random walk
 * contributes to f(ωi, ωo_k) for all k at once (next-event estimation and
 * the exit terms are evaluated towards every ωo_k at every vertex), which
 * amortises the walk itself over thousands of lobe pixels (docs/METRICS.md, "Noise
 * of the ground truth itself"). Same estimator as brdf_bsdf_layered_walk, started
 * from ωi (the BRDF is reciprocal), so the results are unbiased with the same
 * expectation as per-query evaluation; the pixels of one image are correlated
 * (they share walks), which a lobe error averages over. */
#ifndef NBRDF_BRDF_LAYERED_LOBE_H
#define NBRDF_BRDF_LAYERED_LOBE_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "brdf/bsdf.h"

/* f[k] ≈ f(wi, wo[k]) (no cosine) from `walks` walks, with the standard error
 * of the mean in f_se[k] (may be NULL; +Inf when walks = 1). Walk j uses
 * random stream j of `seed`; the result is the same for any `threads`
 * (0 = all). wi and wo[k] must be unit vectors with z > 0. Returns 0 when out
 * of memory. Cost per walk grows with n (each vertex evaluates the bottom
 * BSDF towards every ωo_k: with a layered bottom, one nested walk each). */
int brdf_layered_lobe_eval(const brdf_bsdf_layered *l, vec3 wi, size_t n, const vec3 *wo, int walks,
                           uint64_t seed, int threads, double *f, double *f_se);

/* The lobe image of docs/METRICS.md with src/lobe/lobe.h's pixel convention:
 * res×res, row 0 at the top, pixel (row, col) centred at
 * x = −1 + (col + ½)·2/res, y = 1 − (row + ½)·2/res, ωo = (x, y, √(1 − x² − y²)),
 * ωi = (sin θi, 0, cos θi); value f(ωi, ωo) cos θo, 0 outside the disk. */
int brdf_layered_lobe_image(const brdf_bsdf_layered *l, double theta_i, int res, int walks,
                            uint64_t seed, int threads, double *image, double *image_se);
/* Cancel and progress for long lobe images (a 64x64 image of 256 walks
 * takes up to seconds on a loaded machine): the walks stop once *stop (may
 * be NULL) becomes non-zero, and tick (may be NULL) is called on the
 * calling thread between chunks of walks; a non-zero return stops too. */
typedef struct brdf_layered_lobe_hook {
  const volatile sig_atomic_t *stop;
  int (*tick)(void *user);
  void *user;
} brdf_layered_lobe_hook;

/* brdf_layered_lobe_eval under a hook (may be NULL): returns -1 when stopped, the
 * values then undefined. */
int brdf_layered_lobe_eval_hooked(const brdf_bsdf_layered *l, vec3 wi, size_t n, const vec3 *wo,
                                  int walks, uint64_t seed, int threads,
                                  const brdf_layered_lobe_hook *hook, double *f, double *f_se);

/* brdf_layered_lobe_image under a hook (may be NULL): returns -1 when stopped,
 * the image then undefined. */
int brdf_layered_lobe_image_hooked(const brdf_bsdf_layered *l, double theta_i, int res, int walks,
                                   uint64_t seed, int threads, const brdf_layered_lobe_hook *hook,
                                   double *image, double *image_se);

#endif
