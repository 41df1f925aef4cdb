/* A model's networks on a GPU (src/gpu) for the callers that hand them big batches: the bake
 * (layering, sampler, the energy audit's decoder), later verify/render/eval (decoder). */
#ifndef NBRDF_MODEL_MODEL_GPU_H
#define NBRDF_MODEL_MODEL_GPU_H

#include <stddef.h>

#include "gpu/gpu.h"
#include "model/netio.h"
#include "nbrdf/model.h"

typedef struct model_gpu {
  gpu_context *ctx;
  gpu_network *layering, *sampler, *decoder; /* NULL where not asked for */
  /* Rows to hand a network per call: the GPU networks' chunk (tens to hundreds of thousands
   * of rows) on a GPU, a few hundred on a CPU device (lavapipe), so that cancel stays
   * responsive. */
  size_t batch;
} model_gpu;

enum { MODEL_GPU_LAYERING = 1, MODEL_GPU_SAMPLER = 2, MODEL_GPU_DECODER = 4 };

/* Uploads the networks `nets` (MODEL_GPU_* bits) of `model` (the decoder of `decoder_model`
 * when non-NULL) for `device`:
 * - CPU: *out = NULL, note "";
 * - AUTO: the GPU, or *out = NULL when there is none (or it fails), note saying why;
 * - GPU: the GPU, else an error naming why.
 * `note` (one line, may be NULL) says where the networks run. */
nbrdf_status model_gpu_open(const nbrdf_model *model, const nbrdf_model *decoder_model,
                            nbrdf_device device, unsigned nets, model_gpu **out, char *note,
                            size_t note_size, nbrdf_error *err);
void model_gpu_close(model_gpu *g);

/* nbrdf_model_decode with the decoder on `gpu` (the same checks; NULL: the CPU). */
nbrdf_status model_decode_on(const nbrdf_model *m, struct gpu_network *gpu, size_t n, int channels,
                             const float *latents, const float *wi, const float *wo, float *f,
                             nbrdf_error *err);

/* A runner that runs `gpu` (no CPU workspace) with input/output buffers of max_batch rows. */
nbrdf_status model_gpu_runner(gpu_network *gpu, int max_batch, model_runner *runner,
                              nbrdf_error *err);

#endif
