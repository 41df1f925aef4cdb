// nbrdf shaders: direction encodings (ωi, ωo) -> decoder features (GLSL 450).
// Mirrors src/model/encoding.c: first both directions are rotated about the
// normal so that ωi has azimuth 0; the kinds are those of the weights' header word
// NBRDF_W_ENCODING:
//   0 cartesian: (ωi.xyz, ωo.xyz)
//   1 halfdiff:  Rusinkiewicz 1998: h = normalize(ωi + ωo) and d = ωi in the frame
//                of h (rotated by -φh about z, then by -θh about y)
// followed, for octaves K > 0, by sin(2^k π x), cos(2^k π x) for k < K and each
// of the six base features x, interleaved as (sin, cos) per feature:
// feature 6 + 12 k + 2 j (+1). Directions: unit vectors, z > 0, shading frame z up.
#ifndef NBRDF_ENCODING_GLSL
#define NBRDF_ENCODING_GLSL

#include "nbrdf_common.glsl"

const uint NBRDF_ENCODING_CARTESIAN = 0u;
const uint NBRDF_ENCODING_HALFDIFF = 1u;

// Both directions rotated about the normal so that ωi has azimuth 0, as
// src/model/encoding.c does before every encoding (the BRDFs are isotropic and
// the decoders were trained with ωi in the xz-plane).
void nbrdf_encode_canonical(inout vec3 wi, inout vec3 wo) {
  float s = sqrt(wi.x * wi.x + wi.y * wi.y);
  if (!(s > 1e-12)) return;
  float c = wi.x / s, sn = wi.y / s;
  wo.xy = vec2(c * wo.x + sn * wo.y, -sn * wo.x + c * wo.y);
  wi.xy = vec2(s, 0.0);
}

// The six base features: a = first three, b = last three.
void nbrdf_encode_base(uint kind, vec3 wi, vec3 wo, out vec3 a, out vec3 b) {
  nbrdf_encode_canonical(wi, wo);
  if (kind != NBRDF_ENCODING_HALFDIFF) {
    a = wi;
    b = wo;
    return;
  }
  vec3 s = wi + wo;
  float len = sqrt(dot(s, s));
  // ωi = -ωo happens only at the horizon; any h is then as good as another.
  vec3 h = len > 1e-12 ? s / len : vec3(0.0, 0.0, 1.0);
  float sin_theta = sqrt(h.x * h.x + h.y * h.y);
  float cos_phi = 1.0, sin_phi = 0.0;
  if (sin_theta > 1e-12) {
    cos_phi = h.x / sin_theta;
    sin_phi = h.y / sin_theta;
  }
  float x1 = cos_phi * wi.x + sin_phi * wi.y;
  float y1 = -sin_phi * wi.x + cos_phi * wi.y;
  float z1 = wi.z;
  a = h;
  b = vec3(h.z * x1 - sin_theta * z1, y1, sin_theta * x1 + h.z * z1);
}

// (sin, cos)(2^k π x) with the argument reduced exactly first: 2^(k-1) x is exact in
// float and fract() is exact, so only one period goes into sin/cos (whose accuracy
// Vulkan guarantees only on [-π, π]).
vec2 nbrdf_encode_frequency(float x, int k) {
  float t = k == 0 ? 0.5 * x : ldexp(x, k - 1); // x · 2^k / 2: turns of 2π
  t = t - floor(t + 0.5);                       // in [-0.5, 0.5): exact
  float arg = 2.0 * NBRDF_PI * t;
  return vec2(sin(arg), cos(arg));
}

#endif
