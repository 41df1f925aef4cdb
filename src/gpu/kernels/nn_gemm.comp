#version 450
// One linear map of a network layer on a tile of rows x outputs (docs/GPU.md):
//   y[r][c] = sum_k x[r][k] W[c][k] (+ y[r][c] if ACCUMULATE) (+ bias[c]) (+ a1[r][c]) (+ a2[r][c])
// W is row-major [N x K] at p[w_off] (the PyTorch/nn.h layout). A workgroup computes BM x BN
// outputs; x and W tiles of BK columns are staged in shared memory and every invocation
// keeps TM x TN accumulators in registers (rows tm + i * BM/TM, columns tn + j * BN/TN: the
// invocations of a subgroup read consecutive shared words). Tile sizes are specialization
// constants the host picks from the device's shared-memory limit.
layout(local_size_x_id = 0) in;
layout(constant_id = 1) const int BM = 64;
layout(constant_id = 2) const int BN = 64;
layout(constant_id = 3) const int BK = 16;
layout(constant_id = 4) const int TM = 4;
layout(constant_id = 5) const int TN = 4;

layout(std430, binding = 0) readonly buffer X { float x[]; };
layout(std430, binding = 1) readonly buffer P { float p[]; };
layout(std430, binding = 2) buffer Y { float y[]; };
layout(std430, binding = 3) readonly buffer A1 { float a1[]; };
layout(std430, binding = 4) readonly buffer A2 { float a2[]; };

layout(push_constant) uniform PC {
  uint rows, K, N, w_off, b_off, flags, g_off, be_off;
} pc;

const uint ACCUMULATE = 1u, ADD1 = 2u, ADD2 = 4u, BIAS = 8u;

// Rows of the staged tiles are padded by one word: the loads write consecutive k from
// consecutive invocations, which would otherwise all hit one shared-memory bank.
const int SA = BM + 1, SB = BN + 1;
shared float As[BK * SA]; // As[k * SA + m] = x[m0 + m][k0 + k]
shared float Bs[BK * SB]; // Bs[k * SB + n] = W[n0 + n][k0 + k]

void main() {
  const int MT = BM / TM, NT = BN / TN, T = MT * NT;
  const int tid = int(gl_LocalInvocationID.x);
  const int tm = tid / NT, tn = tid % NT;
  const uint m0 = gl_WorkGroupID.y * uint(BM), n0 = gl_WorkGroupID.x * uint(BN);
  const uint K = pc.K;
  float acc[TM * TN];
  for (int i = 0; i < TM * TN; i++) acc[i] = 0.0;
  for (uint k0 = 0u; k0 < K; k0 += uint(BK)) {
    for (int e = tid; e < BM * BK; e += T) {
      int m = e / BK, k = e % BK;
      uint r = m0 + uint(m), kk = k0 + uint(k);
      As[k * SA + m] = (r < pc.rows && kk < K) ? x[r * K + kk] : 0.0;
    }
    for (int e = tid; e < BN * BK; e += T) {
      int n = e / BK, k = e % BK;
      uint c = n0 + uint(n), kk = k0 + uint(k);
      Bs[k * SB + n] = (c < pc.N && kk < K) ? p[pc.w_off + c * K + kk] : 0.0;
    }
    barrier();
    for (int k = 0; k < BK; k++) {
      float a[TM], b[TN];
      for (int i = 0; i < TM; i++) a[i] = As[k * SA + tm + i * MT];
      for (int j = 0; j < TN; j++) b[j] = Bs[k * SB + tn + j * NT];
      for (int i = 0; i < TM; i++)
        for (int j = 0; j < TN; j++) acc[i * TN + j] += a[i] * b[j];
    }
    barrier();
  }
  for (int i = 0; i < TM; i++) {
    uint r = m0 + uint(tm + i * MT);
    if (r >= pc.rows) continue;
    for (int j = 0; j < TN; j++) {
      uint c = n0 + uint(tn + j * NT);
      if (c >= pc.N) continue;
      uint at = r * pc.N + c;
      float v = acc[i * TN + j];
      // The CPU's order: skip GEMM first, then + x W^T, then bias, residual, skip.
      if ((pc.flags & ACCUMULATE) != 0u) v = y[at] + v;
      if ((pc.flags & BIAS) != 0u) v += p[pc.b_off + c];
      if ((pc.flags & ADD1) != 0u) v += a1[at];
      if ((pc.flags & ADD2) != 0u) v += a2[at];
      y[at] = v;
    }
  }
}
