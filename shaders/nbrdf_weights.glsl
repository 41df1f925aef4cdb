// nbrdf shaders: the packed decoder buffer (include/nbrdf/gpu_pack.h) as GLSL: header word
// indices, layer kinds and the storage-buffer declaration. Shared by the per-invocation
// decoder (nbrdf_decoder.glsl) and the tiled ones (nbrdf_tiled.glsl).
#ifndef NBRDF_WEIGHTS_GLSL
#define NBRDF_WEIGHTS_GLSL

#ifndef NBRDF_WEIGHTS_SET
#define NBRDF_WEIGHTS_SET 0
#endif
#ifndef NBRDF_WEIGHTS_BINDING
#define NBRDF_WEIGHTS_BINDING 0
#endif

// Header words (include/nbrdf/gpu_pack.h has the same numbers).
const uint NBRDF_W_MAGIC = 0u;      // 0x4752424e, "NBRG"
const uint NBRDF_W_VERSION = 1u;    // 1
const uint NBRDF_W_INPUTS = 2u;     // latent_dim + encoding width
const uint NBRDF_W_LAYERS = 3u;     // number of layer records
const uint NBRDF_W_LATENT_DIM = 4u; // 32
const uint NBRDF_W_ENCODING = 5u;   // 0 cartesian, 1 halfdiff
const uint NBRDF_W_OCTAVES = 6u;    // frequency octaves
const uint NBRDF_W_OUTPUT = 7u;     // 0 f, 1 log1p
const uint NBRDF_W_OUTPUTS = 8u;    // network outputs (1)
const uint NBRDF_W_MAX_WIDTH = 9u;  // the NBRDF_MAX_WIDTH this network needs
const uint NBRDF_W_PARAMS = 10u;    // word offset of the parameters
const uint NBRDF_W_PARAM_COUNT = 11u;
const uint NBRDF_W_MACS = 12u;      // multiply-adds per query
const uint NBRDF_W_HEADER = 16u;    // header words; then 16 words per layer
const uint NBRDF_W_LAYER_WORDS = 16u;
// Layer record words: kind, in, out, hidden, skip_from, skip_width, then parameter
// offsets (floats from the parameter start; NBRDF_NONE when absent) w1 b1 g1 be1 w2 b2 g2
// be2 wskip.
const uint NBRDF_NONE = 0xffffffffu;
const uint NBRDF_LINEAR = 1u, NBRDF_LAYERNORM = 2u, NBRDF_RELU = 3u, NBRDF_PLAIN = 4u,
           NBRDF_RESIDUAL = 5u;

layout(std430, set = NBRDF_WEIGHTS_SET, binding = NBRDF_WEIGHTS_BINDING) readonly buffer
    NbrdfWeights {
  uint nbrdf_w[];
};

int nbrdf_latent_dim() { return int(nbrdf_w[NBRDF_W_LATENT_DIM]); }

float nbrdf_param(uint base, uint i) { return uintBitsToFloat(nbrdf_w[base + i]); }

float nbrdf_wf(uint at) { return uintBitsToFloat(nbrdf_w[at]); }

// One layer record of the packed buffer (the words above), as both decoders read it.
struct NbrdfLayer {
  uint kind;
  int n_in, n_out, hidden, skip_width;
  bool has_skip;
  uint w1, b1, g1, be1, w2, b2, g2, be2, wskip;
  uint f16; // word 15: the fp16 copies of the weights (tensor-core kernels), 0 when none
};

NbrdfLayer nbrdf_layer(int l) {
  uint r = NBRDF_W_HEADER + NBRDF_W_LAYER_WORDS * uint(l);
  NbrdfLayer L;
  L.kind = nbrdf_w[r];
  L.n_in = int(nbrdf_w[r + 1u]);
  L.n_out = int(nbrdf_w[r + 2u]);
  L.hidden = int(nbrdf_w[r + 3u]);
  L.has_skip = nbrdf_w[r + 4u] != NBRDF_NONE;
  L.skip_width = int(nbrdf_w[r + 5u]);
  L.w1 = nbrdf_w[r + 6u], L.b1 = nbrdf_w[r + 7u], L.g1 = nbrdf_w[r + 8u], L.be1 = nbrdf_w[r + 9u];
  L.w2 = nbrdf_w[r + 10u], L.b2 = nbrdf_w[r + 11u], L.g2 = nbrdf_w[r + 12u];
  L.be2 = nbrdf_w[r + 13u], L.wskip = nbrdf_w[r + 14u];
  L.f16 = nbrdf_w[r + 15u];
  return L;
}

#endif
