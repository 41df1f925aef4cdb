/* Packing for the GLSL shaders in shaders/ (docs/SHADERS.md has the integration guide).
 *
 * Two storage buffers (std430, read as arrays of 32-bit words; floats are stored as
 * their IEEE bits and read with uintBitsToFloat):
 *
 * The DECODER buffer (shaders/nbrdf_decoder.glsl), little-endian uint32 words:
 *   header (NBRDF_GPU_HEADER_WORDS words, index names below), then one record of
 *   NBRDF_GPU_LAYER_WORDS words per layer:
 *     kind (1 linear, 2 layernorm, 3 relu, 4 plain, 5 residual), in, out, hidden,
 *     skip_from (0 = network input, NBRDF_GPU_NONE = none), skip_width,
 *     w1, b1, g1, be1, w2, b2, g2, be2, wskip (offsets in floats from the parameter
 *     start, NBRDF_GPU_NONE when absent), 0 (the tensor-core kernels' buffer puts the
 *     offset of the layer's fp16 weights there: shaders/nbrdf_tiled.h, nbrdf_tile_f16_pack);
 *   then the parameters, exactly the network's parameter array (the safetensors
 *   tensors in file order: weights [out x in] row-major, PyTorch's layout).
 * The shader is generic over this description; the only thing a pipeline must set is
 * the specialization constant NBRDF_MAX_WIDTH = words[NBRDF_GPU_W_MAX_WIDTH].
 *
 * The LATENT buffer (shaders/nbrdf_latent_fetch.glsl): a whole mip-mapped latent
 * texture as floats, texels in the library's logical order (per colour channel its
 * latents, then proxy sigma and w), levels row-major one after another, with a header
 * giving each level's size and word offset. */
#ifndef NBRDF_GPU_PACK_H
#define NBRDF_GPU_PACK_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/model.h"
#include "nbrdf/status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define NBRDF_GPU_DECODER_MAGIC 0x4752424eu /* "NBRG" */
#define NBRDF_GPU_LATENT_MAGIC 0x544c424eu  /* "NBLT" */
#define NBRDF_GPU_VERSION 1u
#define NBRDF_GPU_NONE 0xffffffffu

/* Decoder header words. */
#define NBRDF_GPU_W_MAGIC 0
#define NBRDF_GPU_W_VERSION 1
#define NBRDF_GPU_W_INPUTS 2     /* latent_dim + encoding width */
#define NBRDF_GPU_W_LAYERS 3     /* layer records */
#define NBRDF_GPU_W_LATENT_DIM 4 /* 32 */
#define NBRDF_GPU_W_ENCODING 5   /* 0 cartesian, 1 halfdiff */
#define NBRDF_GPU_W_OCTAVES 6    /* frequency octaves, 0..8 */
#define NBRDF_GPU_W_OUTPUT 7     /* 0 f = max(o, 0); 1 f = expm1(clamp(o, 0, 80)) */
#define NBRDF_GPU_W_OUTPUTS 8    /* network outputs (1) */
#define NBRDF_GPU_W_MAX_WIDTH 9  /* NBRDF_MAX_WIDTH: largest width, rounded up (gpu_pack.c) */
#define NBRDF_GPU_W_PARAMS 10    /* word offset of the parameters */
#define NBRDF_GPU_W_PARAM_COUNT 11
#define NBRDF_GPU_W_MACS 12 /* multiply-adds per query (saturated at 2^32 - 1) */
#define NBRDF_GPU_HEADER_WORDS 16
#define NBRDF_GPU_LAYER_WORDS 16

/* Latent header words; level l's record (width, height, word offset, 0) starts at word
 * NBRDF_GPU_L_HEADER_WORDS + 4 l, for l < NBRDF_GPU_L_MAX_LEVELS, then the texels. */
#define NBRDF_GPU_L_MAGIC 0
#define NBRDF_GPU_L_VERSION 1
#define NBRDF_GPU_L_CHANNELS 2 /* floats per texel */
#define NBRDF_GPU_L_LEVELS 3
#define NBRDF_GPU_L_LATENT_DIM 4
#define NBRDF_GPU_L_COLOURS 5 /* 1 (mono) or 3 (RGB) */
#define NBRDF_GPU_L_PROXY 6   /* 1 when sigma and w follow each colour's latents */
#define NBRDF_GPU_L_HEADER_WORDS 16
#define NBRDF_GPU_L_MAX_LEVELS 32
#define NBRDF_GPU_L_DATA (NBRDF_GPU_L_HEADER_WORDS + 4 * NBRDF_GPU_L_MAX_LEVELS)

/* Packs the model's decoder. For a latent texture, pass nbrdf_model_for_texture's model:
 * a texture of format version 2 is decoded with its own decoder. With words == NULL only
 * *n_words is set (the size to allocate); otherwise `capacity` words must suffice. Fails
 * (NBRDF_ERR_UNSUPPORTED) for a network the shader cannot run: a skip connection from
 * anything but the network input. */
nbrdf_status nbrdf_gpu_pack_decoder(const nbrdf_model *model, uint32_t *words, size_t capacity,
                                    size_t *n_words, nbrdf_error *err);

/* Packs a latent texture held in memory: `levels` levels of width[l] x height[l] texels
 * of `channels` floats each (data[l], row-major, logical order), for `colours` colour
 * channels of `latent_dim` latents with (proxy != 0) or without sigma and w each. Sizes
 * must follow the round-down mip chain of level 0. words == NULL: size query. */
nbrdf_status nbrdf_gpu_pack_latents(int levels, const int *width, const int *height, int channels,
                                    int latent_dim, int colours, int proxy,
                                    const float *const *data, uint32_t *words, size_t capacity,
                                    size_t *n_words, nbrdf_error *err);

#ifdef __cplusplus
}
#endif
#endif
