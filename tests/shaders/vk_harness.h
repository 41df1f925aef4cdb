/* A minimal headless Vulkan compute harness for the shader tests and bench_shader:
 * instance, device selection, host-visible storage buffers, one compute pipeline per
 * SPIR-V kernel, and a synchronous dispatch. Nothing here knows about BRDFs.
 *
 * Device selection: $NBRDF_VK_DEVICE, when set, picks the first device whose name
 * contains it ("llvmpipe", "NVIDIA", ...); otherwise the first CPU device (Mesa's
 * lavapipe, so that tests run the same everywhere), else the first device. Kernels are
 * loaded from NBRDF_SPIRV_DIR (the build's shaders/ folder) or $NBRDF_SPIRV_DIR. */
#ifndef NBRDF_TESTS_VK_HARNESS_H
#define NBRDF_TESTS_VK_HARNESS_H

#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

typedef struct vkh vkh;

typedef struct vkh_buffer {
  VkBuffer buffer;
  VkDeviceMemory memory;
  void *map; /* persistently mapped, coherent */
  size_t bytes;
} vkh_buffer;

#define VKH_MAX_BINDINGS 8

typedef struct vkh_kernel {
  VkShaderModule module;
  VkDescriptorSetLayout set_layout;
  VkPipelineLayout layout;
  VkPipeline pipeline;
  VkDescriptorPool pool;
  VkDescriptorSet set;
  int n_buffers;
  uint32_t push_bytes;
} vkh_kernel;

/* 0 on success; on failure -1 and a message in msg. */
int vkh_open(vkh **out, char *msg, size_t msg_size);
void vkh_close(vkh *ctx);
const char *vkh_device_name(const vkh *ctx);
int vkh_device_is_cpu(const vkh *ctx);
/* Limits the tiled kernels are sized by (shaders/nbrdf_tiled.h), the subgroup size, and
 * whether the cooperative-matrix kernels (nbrdf_*_coop.spv) can be loaded: the device has
 * VK_NV_cooperative_matrix with a 16x16x16 fp16 x fp16 + fp32 subgroup shape, shaderFloat16
 * and vulkanMemoryModel (enabled at vkh_open), and subgroups of 32. Lavapipe has none. */
uint32_t vkh_max_shared(const vkh *ctx);
uint32_t vkh_max_invocations(const vkh *ctx);
uint32_t vkh_subgroup_size(const vkh *ctx);
int vkh_has_coop(const vkh *ctx);
/* shaderFloat16 enabled and quad subgroup operations: the emulated tensor-core kernels
 * (nbrdf_*_coopemu.spv, tests only) can run (lavapipe can). */
int vkh_has_f16(const vkh *ctx);
/* The last failure's message. */
const char *vkh_error(const vkh *ctx);

int vkh_buffer_create(vkh *ctx, size_t bytes, vkh_buffer *b);
void vkh_buffer_destroy(vkh *ctx, vkh_buffer *b);

/* Kernel `spv_name` (e.g. "nbrdf_decode.spv") with storage buffers at bindings
 * 0..n_buffers-1, `push_bytes` of push constants, and specialization constants
 * 0..n_spec-1 = spec[] (32-bit each). */
int vkh_kernel_create(vkh *ctx, const char *spv_name, int n_buffers, uint32_t push_bytes,
                      int n_spec, const uint32_t *spec, vkh_kernel *k);
void vkh_kernel_destroy(vkh *ctx, vkh_kernel *k);
/* Binds buffers[i] to binding i. */
void vkh_kernel_bind(vkh *ctx, vkh_kernel *k, vkh_buffer *const *buffers);
/* Dispatches `groups` workgroups along x (split into several dispatches above the
 * device's limit) and waits; *seconds (may be NULL) gets the wall time of submit + wait. */
int vkh_run(vkh *ctx, vkh_kernel *k, const void *push, uint32_t groups, double *seconds);
/* `reps` dispatches in one submission, serialised by barriers; *seconds = the time per
 * dispatch from GPU timestamps (vkCmdWriteTimestamp x timestampPeriod; *from_timestamps =
 * 1), else the wall time of submit + wait / reps (*from_timestamps = 0). */
int vkh_time(vkh *ctx, vkh_kernel *k, const void *push, uint32_t groups, int reps,
             double *seconds, int *from_timestamps);

#endif
