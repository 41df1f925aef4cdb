#include "model/proxy.h"

#include "core/warp.h"

/* 1 − exp(−1/2σ²): the Gaussian's mass inside the unit disk, the truncation's
 * normaliser. expm1 keeps it exact for large σ, where it tends to 1/2σ². */
static double disk_mass(double sigma) { return -expm1(-0.5 / (sigma * sigma)); }

double model_proxy_disk_pdf(double sigma, double r2) {
  if (!(r2 <= 1.0)) return 0.0;
  double s2 = sigma * sigma;
  return exp(-0.5 * r2 / s2) / (2.0 * M_PI * s2 * disk_mass(sigma));
}

/* Density of ωo given its half vector h (upper hemisphere, h·ωo ≠ 0). */
static double lobe_pdf(double sigma, vec3 h, vec3 wo) {
  double dot = fabs(v3_dot(wo, h));
  if (!(dot > 0.0) || !(h.z > 0.0)) return 0.0;
  return model_proxy_disk_pdf(sigma, h.x * h.x + h.y * h.y) * h.z / (4.0 * dot);
}

double model_proxy_gaussian_pdf(double sigma, vec3 wi, vec3 wo) {
  if (!(wi.z > 0.0) || !(wo.z > 0.0)) return 0.0;
  return lobe_pdf(sigma, v3_normalize(v3_add(wi, wo)), wo);
}

double model_proxy_gaussian_pdf_sphere(double sigma, vec3 wi, vec3 wo) {
  vec3 s = v3_add(wi, wo);
  double len = v3_length(s);
  if (!(len > 0.0)) return 0.0;
  /* Reflection about h and about −h is the same map; the sampler only draws
   * the upper one, so below-horizon ωo come from h = −normalize(ωi + ωo). */
  vec3 h = v3_scale(s, (s.z < 0.0 ? -1.0 : 1.0) / len);
  return lobe_pdf(sigma, h, wo);
}

double model_proxy_pdf(double sigma, double w, vec3 wi, vec3 wo) {
  if (!(wi.z > 0.0) || !(wo.z > 0.0)) return 0.0;
  double p = w * wo.z / M_PI;
  if (w < 1.0) p += (1.0 - w) * model_proxy_gaussian_pdf(sigma, wi, wo);
  return p;
}

int model_proxy_sample(double sigma, double w, vec3 wi, double u_lobe, double u1, double u2,
                       vec3 *wo, double *pdf) {
  vec3 d;
  if (u_lobe < w) {
    d = core_warp_cosine_hemisphere(u1, u2);
  } else {
    /* Invert the truncated radial CDF: r² = −2σ² log(1 − u1 (1 − exp(−1/2σ²))). */
    double s2 = sigma * sigma;
    double r2 = fmin(1.0, -2.0 * s2 * log1p(-u1 * disk_mass(sigma)));
    double r = sqrt(r2), phi = 2.0 * M_PI * u2;
    vec3 h = v3(r * cos(phi), r * sin(phi), sqrt(fmax(0.0, 1.0 - r2)));
    d = v3_sub(v3_scale(h, 2.0 * v3_dot(wi, h)), wi);
  }
  if (!(d.z > 0.0)) {
    *wo = d;
    *pdf = 0.0;
    return 0;
  }
  *wo = v3_normalize(d);
  *pdf = model_proxy_pdf(sigma, w, wi, *wo);
  return *pdf > 0.0;
}
