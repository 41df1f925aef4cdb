/* The Vulkan entry points the GPU backend uses, loaded at run time: libnbrdf has no
 * link-time Vulkan dependency. gpu_vk_load dlopen()s the loader ($NBRDF_VULKAN_LIBRARY, else
 * libvulkan.so.1) and takes vkGetInstanceProcAddr from it; every other function comes through
 * vkGetInstanceProcAddr / vkGetDeviceProcAddr into a table owned by one gpu_context (no
 * global state). Only compiled with NBRDF_HAVE_GPU (Vulkan headers present at build time). */
#ifndef NBRDF_GPU_GPU_VK_H
#define NBRDF_GPU_GPU_VK_H

#define VK_NO_PROTOTYPES
#include <vulkan/vulkan.h>

#include "nbrdf/status.h"

#define GPU_VK_INSTANCE_FUNCS(X)                                                                   \
  X(vkDestroyInstance)                                                                             \
  X(vkEnumeratePhysicalDevices)                                                                    \
  X(vkGetPhysicalDeviceProperties)                                                                 \
  X(vkGetPhysicalDeviceMemoryProperties)                                                           \
  X(vkGetPhysicalDeviceQueueFamilyProperties)                                                      \
  X(vkEnumerateDeviceExtensionProperties)                                                          \
  X(vkCreateDevice)                                                                                \
  X(vkGetDeviceProcAddr)

#define GPU_VK_DEVICE_FUNCS(X)                                                                     \
  X(vkDestroyDevice)                                                                               \
  X(vkGetDeviceQueue)                                                                              \
  X(vkCreateBuffer)                                                                                \
  X(vkDestroyBuffer)                                                                               \
  X(vkGetBufferMemoryRequirements)                                                                 \
  X(vkAllocateMemory)                                                                              \
  X(vkFreeMemory)                                                                                  \
  X(vkBindBufferMemory)                                                                            \
  X(vkMapMemory)                                                                                   \
  X(vkUnmapMemory)                                                                                 \
  X(vkInvalidateMappedMemoryRanges)                                                                \
  X(vkFlushMappedMemoryRanges)                                                                     \
  X(vkCreateShaderModule)                                                                          \
  X(vkDestroyShaderModule)                                                                         \
  X(vkCreateDescriptorSetLayout)                                                                   \
  X(vkDestroyDescriptorSetLayout)                                                                  \
  X(vkCreatePipelineLayout)                                                                        \
  X(vkDestroyPipelineLayout)                                                                       \
  X(vkCreateComputePipelines)                                                                      \
  X(vkDestroyPipeline)                                                                             \
  X(vkCreateDescriptorPool)                                                                        \
  X(vkDestroyDescriptorPool)                                                                       \
  X(vkAllocateDescriptorSets)                                                                      \
  X(vkUpdateDescriptorSets)                                                                        \
  X(vkCreateCommandPool)                                                                           \
  X(vkDestroyCommandPool)                                                                          \
  X(vkAllocateCommandBuffers)                                                                      \
  X(vkBeginCommandBuffer)                                                                          \
  X(vkEndCommandBuffer)                                                                            \
  X(vkResetCommandBuffer)                                                                          \
  X(vkCmdBindPipeline)                                                                             \
  X(vkCmdBindDescriptorSets)                                                                       \
  X(vkCmdPushConstants)                                                                            \
  X(vkCmdDispatch)                                                                                 \
  X(vkCmdPipelineBarrier)                                                                          \
  X(vkCmdCopyBuffer)                                                                               \
  X(vkQueueSubmit)                                                                                 \
  X(vkCreateFence)                                                                                 \
  X(vkDestroyFence)                                                                                \
  X(vkWaitForFences)                                                                               \
  X(vkResetFences)                                                                                 \
  X(vkDeviceWaitIdle)                                                                              \
  X(vkCreateQueryPool)                                                                             \
  X(vkDestroyQueryPool)                                                                            \
  X(vkCmdResetQueryPool)                                                                           \
  X(vkCmdWriteTimestamp)                                                                           \
  X(vkGetQueryPoolResults)

#define GPU_VK_MEMBER(name) PFN_##name name;

typedef struct gpu_vk {
  void *lib; /* the dlopen()ed loader */
  PFN_vkGetInstanceProcAddr vkGetInstanceProcAddr;
  PFN_vkCreateInstance vkCreateInstance;
  GPU_VK_INSTANCE_FUNCS(GPU_VK_MEMBER)
  GPU_VK_DEVICE_FUNCS(GPU_VK_MEMBER)
  /* VK_NV_cooperative_matrix (NULL where the instance lacks it) */
  PFN_vkGetPhysicalDeviceCooperativeMatrixPropertiesNV vkGetPhysicalDeviceCooperativeMatrixPropertiesNV;
  PFN_vkGetPhysicalDeviceFeatures2 vkGetPhysicalDeviceFeatures2;
} gpu_vk;

/* Opens the loader and fills vkGetInstanceProcAddr and vkCreateInstance; the message names the
 * library and dlerror() when it cannot be loaded. */
nbrdf_status gpu_vk_load(gpu_vk *vk, nbrdf_error *err);
/* After vkCreateInstance: the instance-level functions. */
nbrdf_status gpu_vk_load_instance(gpu_vk *vk, VkInstance instance, nbrdf_error *err);
/* After vkCreateDevice: the device-level functions. */
nbrdf_status gpu_vk_load_device(gpu_vk *vk, VkDevice device, nbrdf_error *err);
void gpu_vk_unload(gpu_vk *vk);

/* "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc. */
const char *gpu_vk_result_name(VkResult r);

#endif
