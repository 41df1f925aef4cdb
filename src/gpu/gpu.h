/* Network inference on a GPU through Vulkan compute (docs/GPU.md).
 *
 * - gpu_context: one Vulkan instance + device + compute queue, the kernels' pipelines and the
 *   device's limits. The Vulkan loader is dlopen()ed at run time (gpu_vk.h); in a build
 *   without glslang/Vulkan headers (or -DNBRDF_BUILD_SHADERS=OFF) every open fails with
 *   "built without GPU support".
 * - gpu_network: one nn_network's weights uploaded once, its activations on the device for
 *   a chunk of rows, one command buffer per chunk (every layer's GEMM and row kernels with
 *   pipeline barriers between them). gpu_network_forward takes any number of rows from host
 *   memory to host memory and streams them through in chunks.
 *
 * No global mutable state: everything lives in the handles. A context may be shared by
 * several networks used from different threads (queue submissions are serialised by the
 * context); one network is used by one thread at a time. Every fallible call returns
 * nbrdf_status with a message. */
#ifndef NBRDF_GPU_GPU_H
#define NBRDF_GPU_GPU_H

#include <stddef.h>
#include <stdint.h>

#include "nbrdf/status.h"
#include "nn/nn.h"

typedef struct gpu_context gpu_context;
typedef struct gpu_network gpu_network;

/* Which device gpu_context_open takes. NBRDF_VK_DEVICE (a substring of the device name, e.g.
 * "llvmpipe" for lavapipe, "NVIDIA") names one for either choice. */
typedef enum gpu_choice {
  GPU_CHOICE_AUTO = 0, /* else the first discrete GPU, else the first integrated one; never a
                          CPU device (lavapipe) unless named */
  GPU_CHOICE_GPU = 1   /* else the first GPU of any kind (discrete, integrated, virtual) */
} gpu_choice;

typedef struct gpu_limits {
  uint32_t shared_bytes;     /* maxComputeSharedMemorySize */
  uint32_t max_invocations;  /* maxComputeWorkGroupInvocations */
  uint32_t max_groups[3];    /* maxComputeWorkGroupCount */
  uint64_t max_buffer_bytes; /* maxStorageBufferRange */
  uint64_t device_bytes;     /* the largest device-local heap */
  int coop_matrix;           /* VK_NV_cooperative_matrix with fp16 16x16x16 -> fp32, enabled */
  char coop_note[160];       /* why not (or "enabled"), for reports */
} gpu_limits;

/* 1 when this build has the Vulkan backend (whether or not a device exists). */
int gpu_built(void);

/* Opens the chosen device. Fails with NBRDF_ERR_UNSUPPORTED (message saying why: no loader,
 * no device, none named so, built without GPU support) when there is none to take. */
nbrdf_status gpu_context_open(gpu_choice choice, gpu_context **out, nbrdf_error *err);
void gpu_context_close(gpu_context *ctx);
const char *gpu_context_name(const gpu_context *ctx);
/* 1 for a CPU implementation (lavapipe). */
int gpu_context_is_cpu(const gpu_context *ctx);
const gpu_limits *gpu_context_limits(const gpu_context *ctx);

typedef enum gpu_precision {
  GPU_FP32 = 0,      /* fp32 GEMMs: agrees with the CPU within float rounding */
  GPU_FP16_COOP = 1  /* tensor cores (GL_NV_cooperative_matrix): fp16 inputs and weights, fp32
                        accumulation; NBRDF_ERR_UNSUPPORTED where the device lacks it */
} gpu_precision;

/* Uploads `nn` (copied: the network may be destroyed afterwards) with buffers for chunks of
 * up to gpu_network_chunk_rows rows (chosen from the device's memory; max_rows > 0 caps it). */
nbrdf_status gpu_network_create(gpu_context *ctx, const nn_network *nn, gpu_precision precision,
                                int max_rows, gpu_network **out, nbrdf_error *err);
void gpu_network_destroy(gpu_network *net);
int gpu_network_chunk_rows(const gpu_network *net);
int gpu_network_inputs(const gpu_network *net);
int gpu_network_outputs(const gpu_network *net);

/* y[rows x outputs] = network(x[rows x inputs]), in chunks (one submission each). */
nbrdf_status gpu_network_forward(gpu_network *net, const float *x, size_t rows, float *y,
                                 nbrdf_error *err);
/* Seconds the device spent in the last forward's kernels (GPU timestamps around the layers
 * of each chunk, the host copies and uploads excluded); < 0 where the queue has none. */
double gpu_network_device_seconds(const gpu_network *net);

#endif
