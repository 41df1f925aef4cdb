/* Internal side of include/nbrdf/gpu_pack.h: packs any decoder, not only a bundle's
 * (tests run custom encodings and presets through the shader with it). */
#ifndef NBRDF_MODEL_GPU_PACK_H
#define NBRDF_MODEL_GPU_PACK_H

#include "model/decoder.h"
#include "nbrdf/gpu_pack.h"

nbrdf_status model_gpu_pack_decoder(const model_decoder *dec, uint32_t *words, size_t capacity,
                                    size_t *n_words, nbrdf_error *err);

#endif
