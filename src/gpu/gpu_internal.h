/* The Vulkan objects behind gpu.h's handles, shared by the files of src/gpu. */
#ifndef NBRDF_GPU_GPU_INTERNAL_H
#define NBRDF_GPU_GPU_INTERNAL_H

#include <pthread.h>

#include "gpu/gpu.h"
#include "gpu/gpu_plan.h"
#include "gpu/gpu_vk.h"

#define GPU_BINDINGS 5 /* x, params, y, add1, add2 */

typedef enum gpu_kernel { GPU_K_GEMM = 0, GPU_K_ROWNORM, GPU_K_GEMM_COOP, GPU_K_COUNT } gpu_kernel;

struct gpu_context {
  gpu_vk vk;
  VkInstance instance;
  VkPhysicalDevice physical;
  VkPhysicalDeviceProperties props;
  VkPhysicalDeviceMemoryProperties mem;
  VkDevice device;
  VkQueue queue;
  uint32_t family;
  pthread_mutex_t queue_lock; /* vkQueueSubmit needs the queue externally synchronised */
  VkDescriptorSetLayout set_layout;
  VkPipelineLayout layout;
  VkPipeline pipe[GPU_K_COUNT];
  /* GEMM tiles the fp32 pipeline was specialised with */
  int bm, bn, bk, tm, tn;
  /* nanoseconds per timestamp tick; 0 where the compute queue has no timestamps */
  double timestamp_ns;
  gpu_limits limits;
};

typedef struct gpu_buffer {
  VkBuffer buffer;
  VkDeviceMemory memory;
  VkDeviceSize size;
  void *map; /* host-visible buffers stay mapped */
  int coherent;
} gpu_buffer;

/* A device-local buffer (host_visible 0) or a mapped host buffer for uploads and readback. */
nbrdf_status gpu_buffer_create(gpu_context *ctx, VkDeviceSize size, int host_visible,
                               gpu_buffer *b, nbrdf_error *err);
void gpu_buffer_destroy(gpu_context *ctx, gpu_buffer *b);
/* Makes host writes visible to the device / device writes visible to the host (no-ops for
 * coherent memory). */
void gpu_buffer_flush(gpu_context *ctx, gpu_buffer *b);
void gpu_buffer_invalidate(gpu_context *ctx, gpu_buffer *b);

/* Pipelines of the embedded kernels (gpu_pipelines.c), called by gpu_context_open. */
nbrdf_status gpu_pipelines_create(gpu_context *ctx, nbrdf_error *err);
void gpu_pipelines_destroy(gpu_context *ctx);

/* Submits one recorded command buffer signalling `fence` (the queue lock held while
 * submitting); gpu_wait waits for the fence. */
nbrdf_status gpu_submit(gpu_context *ctx, VkCommandBuffer cmd, VkFence fence, nbrdf_error *err);
nbrdf_status gpu_wait(gpu_context *ctx, VkFence fence, nbrdf_error *err);


#endif
