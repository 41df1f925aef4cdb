// nbrdf: a batch of decoder queries, TILED: a workgroup decodes NBRDF_T_ROWS queries
// together (nbrdf_tiled.glsl); same buffers as nbrdf_decode.comp (tests, bench).
//   binding 0: the decoder weights (nbrdf_gpu_pack_decoder)
//   binding 1: queries, (6 + latent_dim) floats each: ωi.xyz, ωo.xyz, latent
//   binding 2: two floats per query: f (no cosine), and the raw network output o
//   push constant: the query count
//   specialization constants 0..6: shaders/nbrdf_tiled.h (nbrdf_tile_config)
// Dispatch ceil(n / NBRDF_T_ROWS) workgroups. Compiled twice: nbrdf_decode_tiled.spv
// (fp32, any device) and, with NBRDF_TILED_COOP, nbrdf_decode_coop.spv (tensor cores).
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

layout(std430, binding = 1) readonly buffer Queries { float q[]; };
layout(std430, binding = 2) writeonly buffer Results { vec2 f[]; };
layout(push_constant) uniform Push { uint n; } pc;

void main() {
  int dim = nbrdf_latent_dim();
  uint g0 = gl_WorkGroupID.x * uint(NBRDF_T_ROWS);
  for (int r = nbrdf_t_tid(); r < NBRDF_T_ROWS; r += nbrdf_t_threads()) {
    uint k = g0 + uint(r);
    vec3 wi = vec3(0.0, 0.0, 1.0), wo = wi;
    if (k < pc.n) {
      uint at = k * uint(6 + dim);
      wi = vec3(q[at], q[at + 1u], q[at + 2u]);
      wo = vec3(q[at + 3u], q[at + 4u], q[at + 5u]);
      for (int i = 0; i < dim; i++) nbrdf_tile_input(r, i, q[at + 6u + uint(i)]);
    } else {
      for (int i = 0; i < dim; i++) nbrdf_tile_input(r, i, 0.0);
    }
    nbrdf_tile_encode(r, wi, wo);
  }
  nbrdf_tile_forward();
  for (int r = nbrdf_t_tid(); r < NBRDF_T_ROWS; r += nbrdf_t_threads()) {
    uint k = g0 + uint(r);
    if (k < pc.n) f[k] = vec2(nbrdf_tile_output_f(r), nbrdf_tile_output_raw(r));
  }
}
