// nbrdf: a batch of decoder queries, one per invocation (the kernel the tests and
// bench/bench_shader.c run; an example of how to call nbrdf_decoder.glsl).
//   binding 0: the decoder weights (nbrdf_gpu_pack_decoder)
//   binding 1: queries, (6 + latent_dim) floats each: ωi.xyz, ωo.xyz, latent
//   binding 2: two floats per query: f (no cosine), and the raw network output o
//   push constant: the query count
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "nbrdf_decoder.glsl"

layout(std430, binding = 1) readonly buffer Queries { float q[]; };
layout(std430, binding = 2) writeonly buffer Results { vec2 f[]; };
layout(push_constant) uniform Push { uint n; } pc;

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.n) return;
  int dim = nbrdf_latent_dim();
  uint at = k * uint(6 + dim);
  vec3 wi = vec3(q[at], q[at + 1u], q[at + 2u]);
  vec3 wo = vec3(q[at + 3u], q[at + 4u], q[at + 5u]);
  for (int i = 0; i < dim; i++) nbrdf_decoder_set_latent(i, q[at + 6u + uint(i)]);
  float o = nbrdf_decode_raw(wi, wo);
  f[k] = vec2(nbrdf_decoder_output(o), o);
}
