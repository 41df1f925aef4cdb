// nbrdf shaders: the TILED decoder ("fully fused MLP", as in tiny-cuda-nn): a workgroup
// evaluates a tile of NBRDF_T_ROWS queries ("rows") that share one decoder (GLSL 450).
//
// Generic over the packed decoder buffer like nbrdf_decoder.glsl (the layer table is read
// at run time), but the network runs as one small GEMM per layer over the whole tile:
//   - each layer's weights are staged through shared memory (read from the buffer once
//     per workgroup and K-chunk, not once per query);
//   - the activations of the whole tile live in shared memory;
//   - every invocation computes blocks of outputs: 4 rows x 4 outputs in registers (fp32
//     variant), or 16 x 16 tiles on the tensor cores (NBRDF_TILED_COOP: fp16 inputs,
//     fp32 accumulators, GL_NV_cooperative_matrix), with bias, the residual input, skip
//     terms, LayerNorm and ReLU fused into the epilogue pass.
// The math is nbrdf_decoder.glsl's (src/nn/nn.h): LayerNorm eps 1e-5, biased variance,
// residual and skip terms added before normalisation. Every invocation of the workgroup
// must call nbrdf_tile_forward() (it contains barriers); see nbrdf_shade_tiled.comp.
//
// Pipeline-time values (specialization constants; shaders/nbrdf_tiled.h computes them
// from the packed header and the device's limits, nbrdf_tile_config):
//   id 0 NBRDF_T_XW    fp32: activation width capacity (multiple of 4)
//                      coop: row stride of the fp32 activations (width rounded to 16, + 4)
//   id 1              workgroup size (local_size_x_id, declared by the kernel)
//   id 2 NBRDF_T_ROWS  rows per tile (fp32: multiple of 4; coop: multiple of 16)
//   id 3 NBRDF_T_HW    hidden width capacity / coop: stride of the fp32 hidden activations
//   id 4 NBRDF_T_INW   width of the kept network input (skip connections), else 4
//   id 5 NBRDF_T_WCH   weight staging elements (fp32: floats; coop: halfs)
//   id 6 NBRDF_T_BPT   fp32: 4x4 blocks per invocation; coop: row stride of the fp16 copy
// Use:
//   #include "nbrdf_tiled.glsl"   (after layout(local_size_x_id = 1) in; a kernel compiled with
//                                  NBRDF_TILED_COOP enables the extensions NBRDF_TILED_EXTENSIONS
//                                  lists right after #version, as nbrdf_decode_tiled.comp does)
//   for rows r of this invocation (r = tid; r < NBRDF_T_ROWS; r += threads):
//     nbrdf_tile_input(r, i, latent_i) for i < latent_dim; nbrdf_tile_encode(r, wi, wo);
//   nbrdf_tile_forward();   // every invocation, uniform control flow
//   f of row r = nbrdf_tile_output_f(r)  (raw network output: nbrdf_tile_output_raw(r))
#ifndef NBRDF_TILED_GLSL
#define NBRDF_TILED_GLSL

#include "nbrdf_encoding.glsl"
#include "nbrdf_weights.glsl"

layout(constant_id = 0) const int NBRDF_T_XW = 64;
layout(constant_id = 2) const int NBRDF_T_ROWS = 32;
layout(constant_id = 3) const int NBRDF_T_HW = 32;
layout(constant_id = 4) const int NBRDF_T_INW = 4;
layout(constant_id = 5) const int NBRDF_T_WCH = 2048;
layout(constant_id = 6) const int NBRDF_T_BPT = 4;

int nbrdf_t_tid() { return int(gl_LocalInvocationIndex); }
int nbrdf_t_threads() { return int(gl_WorkGroupSize.x); }

// Post-GEMM pass modes (bits).
const int NBRDF_T_LN = 1, NBRDF_T_RELU = 2;

#ifndef NBRDF_TILED_COOP
// ---------------------------------------------------------------- fp32 (any device) ---
// Activations transposed, [feature][row] (a vec4 = 4 rows of one feature): the GEMM reads
// 4 rows with one load, the per-row epilogue walks a row with consecutive invocations on
// consecutive addresses. Buffers: X (block input/output, in place) at 0, H (a residual
// block's hidden layer) at ROWS * XW, IN (the network input, kept for skips) after H.
shared vec4 nbrdf_s_act[NBRDF_T_ROWS * (NBRDF_T_XW + NBRDF_T_HW + NBRDF_T_INW) / 4];
// One K-chunk of a layer's weights, transposed: [k][output], a vec4 = the 4 outputs of a
// block (one load for the 4 x 4 block's 16 FMAs); row stride np + 4 when np is a multiple
// of 8, so that the staging stores (consecutive k) hit 8 banks, not 1.
shared vec4 nbrdf_s_w[NBRDF_T_WCH / 4];
// Accumulators: block j of this invocation, row q: nbrdf_acc[4 j + q] = 4 outputs.
vec4 nbrdf_acc[NBRDF_T_BPT * 4];

const int NBRDF_T_X = 0;
int nbrdf_t_h() { return NBRDF_T_ROWS * NBRDF_T_XW; }
int nbrdf_t_in() { return NBRDF_T_ROWS * (NBRDF_T_XW + NBRDF_T_HW); }

float nbrdf_t_get(int buf, int k, int r) {
  int i = buf + k * NBRDF_T_ROWS + r;
  return nbrdf_s_act[i >> 2][i & 3];
}
void nbrdf_t_put(int buf, int k, int r, float v) {
  int i = buf + k * NBRDF_T_ROWS + r;
  nbrdf_s_act[i >> 2][i & 3] = v;
}

void nbrdf_t_gemm_zero() {
  for (int j = 0; j < NBRDF_T_BPT * 4; j++) nbrdf_acc[j] = vec4(0.0);
}

// acc += src[rows x K] W^T, W row-major [N x K] at word `w` of the weights buffer.
void nbrdf_t_gemm(uint w, uint wh, int src, int K, int N) {
  int tid = nbrdf_t_tid(), nt = nbrdf_t_threads();
  int np = (N + 3) & ~3, npp = (np & 7) == 0 ? np + 4 : np;
  int kc = max(1, min(K, (NBRDF_T_WCH & ~3) / npp));
  int rbn = NBRDF_T_ROWS / 4, nb = rbn * (np / 4);
  for (int k0 = 0; k0 < K; k0 += kc) {
    int kn = min(kc, K - k0);
    barrier(); // the previous chunk's readers are done
    for (int i = tid; i < np * kn; i += nt) { // consecutive k: coalesced reads of W's rows
      int n = i / kn, kk = i - n * kn, at = kk * npp + n;
      nbrdf_s_w[at >> 2][at & 3] = n < N ? nbrdf_wf(w + uint(n * K + k0 + kk)) : 0.0;
    }
    barrier();
    for (int j = 0; j < NBRDF_T_BPT; j++) {
      int b = tid + j * nt;
      if (b < nb) {
        int rb = b % rbn, cb = b / rbn;
        int a = (src + k0 * NBRDF_T_ROWS) / 4 + rb;
        vec4 c0 = nbrdf_acc[4 * j], c1 = nbrdf_acc[4 * j + 1], c2 = nbrdf_acc[4 * j + 2],
             c3 = nbrdf_acc[4 * j + 3];
        for (int kk = 0; kk < kn; kk++) {
          vec4 x = nbrdf_s_act[a + kk * (NBRDF_T_ROWS / 4)];
          vec4 wv = nbrdf_s_w[cb + kk * (npp / 4)];
          c0 += x.x * wv;
          c1 += x.y * wv;
          c2 += x.z * wv;
          c3 += x.w * wv;
        }
        nbrdf_acc[4 * j] = c0, nbrdf_acc[4 * j + 1] = c1, nbrdf_acc[4 * j + 2] = c2,
        nbrdf_acc[4 * j + 3] = c3;
      }
    }
  }
}

// dst[rows x N] = acc (+ dst when add: a residual block's input, in place).
void nbrdf_t_gemm_store(int dst, int N, bool add) {
  int tid = nbrdf_t_tid(), nt = nbrdf_t_threads();
  int np = (N + 3) & ~3;
  int rbn = NBRDF_T_ROWS / 4, nb = rbn * (np / 4);
  barrier(); // every read of the GEMM's source is done (dst may be the source)
  for (int j = 0; j < NBRDF_T_BPT; j++) {
    int b = tid + j * nt;
    if (b < nb) {
      int rb = b % rbn, cb = b / rbn;
      for (int q = 0; q < 4; q++) {
        int r = 4 * rb + q;
        for (int o = 0; o < 4; o++) {
          int n = 4 * cb + o;
          if (n < N) {
            float v = nbrdf_acc[4 * j + q][o];
            if (add) v += nbrdf_t_get(dst, n, r);
            nbrdf_t_put(dst, n, r, v);
          }
        }
      }
    }
  }
  barrier();
}

// In place on buf[rows x N], one invocation per row: v += bias + add[.] (optional), then
// LayerNorm (gamma, beta) and/or ReLU by `mode` (nbrdf_decoder.glsl's nbrdf_norm).
void nbrdf_t_post(uint base, int buf, int N, uint bias, int add, uint g, uint be, int mode) {
  int tid = nbrdf_t_tid(), nt = nbrdf_t_threads();
  for (int r = tid; r < NBRDF_T_ROWS; r += nt) {
    float sum = 0.0;
    for (int c = 0; c < N; c++) {
      float v = nbrdf_t_get(buf, c, r);
      if (bias != NBRDF_NONE) v = v + nbrdf_param(base, bias + uint(c));
      if (add >= 0) v = v + nbrdf_t_get(add, c, r);
      nbrdf_t_put(buf, c, r, v);
      sum += v;
    }
    if ((mode & NBRDF_T_LN) != 0) {
      float mean = sum / float(N), ss = 0.0;
      for (int c = 0; c < N; c++) {
        float d = nbrdf_t_get(buf, c, r) - mean;
        ss += d * d;
      }
      float rs = 1.0 / sqrt(ss / float(N) + 1e-5);
      for (int c = 0; c < N; c++) {
        float v = (nbrdf_t_get(buf, c, r) - mean) * rs * nbrdf_param(base, g + uint(c)) +
                  nbrdf_param(base, be + uint(c));
        nbrdf_t_put(buf, c, r, (mode & NBRDF_T_RELU) != 0 ? max(v, 0.0) : v);
      }
    } else if ((mode & NBRDF_T_RELU) != 0) {
      for (int c = 0; c < N; c++) nbrdf_t_put(buf, c, r, max(nbrdf_t_get(buf, c, r), 0.0));
    }
  }
  barrier();
}

// Feature k of row r of the network input.
void nbrdf_tile_input(int r, int k, float v) {
  nbrdf_t_put(NBRDF_T_X, k, r, v);
  if (NBRDF_T_INW > 4) nbrdf_t_put(nbrdf_t_in(), k, r, v);
}
void nbrdf_t_input_pad(int r) {}

float nbrdf_tile_output_raw(int r) { return nbrdf_t_get(NBRDF_T_X, 0, r); }

#else
// ------------------------------------------------- fp16 tensor cores (NVIDIA, coop) ---
// Row-major tiles: X32 [rows][XW] (fp32 block input/output), H32 [rows][HW] (fp32
// hidden), IN32 [rows][INW] (kept input); AH [rows][BPT] the fp16 copy of whatever the
// next GEMM reads (X after an X pass, H after the hidden pass), INH the fp16 input, WH a
// K-chunk of the weights as fp16, column-major B = W^T. The post pass keeps AH equal to
// fp16 of the activations it writes, zero-padded to a multiple of 16 columns.
shared float nbrdf_s_f32[NBRDF_T_ROWS * (NBRDF_T_XW + NBRDF_T_HW + NBRDF_T_INW)];
shared float16_t nbrdf_s_f16[NBRDF_T_ROWS * (NBRDF_T_BPT + NBRDF_T_INW + 16) + NBRDF_T_WCH];
#define NBRDF_C_TPS 4 // 16x16 output tiles per subgroup at most (nbrdf_tiled.h)
#ifndef NBRDF_COOP_EMU
fcoopmatNV<32, gl_ScopeSubgroup, 16, 16> nbrdf_cacc[NBRDF_C_TPS];
#else
// NBRDF_COOP_EMU (tests only, nbrdf_*_coopemu.spv): the same kernel with the three matrix
// operations done by plain arithmetic, so that lavapipe checks every offset, stride,
// padding and pass of the tensor-core kernel. Lane l of a subgroup holds elements
// l + m * subgroupSize (row-major in the 16 x 16 tile) of each accumulator.
float nbrdf_cacc[NBRDF_C_TPS][32];
int nbrdf_e_count() { return 256 / int(gl_SubgroupSize); }
int nbrdf_e_at(int m) { return int(gl_SubgroupInvocationID) + m * int(gl_SubgroupSize); }
#endif

const int NBRDF_T_X = 0;
int nbrdf_t_h() { return NBRDF_T_ROWS * NBRDF_T_XW; }
int nbrdf_t_in() { return NBRDF_T_ROWS * (NBRDF_T_XW + NBRDF_T_HW); }
int nbrdf_t_stride(int buf) {
  return buf == NBRDF_T_X ? NBRDF_T_XW : buf == nbrdf_t_h() ? NBRDF_T_HW : NBRDF_T_INW;
}
const int NBRDF_T_AH = 0;
int nbrdf_t_inh() { return NBRDF_T_ROWS * NBRDF_T_BPT; }
int nbrdf_t_inh_stride() { return NBRDF_T_INW + 16; }

float16_t nbrdf_t_half(float v) { return float16_t(clamp(v, -65504.0, 65504.0)); }

void nbrdf_t_gemm_zero() {
  for (int j = 0; j < NBRDF_C_TPS; j++)
#ifndef NBRDF_COOP_EMU
    nbrdf_cacc[j] = fcoopmatNV<32, gl_ScopeSubgroup, 16, 16>(0.0);
#else
    for (int m = 0; m < 32; m++) nbrdf_cacc[j][m] = 0.0;
#endif
}

// coopMatLoadNV / coopMatStoreNV of accumulator j, row-major fp32 at `at`, `stride`.
void nbrdf_t_acc_load(int j, int at, int stride) {
#ifndef NBRDF_COOP_EMU
  coopMatLoadNV(nbrdf_cacc[j], nbrdf_s_f32, uint(at), uint(stride), false);
#else
  for (int m = 0; m < nbrdf_e_count(); m++) {
    int e = nbrdf_e_at(m);
    nbrdf_cacc[j][m] = nbrdf_s_f32[at + (e >> 4) * stride + (e & 15)];
  }
#endif
}
void nbrdf_t_acc_store(int j, int at, int stride) {
#ifndef NBRDF_COOP_EMU
  coopMatStoreNV(nbrdf_cacc[j], nbrdf_s_f32, uint(at), uint(stride), false);
#else
  for (int m = 0; m < nbrdf_e_count(); m++) {
    int e = nbrdf_e_at(m);
    nbrdf_s_f32[at + (e >> 4) * stride + (e & 15)] = nbrdf_cacc[j][m];
  }
#endif
}
// acc j += A B: A 16 x 16 fp16 row-major in shared memory at `a` (stride as), loaded once
// by nbrdf_t_a_load for every tile of the subgroup that shares it; B 16 x 16 fp16
// column-major in the weights buffer (the host's fp16 copy, nbrdf_tile_f16_pack): column
// n of B = row n of W, from word `b`, `bs` words (2 halfs each) between columns.
#ifndef NBRDF_COOP_EMU
fcoopmatNV<16, gl_ScopeSubgroup, 16, 16> nbrdf_ca;
void nbrdf_t_a_load(int a, int as) {
  coopMatLoadNV(nbrdf_ca, nbrdf_s_f16, uint(a), uint(as), false);
}
void nbrdf_t_acc_mma(int j, uint b, uint bs) {
  fcoopmatNV<16, gl_ScopeSubgroup, 16, 16> mb;
  coopMatLoadNV(mb, nbrdf_w, b, bs, true);
  nbrdf_cacc[j] = coopMatMulAddNV(nbrdf_ca, mb, nbrdf_cacc[j]);
}
#else
int nbrdf_ea, nbrdf_eas;
void nbrdf_t_a_load(int a, int as) { nbrdf_ea = a, nbrdf_eas = as; }
float nbrdf_t_wh(uint b, uint bs, int col, int k) {
  uint i = 2u * (b + uint(col) * bs) + uint(k);
  return unpackHalf2x16(nbrdf_w[i >> 1])[i & 1u];
}
void nbrdf_t_acc_mma(int j, uint b, uint bs) {
  for (int m = 0; m < nbrdf_e_count(); m++) {
    int e = nbrdf_e_at(m), row = e >> 4, col = e & 15;
    float s = 0.0;
    for (int k = 0; k < 16; k++)
      s += float(nbrdf_s_f16[nbrdf_ea + row * nbrdf_eas + k]) * nbrdf_t_wh(b, bs, col, k);
    nbrdf_cacc[j][m] += s;
  }
}
#endif

int nbrdf_t_tiles(int N) { return (NBRDF_T_ROWS / 16) * (((N + 15) & ~15) / 16); }

// acc = dst (a residual block's input, added in the accumulators).
void nbrdf_t_gemm_load(int dst, int N) {
  int stride = nbrdf_t_stride(dst), mtn = NBRDF_T_ROWS / 16, tiles = nbrdf_t_tiles(N);
  for (int j = 0; j < NBRDF_C_TPS; j++) {
    int t = int(gl_SubgroupID) + j * int(gl_NumSubgroups);
    if (t < tiles) {
      int mt = t % mtn, nt16 = t / mtn;
      nbrdf_t_acc_load(j, dst + mt * 16 * stride + nt16 * 16, stride);
    }
  }
}

// acc += A[rows x K] W^T; A is the fp16 copy at half offset `srca` (stride astride), W's
// fp16 copy at word `wh` of the buffer ([round16(N)][round16(K)] halfs, zero-padded): no
// staging, no barriers; every workgroup reads the same few KB (L1/L2 resident).
void nbrdf_t_gemm16(uint wh, int srca, int astride, int K, int N) {
  int kp = (K + 15) & ~15, mtn = NBRDF_T_ROWS / 16, tiles = nbrdf_t_tiles(N);
  int sg = int(gl_SubgroupID), nsg = int(gl_NumSubgroups);
  if (sg >= tiles) return;
  uint bs = uint(kp / 2);
  for (int kt = 0; kt < kp; kt += 16) {
    int amt = -1;
    for (int j = 0; j < NBRDF_C_TPS; j++) {
      int t = sg + j * nsg;
      if (t < tiles) {
        int mt = t % mtn, nt16 = t / mtn;
        if (mt != amt) nbrdf_t_a_load(srca + mt * 16 * astride + kt, astride), amt = mt;
        nbrdf_t_acc_mma(j, wh + uint(nt16 * 16) * bs + uint(kt / 2), bs);
      }
    }
  }
}

void nbrdf_t_gemm(uint w, uint wh, int src, int K, int N) {
  if (src == nbrdf_t_in())
    nbrdf_t_gemm16(wh, nbrdf_t_inh(), nbrdf_t_inh_stride(), K, N);
  else
    nbrdf_t_gemm16(wh, NBRDF_T_AH, NBRDF_T_BPT, K, N);
}

void nbrdf_t_gemm_store(int dst, int N, bool add) {
  int stride = nbrdf_t_stride(dst), mtn = NBRDF_T_ROWS / 16, tiles = nbrdf_t_tiles(N);
  // No barrier before the store: the GEMMs read only the fp16 copies (AH, INH) and the
  // buffer, and each subgroup stores the tiles it computed (and, for a residual block,
  // loaded from dst itself). The barrier after it keeps the post pass, which rewrites AH,
  // behind every subgroup's GEMM.
  for (int j = 0; j < NBRDF_C_TPS; j++) {
    int t = int(gl_SubgroupID) + j * int(gl_NumSubgroups);
    if (t < tiles) {
      int mt = t % mtn, nt16 = t / mtn;
      nbrdf_t_acc_store(j, dst + mt * 16 * stride + nt16 * 16, stride);
    }
  }
  barrier();
}

// Sum over the quad (4 consecutive invocations of a subgroup): the same value in all 4.
float nbrdf_t_sum4(float x) {
  x += subgroupQuadSwapHorizontal(x);
  return x + subgroupQuadSwapVertical(x);
}

// Four invocations per row (columns q, q + 4, ...: a quad), sums over the 4 by quad swaps.
void nbrdf_t_post(uint base, int buf, int N, uint bias, int add, uint g, uint be, int mode) {
  int tid = nbrdf_t_tid(), nt = nbrdf_t_threads();
  int stride = nbrdf_t_stride(buf), np = (N + 15) & ~15;
  for (int i = tid; i < 4 * NBRDF_T_ROWS; i += nt) {
    int r = i >> 2, q = i & 3, at = buf + r * stride, ah = NBRDF_T_AH + r * NBRDF_T_BPT;
    float sum = 0.0;
    for (int c = q; c < N; c += 4) {
      float v = nbrdf_s_f32[at + c];
      if (bias != NBRDF_NONE) v = v + nbrdf_param(base, bias + uint(c));
      if (add >= 0) v = v + nbrdf_s_f32[add + r * NBRDF_T_INW + c];
      nbrdf_s_f32[at + c] = v;
      sum += v;
    }
    float mean = 0.0, rs = 1.0;
    if ((mode & NBRDF_T_LN) != 0) {
      mean = nbrdf_t_sum4(sum) / float(N);
      float ss = 0.0;
      for (int c = q; c < N; c += 4) {
        float d = nbrdf_s_f32[at + c] - mean;
        ss += d * d;
      }
      rs = 1.0 / sqrt(nbrdf_t_sum4(ss) / float(N) + 1e-5);
    }
    for (int c = q; c < N; c += 4) {
      float v = nbrdf_s_f32[at + c];
      if ((mode & NBRDF_T_LN) != 0)
        v = (v - mean) * rs * nbrdf_param(base, g + uint(c)) + nbrdf_param(base, be + uint(c));
      if ((mode & NBRDF_T_RELU) != 0) v = max(v, 0.0);
      nbrdf_s_f32[at + c] = v;
      nbrdf_s_f16[ah + c] = nbrdf_t_half(v);
    }
    for (int c = N + q; c < np; c += 4) nbrdf_s_f16[ah + c] = float16_t(0.0);
  }
  barrier();
}

void nbrdf_tile_input(int r, int k, float v) {
  nbrdf_s_f32[NBRDF_T_X + r * NBRDF_T_XW + k] = v;
  nbrdf_s_f16[NBRDF_T_AH + r * NBRDF_T_BPT + k] = nbrdf_t_half(v);
  if (NBRDF_T_INW > 4) {
    nbrdf_s_f32[nbrdf_t_in() + r * NBRDF_T_INW + k] = v;
    nbrdf_s_f16[nbrdf_t_inh() + r * nbrdf_t_inh_stride() + k] = nbrdf_t_half(v);
  }
}

// Zeros after the last input up to a multiple of 16 (the padded K of the first GEMM).
void nbrdf_t_input_pad(int r) {
  int n = int(nbrdf_w[NBRDF_W_INPUTS]), np = (n + 15) & ~15;
  for (int k = n; k < np; k++) {
    nbrdf_s_f16[NBRDF_T_AH + r * NBRDF_T_BPT + k] = float16_t(0.0);
    if (NBRDF_T_INW > 4) nbrdf_s_f16[nbrdf_t_inh() + r * nbrdf_t_inh_stride() + k] = float16_t(0.0);
  }
}

float nbrdf_tile_output_raw(int r) { return nbrdf_s_f32[NBRDF_T_X + r * NBRDF_T_XW]; }
#endif

// ------------------------------------------------------------------------ common ---

// The encoding features of row r (after its latent_dim latents), as nbrdf_decode_raw.
void nbrdf_tile_encode(int r, vec3 wi, vec3 wo) {
  int dim = nbrdf_latent_dim();
  vec3 a, b;
  nbrdf_encode_base(nbrdf_w[NBRDF_W_ENCODING], wi, wo, a, b);
  float base6[6] = float[6](a.x, a.y, a.z, b.x, b.y, b.z);
  for (int j = 0; j < 6; j++) nbrdf_tile_input(r, dim + j, base6[j]);
  int octaves = int(nbrdf_w[NBRDF_W_OCTAVES]);
  for (int k = 0; k < octaves; k++)
    for (int j = 0; j < 6; j++) {
      vec2 sc = nbrdf_encode_frequency(base6[j], k);
      nbrdf_tile_input(r, dim + 6 + 12 * k + 2 * j, sc.x);
      nbrdf_tile_input(r, dim + 7 + 12 * k + 2 * j, sc.y);
    }
  nbrdf_t_input_pad(r);
}

// Runs the network on the tile's inputs; the output stays in shared memory.
void nbrdf_tile_forward() {
  uint base = nbrdf_w[NBRDF_W_PARAMS];
  int n_layers = int(nbrdf_w[NBRDF_W_LAYERS]);
  int X = NBRDF_T_X, H = nbrdf_t_h(), IN = nbrdf_t_in();
  barrier(); // the inputs written by every invocation
  for (int l = 0; l < n_layers; l++) {
    NbrdfLayer L = nbrdf_layer(l);
    uint kind = L.kind;
    int n_in = L.n_in, n_out = L.n_out, hidden = L.hidden, skip_width = L.skip_width;
    bool has_skip = L.has_skip;
    uint w1 = L.w1, b1 = L.b1, g1 = L.g1, be1 = L.be1, w2 = L.w2, b2 = L.b2, g2 = L.g2,
         be2 = L.be2, wskip = L.wskip;
    bool projected = has_skip && wskip != NBRDF_NONE;
    int skip_add = has_skip && !projected ? IN : -1;
    // The fp16 copies (coop kernels, nbrdf_tile_f16_pack): w1, then w2, then wskip.
    int n1 = kind == NBRDF_RESIDUAL ? hidden : n_out;
    uint h1 = L.f16;
    uint h2 = h1 + uint(((n1 + 15) & ~15) * ((n_in + 15) & ~15) / 2);
    uint hs = kind == NBRDF_RESIDUAL ? h2 + uint(((n_out + 15) & ~15) * ((hidden + 15) & ~15) / 2)
                                     : h2;
    if (kind == NBRDF_LAYERNORM) {
      nbrdf_t_post(base, X, n_out, NBRDF_NONE, -1, g1, be1, NBRDF_T_LN);
    } else if (kind == NBRDF_RELU) {
      nbrdf_t_post(base, X, n_out, NBRDF_NONE, -1, NBRDF_NONE, NBRDF_NONE, NBRDF_T_RELU);
    } else if (kind == NBRDF_LINEAR || kind == NBRDF_PLAIN) {
      nbrdf_t_gemm_zero();
      nbrdf_t_gemm(base + w1, h1, X, n_in, n_out);
      if (projected) nbrdf_t_gemm(base + wskip, hs, IN, skip_width, n_out);
      nbrdf_t_gemm_store(X, n_out, false);
      nbrdf_t_post(base, X, n_out, b1, skip_add, g1, be1,
                   kind == NBRDF_PLAIN ? NBRDF_T_LN | NBRDF_T_RELU : 0);
    } else if (kind == NBRDF_RESIDUAL) {
      nbrdf_t_gemm_zero();
      nbrdf_t_gemm(base + w1, h1, X, n_in, hidden);
      nbrdf_t_gemm_store(H, hidden, false);
      nbrdf_t_post(base, H, hidden, b1, -1, g1, be1, NBRDF_T_LN | NBRDF_T_RELU);
      // y = ReLU(LN2(h W2^T + b2 + x (+ skip))): x is added in place.
#ifdef NBRDF_TILED_COOP
      nbrdf_t_gemm_load(X, n_out);
      nbrdf_t_gemm(base + w2, h2, H, hidden, n_out);
      if (projected) nbrdf_t_gemm(base + wskip, hs, IN, skip_width, n_out);
      nbrdf_t_gemm_store(X, n_out, false);
#else
      nbrdf_t_gemm_zero();
      nbrdf_t_gemm(base + w2, h2, H, hidden, n_out);
      if (projected) nbrdf_t_gemm(base + wskip, hs, IN, skip_width, n_out);
      nbrdf_t_gemm_store(X, n_out, true);
#endif
      nbrdf_t_post(base, X, n_out, b2, skip_add, g2, be2, NBRDF_T_LN | NBRDF_T_RELU);
    }
  }
}

float nbrdf_tile_output_f(int r) {
  float o = nbrdf_tile_output_raw(r);
  if (nbrdf_w[NBRDF_W_OUTPUT] == 1u) return nbrdf_expm1(min(max(o, 0.0), 80.0));
  return max(o, 0.0);
}

#endif
