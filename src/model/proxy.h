/* The importance-sampling proxy of Fan et al. 2022, Eq. 6:
 *
 *   p(ωo | ωi) = (1 − w) · p_G(ωo | ωi; σ) + w · cos θo / π
 *
 * p_G places the half vector h = normalize(ωi + ωo): its projection (h.x, h.y)
 * on the unit disk follows an isotropic 2-D Gaussian of standard deviation σ
 * centred on the normal, truncated to the disk and renormalised, so that the
 * radial CDF F(r) = (1 − exp(−r²/2σ²)) / (1 − exp(−1/2σ²)) inverts in closed
 * form. Densities convert to solid angle through the half-vector Jacobians:
 * a solid angle dω_h around h projects onto the disk as dA = cos θh dω_h, so
 * p(h) = p_disk(h.x, h.y) · cos θh; reflection ωo = 2 (ωi·h) h − ωi gives
 * p(ωo) = p(h) / (4 |ωo·h|) (Walter et al. 2007, Eq. 14).
 *
 * A reflected direction can fall below the horizon. The sampler reports such a
 * sample as invalid and its mass is lost: over the upper hemisphere the pdf
 * integrates to 1 − (lost mass) ≤ 1, and it is still exactly the density of
 * the valid samples, which is what an unbiased MIS estimator needs. Over the
 * whole sphere (model_proxy_gaussian_pdf_sphere) the Gaussian lobe integrates
 * to exactly 1.
 *
 * σ is the Gaussian's std on the projected disk: σ → 0 approaches a mirror
 * about the normal, σ → ∞ a uniform disk (a cosine-weighted half vector). */
#ifndef NBRDF_MODEL_PROXY_H
#define NBRDF_MODEL_PROXY_H

#include "core/vec3.h"

/* Smallest σ the proxy accepts; the sampling network's output is floored here. */
#define MODEL_PROXY_SIGMA_MIN 1e-3

/* Density on the unit disk of the truncated Gaussian at radius² r2 (0 for r2 > 1). */
double model_proxy_disk_pdf(double sigma, double r2);

/* The Gaussian lobe alone, for ωo on the upper hemisphere (0 below). */
double model_proxy_gaussian_pdf(double sigma, vec3 wi, vec3 wo);
/* The Gaussian lobe's density over the whole sphere of ωo, below-horizon
 * reflections included (for tests of the lost mass). */
double model_proxy_gaussian_pdf_sphere(double sigma, vec3 wi, vec3 wo);

/* Eq. 6 for ωi, ωo (unit, z > 0); 0 when either is at or below the horizon. */
double model_proxy_pdf(double sigma, double w, vec3 wi, vec3 wo);

/* Draws ωo for ωi: u_lobe < w picks the Lambert lobe, otherwise the Gaussian,
 * with (u1, u2) ∈ [0,1)² for the chosen lobe. Returns 1 and sets *wo and *pdf
 * (the full mixture density of Eq. 6 at ωo) for a valid sample; returns 0 when
 * ωo falls at or below the horizon (then *pdf = 0). */
int model_proxy_sample(double sigma, double w, vec3 wi, double u_lobe, double u1, double u2,
                       vec3 *wo, double *pdf);

#endif
