// nbrdf: the material kernel of nbrdf_shade.comp, TILED (nbrdf_tiled.glsl): the rows of a
// workgroup are (query, colour channel) pairs, row = query * colours + channel, so an RGB
// texel's three decodes (same directions, each channel's latents) are three rows of the
// same GEMM. Each row fetches the filtered texel at (uv, lod) for its own channel; the
// channel-0 row also evaluates the proxy pdf.
//   binding 0: decoder weights (nbrdf_gpu_pack_decoder)
//   binding 1: latent texture (nbrdf_gpu_pack_latents)
//   binding 2: queries, 9 floats each: u, v, lod, ωi.xyz, ωo.xyz
//   binding 3: results, 4 floats per query: f of colour 0..2 (colours beyond the
//              texture's: 0), and the proxy pdf of colour 0 (0 without a stored proxy)
//   push constant: the query count
//   specialization constants 0..6: shaders/nbrdf_tiled.h (nbrdf_tile_config)
// Dispatch ceil(n * colours / NBRDF_T_ROWS) workgroups. Compiled twice:
// nbrdf_shade_tiled.spv (fp32, any device), nbrdf_shade_coop.spv (NBRDF_TILED_COOP).
#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef NBRDF_TILED_COOP
#ifndef NBRDF_COOP_EMU
#extension GL_NV_cooperative_matrix : require
#extension GL_KHR_memory_scope_semantics : require
#endif
#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_quad : require
#endif
layout(local_size_x_id = 1) in;

#include "nbrdf_tiled.glsl"
#include "nbrdf_latent_fetch.glsl"
#include "nbrdf_proxy.glsl"

layout(std430, binding = 2) readonly buffer Queries { float q[]; };
layout(std430, binding = 3) writeonly buffer Results { float result[]; };
layout(push_constant) uniform Push { uint n; } pc;

void main() {
  int dim = nbrdf_latent_dim();
  uint colours = nbrdf_l[NBRDF_L_COLOURS];
  uint rows = pc.n * colours;
  uint g0 = gl_WorkGroupID.x * uint(NBRDF_T_ROWS);
  for (int r = nbrdf_t_tid(); r < NBRDF_T_ROWS; r += nbrdf_t_threads()) {
    uint g = g0 + uint(r);
    vec3 wi = vec3(0.0, 0.0, 1.0), wo = wi;
    if (g < rows) {
      uint k = g / colours, c = g - k * colours, at = 9u * k;
      vec2 uv = vec2(q[at], q[at + 1u]);
      float lod = q[at + 2u];
      wi = vec3(q[at + 3u], q[at + 4u], q[at + 5u]);
      wo = vec3(q[at + 6u], q[at + 7u], q[at + 8u]);
      NbrdfFootprint fp = nbrdf_latent_footprint(uv, lod);
      for (int i = 0; i < dim; i++)
        nbrdf_tile_input(r, i, nbrdf_latent_channel(fp, nbrdf_latent_index(c, uint(i))));
      if (c == 0u) {
        float pdf = 0.0;
        if (nbrdf_l[NBRDF_L_PROXY] != 0u) {
          float sigma = nbrdf_latent_channel(fp, nbrdf_latent_index_sigma(0u));
          float w = nbrdf_latent_channel(fp, nbrdf_latent_index_w(0u));
          pdf = nbrdf_proxy_pdf(sigma, w, wi, wo);
        }
        result[4u * k + 3u] = pdf;
        for (uint cc = colours; cc < 3u; cc++) result[4u * k + cc] = 0.0;
      }
    } else {
      for (int i = 0; i < dim; i++) nbrdf_tile_input(r, i, 0.0);
    }
    nbrdf_tile_encode(r, wi, wo);
  }
  nbrdf_tile_forward();
  for (int r = nbrdf_t_tid(); r < NBRDF_T_ROWS; r += nbrdf_t_threads()) {
    uint g = g0 + uint(r);
    if (g < rows) {
      uint k = g / colours;
      result[4u * k + (g - k * colours)] = nbrdf_tile_output_f(r);
    }
  }
}
