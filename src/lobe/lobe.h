/* Lobe images and the accuracy metrics of docs/METRICS.md, shared by the ground-truth
 * benchmark, `nbrdf verify` and `nbrdf evaluate`.
 *
 * A lobe image of a single-channel BRDF f at incidence θi (φi = 0) is a res×res
 * image over the projected unit disk: pixel (row, col) has its centre at
 *   x = −1 + (col + ½)·2/res,   y = 1 − (row + ½)·2/res   (row 0 at the top, +y up),
 * and, where x² + y² < 1, holds f(ωi, ωo)·cos θo with ωo = (x, y, √(1 − x² − y²))
 * and ωi = (sin θi, 0, cos θi); pixels outside the disk hold 0. This is the
 * outgoing-radiance plot of the paper's Figs. 10, 11 and 15: the mirror
 * direction of ωi lies at x = −sin θi, left of the centre. Images are stored
 * row-major, one after the other (image t starts at t·res·res). */
#ifndef NBRDF_LOBE_LOBE_H
#define NBRDF_LOBE_LOBE_H

#include <stddef.h>

#include "nbrdf/brdf.h"
#include "nbrdf/status.h"

/* The standard set of docs/METRICS.md: 64×64 images at θi ∈ {0°, 30°, 60°, 80°}. */
#define NBRDF_LOBE_RES 64
#define NBRDF_LOBE_N_THETA 4
extern const double lobe_theta_deg[NBRDF_LOBE_N_THETA];

/* A BRDF as a batched callback: f[k] = f(queries[k].wi, queries[k].wo) for
 * k < n, without the cosine factor. Called once per lobe_images() with
 * every pixel of every image, so a network or the Monte Carlo estimator sees
 * one large batch. Must fill every f[k] with a finite value or fail. */
typedef nbrdf_status (*lobe_fn)(void *user, size_t n, const nbrdf_query *queries, double *f,
                                nbrdf_error *err);

/* Direction ωo of pixel (row, col); returns 0 (and leaves wo alone) outside
 * the disk. */
int lobe_pixel_wo(int res, int row, int col, double wo[3]);

/* Number of pixel centres inside the disk, i.e. queries per image. */
size_t lobe_pixels_inside(int res);

/* Fills n_theta images of res×res doubles (images[t·res·res + row·res + col])
 * for θi = theta_deg[t] (degrees, in [0, 90)). One call of `fn` for all of them. */
nbrdf_status lobe_images(lobe_fn fn, void *user, int res, int n_theta, const double *theta_deg,
                         double *images, nbrdf_error *err);

/* Lobe error Σ|approx − ref| / Σ|ref| over n_pixels values (all images of a
 * set together), as a fraction (×100 for percent). 0 when both are all zero;
 * +Inf when only the reference is. */
double lobe_l1_error(size_t n_pixels, const double *ref, const double *approx);

/* Directional albedo ρ(θi) = ∫ f cos θo dωo from one lobe image. With
 * dx dy = cos θo dωo on the projected disk, ρ = ∫∫ f dx dy, so each pixel
 * contributes (pixel / cos θo)·(2/res)² — the midpoint rule on the disk. It
 * resolves a lobe only as well as the pixels do (an α = 0.01 coat is a few
 * pixels wide); nbrdf_brdf_albedo() estimates ρ without that error. */
double lobe_albedo(int res, const double *image);

/* Albedo error |ρ̂ − ρ| of each of n_images image pairs (per_image may be NULL;
 * else receives n_images values); returns their mean. */
double lobe_albedo_error(int res, int n_images, const double *ref, const double *approx,
                         double *per_image);

/* Point-wise error of one lobe image: the median over the pixels
 * where the reference f is above `floor_fraction` (0.01) of the image's peak f
 * of |f̂/f − 1| (images hold f·cos θo; the ratio is f's). Unlike the lobe
 * error, which sums over the image so that a wrong peak hides behind a right
 * background, it weighs every visible direction alike. NaN when no pixel
 * qualifies (an all-zero reference). lobe_pointwise.c */
double lobe_pointwise_error(int res, const double *ref, const double *approx,
                            double floor_fraction);

/* Median of the finite values among n (NaN when none); sorts a copy. */
double lobe_median_finite(size_t n, const double *x);

/* Adapter for the ground truth: `user` points to an lobe_brdf, and the
 * lobe is evaluated with nbrdf_brdf_eval() and those options (lobe_brdf.c). */
typedef struct lobe_brdf {
  const nbrdf_brdf *brdf;
  nbrdf_eval_options options;
} lobe_brdf;
nbrdf_status lobe_brdf_fn(void *user, size_t n, const nbrdf_query *queries, double *f,
                          nbrdf_error *err);

#endif
