// nbrdf shaders: the importance-sampling proxy of Fan et al. 2022, Eq. 6 (GLSL 450).
//
//   p(ωo | ωi) = (1 - w) p_G(ωo | ωi; σ) + w cos θo / π
//
// Mirrors src/model/proxy.c (which has the derivation): p_G puts the projected half
// vector (h.x, h.y) under an isotropic Gaussian of std σ truncated to the unit disk,
// p(h) = p_disk cos θh, p(ωo) = p(h) / (4 |ωo·h|). σ and w are per-latent constants:
// the bake stores them per texel (channels proxy.sigma.*, proxy.w.*), so no network runs
// here. Same uniforms u -> same ωo as nbrdf_proxy_sample (tests/shaders/test_shader_proxy.c).
#ifndef NBRDF_PROXY_GLSL
#define NBRDF_PROXY_GLSL

#include "nbrdf_common.glsl"

// 1 - exp(-1/2σ²): the Gaussian's mass inside the unit disk.
float nbrdf_proxy_disk_mass(float sigma) { return -nbrdf_expm1(-0.5 / (sigma * sigma)); }

// Density on the unit disk of the truncated Gaussian at radius² r2 (0 outside).
float nbrdf_proxy_disk_pdf(float sigma, float r2) {
  if (!(r2 <= 1.0)) return 0.0;
  float s2 = sigma * sigma;
  return exp(-0.5 * r2 / s2) / (2.0 * NBRDF_PI * s2 * nbrdf_proxy_disk_mass(sigma));
}

// Eq. 6 for unit ωi, ωo; 0 when either is at or below the horizon.
float nbrdf_proxy_pdf(float sigma, float w, vec3 wi, vec3 wo) {
  if (!(wi.z > 0.0) || !(wo.z > 0.0)) return 0.0;
  float p = w * wo.z / NBRDF_PI;
  if (w < 1.0) {
    vec3 h = normalize(wi + wo);
    float d = abs(dot(wo, h));
    if (d > 0.0 && h.z > 0.0)
      p += (1.0 - w) * nbrdf_proxy_disk_pdf(sigma, h.x * h.x + h.y * h.y) * h.z / (4.0 * d);
  }
  return p;
}

// Shirley-Chiu concentric map of [0,1)² onto the unit disk (src/core/warp.c).
vec2 nbrdf_warp_disk(float u1, float u2) {
  float a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
  if (a == 0.0 && b == 0.0) return vec2(0.0);
  float r, phi;
  if (abs(a) > abs(b)) {
    r = a;
    phi = (NBRDF_PI / 4.0) * (b / a);
  } else {
    r = b;
    phi = NBRDF_PI / 2.0 - (NBRDF_PI / 4.0) * (a / b);
  }
  return vec2(r * cos(phi), r * sin(phi));
}

// Draws ωo for ωi from u ∈ [0,1)³: u.x < w picks the Lambert lobe, (u.y, u.z) drive the
// chosen lobe. Returns (ωo, pdf) with pdf = nbrdf_proxy_pdf(ωo) > 0, or pdf = 0 when the
// reflection falls at or below the horizon (the sample is lost, as in the C sampler).
vec4 nbrdf_proxy_sample(float sigma, float w, vec3 wi, vec3 u) {
  vec3 d;
  if (u.x < w) {
    vec2 p = nbrdf_warp_disk(u.y, u.z);
    d = vec3(p, sqrt(max(0.0, 1.0 - p.x * p.x - p.y * p.y)));
  } else {
    // Invert the truncated radial CDF: r² = -2σ² log(1 - u1 (1 - exp(-1/2σ²))).
    float s2 = sigma * sigma;
    float r2 = min(1.0, -2.0 * s2 * nbrdf_log1p(-u.y * nbrdf_proxy_disk_mass(sigma)));
    // φ = 2π u.z, evaluated as φ' = φ - π in [-π, π) where Vulkan bounds sin/cos's error.
    float r = sqrt(r2), phi = 2.0 * NBRDF_PI * (u.z - 0.5);
    vec3 h = vec3(-r * cos(phi), -r * sin(phi), sqrt(max(0.0, 1.0 - r2)));
    d = 2.0 * dot(wi, h) * h - wi;
  }
  if (!(d.z > 0.0)) return vec4(d, 0.0);
  vec3 wo = normalize(d);
  return vec4(wo, nbrdf_proxy_pdf(sigma, w, wi, wo));
}

#endif
