// nbrdf shaders: the decoder network, f(latent, ωi, ωo) without the cosine (GLSL 450).
//
// GENERIC over the architecture: the network is read from the weights buffer written by
// nbrdf_gpu_pack_decoder (include/nbrdf/gpu_pack.h, docs/SHADERS.md), so one compiled
// shader runs every preset and any trained bundle. The only compile-time knob is the
// specialization constant NBRDF_MAX_WIDTH (the size of the per-invocation activation
// arrays); set it at pipeline creation to header word NBRDF_W_MAX_WIDTH of the buffer
// (exactly the largest width the network needs), e.g. 32 for the `small` preset, 256 for
// `paper`. A larger value works, a smaller one reads out of bounds.
//
// Math (src/nn/nn.h, bit-for-bit the same operations up to summation order):
//   LINEAR    y = x W^T + b (+ skip)
//   LAYERNORM y = (x - mean) / sqrt(var + 1e-5) * gamma + beta   (biased variance)
//   PLAIN     y = ReLU(LN(x W^T + b (+ skip)))
//   RESIDUAL  h = ReLU(LN1(x W1^T + b1)); y = ReLU(LN2(h W2^T + b2 + x (+ skip)))
// Skip connections are supported from the network input only (the packer refuses others).
// Output transform: f = max(o, 0) (`f`), or f = expm1(clamp(o, 0, 80)) (`log1p`).
//
// Use:
//   #define NBRDF_WEIGHTS_BINDING 0   // optional: set / binding / constant_id of your own
//   #include "nbrdf_decoder.glsl"
//   for (int i = 0; i < nbrdf_latent_dim(); i++) nbrdf_decoder_set_latent(i, latent[i]);
//   float f = nbrdf_decode(wi, wo);
// A decode costs nbrdf_w[NBRDF_W_MACS] multiply-adds (one colour channel).
#ifndef NBRDF_DECODER_GLSL
#define NBRDF_DECODER_GLSL

#include "nbrdf_encoding.glsl"

#include "nbrdf_weights.glsl"

#ifndef NBRDF_MAX_WIDTH_ID
#define NBRDF_MAX_WIDTH_ID 0
#endif

layout(constant_id = NBRDF_MAX_WIDTH_ID) const int NBRDF_MAX_WIDTH = 256;

// Per-invocation activations: 0 and 1 ping-pong, 2 the network input (kept for skips),
// 3 a residual block's hidden layer.
float nbrdf_act[4][NBRDF_MAX_WIDTH];
const int NBRDF_BUF_INPUT = 2, NBRDF_BUF_HIDDEN = 3;

void nbrdf_decoder_set_latent(int i, float v) { nbrdf_act[NBRDF_BUF_INPUT][i] = v; }

// act[dst][o] (+)= sum_j W[o][j] act[src][j], W row-major [out x in] at float offset w.
// Four outputs share each loaded input (register blocking) and the inner loop takes 8
// inputs per iteration. Besides the usual GPU benefit this keeps the total loop count far
// below Mesa llvmpipe's limit of 65535 loop iterations per invocation, shared by all loops
// (LP_MAX_TGSI_LOOP_ITERATIONS): past it lavapipe silently ends loops early. The `paper`
// decoder (1.06 M MACs) takes about 40 k iterations this way. Each output still sums in
// input order, as one dot product.
void nbrdf_gemv(uint base, uint w, int src, int dst, int n_in, int n_out, bool accumulate) {
  int o = 0;
  for (; o + 4 <= n_out; o += 4) {
    uint r0 = base + w + uint(o * n_in), r1 = r0 + uint(n_in), r2 = r1 + uint(n_in),
         r3 = r2 + uint(n_in);
    vec4 s = accumulate ? vec4(nbrdf_act[dst][o], nbrdf_act[dst][o + 1], nbrdf_act[dst][o + 2],
                               nbrdf_act[dst][o + 3])
                        : vec4(0.0);
    int j = 0;
    for (; j + 8 <= n_in; j += 8)
      for (int t = 0; t < 8; t++) { // constant trip count: unrolled by the compiler
        float x = nbrdf_act[src][j + t];
        uint at = uint(j + t);
        s.x += nbrdf_wf(r0 + at) * x;
        s.y += nbrdf_wf(r1 + at) * x;
        s.z += nbrdf_wf(r2 + at) * x;
        s.w += nbrdf_wf(r3 + at) * x;
      }
    for (; j < n_in; j++) {
      float x = nbrdf_act[src][j];
      s.x += nbrdf_wf(r0 + uint(j)) * x;
      s.y += nbrdf_wf(r1 + uint(j)) * x;
      s.z += nbrdf_wf(r2 + uint(j)) * x;
      s.w += nbrdf_wf(r3 + uint(j)) * x;
    }
    nbrdf_act[dst][o] = s.x;
    nbrdf_act[dst][o + 1] = s.y;
    nbrdf_act[dst][o + 2] = s.z;
    nbrdf_act[dst][o + 3] = s.w;
  }
  for (; o < n_out; o++) {
    uint row = base + w + uint(o * n_in);
    float s = accumulate ? nbrdf_act[dst][o] : 0.0;
    int j = 0;
    for (; j + 8 <= n_in; j += 8)
      for (int t = 0; t < 8; t++) s += nbrdf_wf(row + uint(j + t)) * nbrdf_act[src][j + t];
    for (; j < n_in; j++) s += nbrdf_wf(row + uint(j)) * nbrdf_act[src][j];
    nbrdf_act[dst][o] = s;
  }
}

// In place on act[buf][0..n): u += bias + act[add1] + act[add2] (each optional, -1/NONE =
// none), then LayerNorm with gamma/beta and an optional ReLU (nn_ln_forward's order).
// Loops go 4 columns at a time for the loop budget above.
void nbrdf_norm(uint base, int buf, int n, uint bias, int add1, int add2, uint gamma, uint beta,
                bool relu) {
  float sum = 0.0;
  for (int c0 = 0; c0 < n; c0 += 4)
    for (int t = 0; t < 4; t++) { // constant trip count: unrolled by the compiler
      int c = c0 + t;
      if (c >= n) break;
      float v = nbrdf_act[buf][c];
      if (bias != NBRDF_NONE) v = v + nbrdf_param(base, bias + uint(c));
      if (add1 >= 0) v = v + nbrdf_act[add1][c];
      if (add2 >= 0) v = v + nbrdf_act[add2][c];
      nbrdf_act[buf][c] = v;
      sum += v;
    }
  float mean = sum / float(n);
  float ss = 0.0;
  for (int c0 = 0; c0 < n; c0 += 4)
    for (int t = 0; t < 4; t++) { // constant trip count: unrolled by the compiler
      int c = c0 + t;
      if (c >= n) break;
      float d = nbrdf_act[buf][c] - mean;
      ss += d * d;
    }
  float rs = 1.0 / sqrt(ss / float(n) + 1e-5);
  for (int c0 = 0; c0 < n; c0 += 4)
    for (int t = 0; t < 4; t++) { // constant trip count: unrolled by the compiler
      int c = c0 + t;
      if (c >= n) break;
      float v = (nbrdf_act[buf][c] - mean) * rs * nbrdf_param(base, gamma + uint(c)) +
                nbrdf_param(base, beta + uint(c));
      nbrdf_act[buf][c] = relu ? max(v, 0.0) : v;
    }
}

// Runs the network on act[NBRDF_BUF_INPUT]; returns the buffer holding the output.
// Every layer is up to three steps of (matrix-vector product, LayerNorm), so that the
// shader has ONE call site of each: the inlined code stays small, which matters for
// compile time (lavapipe's LLVM took tens of seconds on the unrolled form with a call
// site per layer kind) and for instruction caches on GPUs.
int nbrdf_network_forward() {
  uint base = nbrdf_w[NBRDF_W_PARAMS];
  int n_layers = int(nbrdf_w[NBRDF_W_LAYERS]);
  int src = NBRDF_BUF_INPUT;
  for (int l = 0; l < n_layers; l++) {
    NbrdfLayer L = nbrdf_layer(l);
    uint kind = L.kind;
    int n_in = L.n_in, n_out = L.n_out, hidden = L.hidden, skip_width = L.skip_width;
    bool has_skip = L.has_skip;
    uint w1 = L.w1, b1 = L.b1, g1 = L.g1, be1 = L.be1, w2 = L.w2, b2 = L.b2, g2 = L.g2,
         be2 = L.be2, wskip = L.wskip;
    int dst = src == 0 ? 1 : 0;
    bool projected = has_skip && wskip != NBRDF_NONE;
    int skip_add = has_skip && !projected ? NBRDF_BUF_INPUT : -1;
    bool dense = kind == NBRDF_LINEAR || kind == NBRDF_PLAIN;
    if (kind == NBRDF_LAYERNORM || kind == NBRDF_RELU)
      for (int c = 0; c < n_out; c++)
        nbrdf_act[dst][c] = kind == NBRDF_RELU ? max(nbrdf_act[src][c], 0.0) : nbrdf_act[src][c];
    for (int step = 0; step < 3; step++) {
      // Matrix-vector step: W (from -> to), n_in -> n_out, accumulate into `to`?
      uint gw = NBRDF_NONE;
      int from = src, to = dst, gin = n_in, gout = n_out;
      bool acc = false;
      // LayerNorm step on buffer nb: bias, two additions, gamma, beta, ReLU.
      int nb = -1, nn = n_out, a1 = -1, a2 = -1;
      uint nbias = NBRDF_NONE, ng = NBRDF_NONE, nbe = NBRDF_NONE;
      bool relu = true;
      if (step == 0 && projected && kind != NBRDF_RESIDUAL) {
        gw = wskip, from = NBRDF_BUF_INPUT, gin = skip_width;
      } else if (step == 1 && dense) {
        gw = w1, acc = projected;
        if (kind == NBRDF_PLAIN) nb = dst, nbias = b1, a1 = skip_add, ng = g1, nbe = be1;
      } else if (step == 0 && kind == NBRDF_RESIDUAL) {
        gw = w1, to = NBRDF_BUF_HIDDEN, gout = hidden;
        nb = NBRDF_BUF_HIDDEN, nn = hidden, nbias = b1, ng = g1, nbe = be1;
      } else if (step == 1 && kind == NBRDF_RESIDUAL && projected) {
        gw = wskip, from = NBRDF_BUF_INPUT, gin = skip_width;
      } else if (step == 2 && kind == NBRDF_RESIDUAL) {
        // The block's input is added before normalisation and activation (paper Fig. 3).
        gw = w2, from = NBRDF_BUF_HIDDEN, gin = hidden, acc = projected;
        nb = dst, nbias = b2, a1 = src, a2 = skip_add, ng = g2, nbe = be2;
      } else if (step == 0 && kind == NBRDF_LAYERNORM) {
        nb = dst, ng = g1, nbe = be1, relu = false;
      }
      if (gw != NBRDF_NONE) nbrdf_gemv(base, gw, from, to, gin, gout, acc);
      if (nb >= 0) nbrdf_norm(base, nb, nn, nbias, a1, a2, ng, nbe, relu);
    }
    if (kind == NBRDF_LINEAR)
      for (int o = 0; o < n_out; o++) {
        float v = nbrdf_act[dst][o] + nbrdf_param(base, b1 + uint(o));
        if (skip_add >= 0) v = v + nbrdf_act[skip_add][o];
        nbrdf_act[dst][o] = v;
      }
    src = dst;
  }
  return src;
}

// Raw network output o for the latent set with nbrdf_decoder_set_latent and (ωi, ωo).
float nbrdf_decode_raw(vec3 wi, vec3 wo) {
  int dim = nbrdf_latent_dim();
  vec3 a, b;
  nbrdf_encode_base(nbrdf_w[NBRDF_W_ENCODING], wi, wo, a, b);
  float base6[6] = float[6](a.x, a.y, a.z, b.x, b.y, b.z);
  for (int j = 0; j < 6; j++) nbrdf_act[NBRDF_BUF_INPUT][dim + j] = base6[j];
  int octaves = int(nbrdf_w[NBRDF_W_OCTAVES]);
  for (int k = 0; k < octaves; k++)
    for (int j = 0; j < 6; j++) {
      vec2 sc = nbrdf_encode_frequency(base6[j], k);
      nbrdf_act[NBRDF_BUF_INPUT][dim + 6 + 12 * k + 2 * j] = sc.x;
      nbrdf_act[NBRDF_BUF_INPUT][dim + 7 + 12 * k + 2 * j] = sc.y;
    }
  return nbrdf_act[nbrdf_network_forward()][0];
}

// f from the raw output o (MODEL_OUTPUT_F / MODEL_OUTPUT_LOG1P of src/model/decoder.h).
float nbrdf_decoder_output(float o) {
  if (nbrdf_w[NBRDF_W_OUTPUT] == 1u) return nbrdf_expm1(min(max(o, 0.0), 80.0));
  return max(o, 0.0);
}

// f(ωi, ωo) >= 0 without the cosine factor.
float nbrdf_decode(vec3 wi, vec3 wo) { return nbrdf_decoder_output(nbrdf_decode_raw(wi, wo)); }

#endif
