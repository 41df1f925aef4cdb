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

#endif
