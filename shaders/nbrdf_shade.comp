// nbrdf: one shading query per invocation on a latent texture: fetch the filtered texel at
// (uv, lod), decode every colour channel for (ωi, ωo), and evaluate the proxy pdf with the
// texel's own σ and w. What a renderer's material kernel does; bench_shader times it for a
// 1920x1080 frame.
//   binding 0: decoder weights (nbrdf_gpu_pack_decoder)
//   binding 1: latent texture (nbrdf_gpu_pack_latents)
//   binding 2: queries, 9 floats each: u, v, lod, ωi.xyz, ωo.xyz
//   binding 3: results, 4 floats each: f of colour 0..2 (colours beyond the texture's: 0),
//              and the proxy pdf of colour 0 (0 when the texture stores no proxy)
//   push constant: the query count
#version 450
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;

#include "nbrdf_decoder.glsl"
#include "nbrdf_latent_fetch.glsl"
#include "nbrdf_proxy.glsl"

layout(std430, binding = 2) readonly buffer Queries { float q[]; };
layout(std430, binding = 3) writeonly buffer Results { vec4 result[]; };
layout(push_constant) uniform Push { uint n; } pc;

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.n) return;
  uint at = 9u * k;
  vec2 uv = vec2(q[at], q[at + 1u]);
  float lod = q[at + 2u];
  vec3 wi = vec3(q[at + 3u], q[at + 4u], q[at + 5u]);
  vec3 wo = vec3(q[at + 6u], q[at + 7u], q[at + 8u]);
  NbrdfFootprint fp = nbrdf_latent_footprint(uv, lod);
  vec4 r = vec4(0.0);
  uint colours = nbrdf_l[NBRDF_L_COLOURS];
  int dim = nbrdf_latent_dim();
  for (uint c = 0u; c < colours; c++) {
    for (int i = 0; i < dim; i++)
      nbrdf_decoder_set_latent(i, nbrdf_latent_channel(fp, nbrdf_latent_index(c, uint(i))));
    r[c] = nbrdf_decode(wi, wo);
  }
  if (nbrdf_l[NBRDF_L_PROXY] != 0u) {
    float sigma = nbrdf_latent_channel(fp, nbrdf_latent_index_sigma(0u));
    float w = nbrdf_latent_channel(fp, nbrdf_latent_index_w(0u));
    r.w = nbrdf_proxy_pdf(sigma, w, wi, wo);
  }
  result[k] = r;
}
