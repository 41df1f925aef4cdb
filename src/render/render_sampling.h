/* The renderer's sampling decisions, kept apart so that tests can check them
 * against their densities: the power heuristic of MIS, and the BRDF-sampling
 * density of a texel with one proxy (sigma, w) per colour channel. */
#ifndef NBRDF_RENDER_RENDER_SAMPLING_H
#define NBRDF_RENDER_RENDER_SAMPLING_H

#include "core/vec3.h"

/* Veach's power heuristic (β = 2) for the strategy of density pa against pb:
 * pa² / (pa² + pb²); 0 when both are 0. w(pa, pb) + w(pb, pa) = 1 whenever
 * either density is positive. */
static inline double render_power_heuristic(double pa, double pb) {
  double a = pa * pa, b = pb * pb;
  if (!(a + b > 0.0)) return 0.0;
  if (!isfinite(a + b)) return isfinite(a) ? 0.0 : (isfinite(b) ? 1.0 : 0.5);
  return a / (a + b);
}

/* The density of render_proxy_mix_sample: the mean of the colour channels'
 * proxy densities (nbrdf_proxy_pdf, paper Eq. 6). wi, wo in the shading
 * frame. */
double render_proxy_mix_pdf(int channels, const float *sigma, const float *w, vec3 wi, vec3 wo);

/* One-sample mixture over the colour channels: u[0] picks channel
 * floor(u[0]·channels), u[1..3] drive nbrdf_proxy_sample for it. Returns 1
 * with *wo and *pdf = render_proxy_mix_pdf(wo) > 0, or 0 when the reflected
 * direction falls below the horizon (a lost sample, its mass missing from
 * the density: the estimator stays unbiased). */
int render_proxy_mix_sample(int channels, const float *sigma, const float *w, vec3 wi,
                            const double u[4], vec3 *wo, double *pdf);

#endif
