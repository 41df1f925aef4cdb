// Test kernel: latent fetch (nbrdf_latent_fetch.glsl).
//   binding 0: queries, 4 floats each: u, v, lod, level (level >= 0: bilinear in that
//              level; < 0: trilinear at lod)
//   binding 1: the latent texture (nbrdf_gpu_pack_latents)
//   binding 2: results, `channels` floats per query
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "nbrdf_latent_fetch.glsl"

layout(std430, binding = 0) readonly buffer Queries { vec4 q[]; };
layout(std430, binding = 2) writeonly buffer Results { float r[]; };
layout(push_constant) uniform Push { uint n; } pc;

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.n) return;
  vec4 c = q[k];
  NbrdfFootprint fp = c.w >= 0.0 ? nbrdf_latent_footprint_level(c.xy, uint(c.w))
                                 : nbrdf_latent_footprint(c.xy, c.z);
  uint C = nbrdf_l[NBRDF_L_CHANNELS];
  for (uint i = 0u; i < C; i++) r[k * C + i] = nbrdf_latent_channel(fp, i);
}
