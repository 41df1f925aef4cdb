// Test kernel: the proxy sampler and pdf (nbrdf_proxy.glsl).
//   binding 0: cases, 12 floats each: sigma, w, ωi.xyz, u.xyz, ωo.xyz (for the pdf), 0
//   binding 1: results, 8 floats each: sampled ωo.xyz, its pdf (0 = lost), pdf(ωi, given
//              ωo), 0, 0, 0
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "nbrdf_proxy.glsl"

layout(std430, binding = 0) readonly buffer Cases { float q[]; };
layout(std430, binding = 1) writeonly buffer Results { float r[]; };
layout(push_constant) uniform Push { uint n; } pc;

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.n) return;
  uint at = 12u * k;
  float sigma = q[at], w = q[at + 1u];
  vec3 wi = vec3(q[at + 2u], q[at + 3u], q[at + 4u]);
  vec3 u = vec3(q[at + 5u], q[at + 6u], q[at + 7u]);
  vec3 wo = vec3(q[at + 8u], q[at + 9u], q[at + 10u]);
  vec4 s = nbrdf_proxy_sample(sigma, w, wi, u);
  uint o = 8u * k;
  r[o] = s.x;
  r[o + 1u] = s.y;
  r[o + 2u] = s.z;
  r[o + 3u] = s.w;
  r[o + 4u] = nbrdf_proxy_pdf(sigma, w, wi, wo);
  r[o + 5u] = 0.0;
  r[o + 6u] = 0.0;
  r[o + 7u] = 0.0;
}
