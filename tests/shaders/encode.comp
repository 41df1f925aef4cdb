// Test kernel: the direction encoding alone (nbrdf_encoding.glsl).
//   binding 0: pairs, 6 floats each (ωi, ωo); binding 1: features, 102 floats per pair
//   push: n, kind, octaves
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "nbrdf_encoding.glsl"

layout(std430, binding = 0) readonly buffer Pairs { float q[]; };
layout(std430, binding = 1) writeonly buffer Features { float feat[]; };
layout(push_constant) uniform Push { uint n; uint kind; uint octaves; } pc;

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.n) return;
  vec3 wi = vec3(q[6u * k], q[6u * k + 1u], q[6u * k + 2u]);
  vec3 wo = vec3(q[6u * k + 3u], q[6u * k + 4u], q[6u * k + 5u]);
  vec3 a, b;
  nbrdf_encode_base(pc.kind, wi, wo, a, b);
  float base6[6] = float[6](a.x, a.y, a.z, b.x, b.y, b.z);
  uint at = 102u * k;
  for (int j = 0; j < 6; j++) feat[at + uint(j)] = base6[j];
  for (int o = 0; o < int(pc.octaves); o++)
    for (int j = 0; j < 6; j++) {
      vec2 sc = nbrdf_encode_frequency(base6[j], o);
      feat[at + uint(6 + 12 * o + 2 * j)] = sc.x;
      feat[at + uint(7 + 12 * o + 2 * j)] = sc.y;
    }
}
