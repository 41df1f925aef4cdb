#version 450
// nn_gemm.comp's map on tensor cores (GL_NV_cooperative_matrix): x and W tiles are staged
// in shared memory as fp16, 16 x 16 x 16 fragments multiply-add into fp32 accumulators, the
// 64 x 64 result goes through shared memory into the same fp32 epilogue (previous y, bias,
// residual, skip). 128 invocations = 4 subgroups of 32; subgroup s owns the 32 x 32 block
// (s / 2, s % 2) of the tile, i.e. 2 x 2 fragments. Only selected where the device reports
// VK_NV_cooperative_matrix with this shape (gpu_context.c); never on lavapipe.
#extension GL_NV_cooperative_matrix : require
#extension GL_EXT_shader_explicit_arithmetic_types_float16 : require
#extension GL_KHR_memory_scope_semantics : require
#extension GL_KHR_shader_subgroup_basic : require
layout(local_size_x = 128) in;

layout(std430, binding = 0) readonly buffer X { float x[]; };
layout(std430, binding = 1) readonly buffer P { float p[]; };
layout(std430, binding = 2) buffer Y { float y[]; };
layout(std430, binding = 3) readonly buffer A1 { float a1[]; };
layout(std430, binding = 4) readonly buffer A2 { float a2[]; };

layout(push_constant) uniform PC {
  uint rows, K, N, w_off, b_off, flags, g_off, be_off;
} pc;

const uint ACCUMULATE = 1u, ADD1 = 2u, ADD2 = 4u, BIAS = 8u;
const uint BM = 64u, BN = 64u, BK = 32u;

shared float16_t As[BM * BK]; // row-major [m][k]: matrix A (M x K)
shared float16_t Bs[BN * BK]; // [n][k] = W rows: matrix B (K x N) column-major
shared float Cs[BM * BN];     // row-major [m][n]

#define FRAG16 fcoopmatNV<16, gl_ScopeSubgroup, 16, 16>
#define FRAG32 fcoopmatNV<32, gl_ScopeSubgroup, 16, 16>

void main() {
  const uint tid = gl_LocalInvocationID.x;
  const uint sg = tid / 32u; // VK_NV_cooperative_matrix exists on NVIDIA only: subgroups of 32
  const uint sm = (sg / 2u) * 32u, sn = (sg % 2u) * 32u;
  const uint m0 = gl_WorkGroupID.y * BM, n0 = gl_WorkGroupID.x * BN, K = pc.K;
  FRAG32 c00 = FRAG32(0.0), c01 = FRAG32(0.0), c10 = FRAG32(0.0), c11 = FRAG32(0.0);
  for (uint k0 = 0u; k0 < K; k0 += BK) {
    for (uint e = tid; e < BM * BK; e += 128u) {
      uint m = e / BK, k = e % BK, r = m0 + m, kk = k0 + k;
      As[e] = float16_t((r < pc.rows && kk < K) ? x[r * K + kk] : 0.0);
    }
    for (uint e = tid; e < BN * BK; e += 128u) {
      uint n = e / BK, k = e % BK, c = n0 + n, kk = k0 + k;
      Bs[e] = float16_t((c < pc.N && kk < K) ? p[pc.w_off + c * K + kk] : 0.0);
    }
    barrier();
    for (uint k = 0u; k < BK; k += 16u) {
      FRAG16 a0, a1f, b0, b1;
      coopMatLoadNV(a0, As, (sm + 0u) * BK + k, BK, false);
      coopMatLoadNV(a1f, As, (sm + 16u) * BK + k, BK, false);
      coopMatLoadNV(b0, Bs, (sn + 0u) * BK + k, BK, true);
      coopMatLoadNV(b1, Bs, (sn + 16u) * BK + k, BK, true);
      c00 = coopMatMulAddNV(a0, b0, c00);
      c01 = coopMatMulAddNV(a0, b1, c01);
      c10 = coopMatMulAddNV(a1f, b0, c10);
      c11 = coopMatMulAddNV(a1f, b1, c11);
    }
    barrier();
  }
  coopMatStoreNV(c00, Cs, (sm + 0u) * BN + sn + 0u, BN, false);
  coopMatStoreNV(c01, Cs, (sm + 0u) * BN + sn + 16u, BN, false);
  coopMatStoreNV(c10, Cs, (sm + 16u) * BN + sn + 0u, BN, false);
  coopMatStoreNV(c11, Cs, (sm + 16u) * BN + sn + 16u, BN, false);
  barrier();
  for (uint e = tid; e < BM * BN; e += 128u) {
    uint r = m0 + e / BN, c = n0 + e % BN;
    if (r >= pc.rows || c >= pc.N) continue;
    uint at = r * pc.N + c;
    float v = Cs[e];
    if ((pc.flags & ACCUMULATE) != 0u) v = y[at] + v;
    if ((pc.flags & BIAS) != 0u) v += p[pc.b_off + c];
    if ((pc.flags & ADD1) != 0u) v += a1[at];
    if ((pc.flags & ADD2) != 0u) v += a2[at];
    y[at] = v;
  }
}
