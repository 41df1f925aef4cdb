/* Run-time loading of the Vulkan loader (gpu_vk.h). */
#include "gpu/gpu_vk.h"

#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

nbrdf_status gpu_vk_load(gpu_vk *vk, nbrdf_error *err) {
  memset(vk, 0, sizeof *vk);
  const char *name = getenv("NBRDF_VULKAN_LIBRARY");
  if (!name || !*name) name = "libvulkan.so.1";
  vk->lib = dlopen(name, RTLD_NOW | RTLD_LOCAL);
  if (!vk->lib) {
    const char *why = dlerror();
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "no Vulkan loader: cannot load %s (%s)", name,
                     why ? why : "unknown error");
  }
  /* dlsym returns void *; a function pointer is copied out of it bytewise (ISO C). */
  void *sym = dlsym(vk->lib, "vkGetInstanceProcAddr");
  if (sym) memcpy(&vk->vkGetInstanceProcAddr, &sym, sizeof sym);
  if (!vk->vkGetInstanceProcAddr) {
    dlclose(vk->lib);
    vk->lib = NULL;
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s has no vkGetInstanceProcAddr", name);
  }
  vk->vkCreateInstance =
      (PFN_vkCreateInstance)vk->vkGetInstanceProcAddr(VK_NULL_HANDLE, "vkCreateInstance");
  if (!vk->vkCreateInstance) {
    gpu_vk_unload(vk);
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s has no vkCreateInstance", name);
  }
  return NBRDF_OK;
}

nbrdf_status gpu_vk_load_instance(gpu_vk *vk, VkInstance instance, nbrdf_error *err) {
#define LOAD(name)                                                                                 \
  vk->name = (PFN_##name)vk->vkGetInstanceProcAddr(instance, #name);                              \
  if (!vk->name) return core_fail(err, NBRDF_ERR_UNSUPPORTED, "Vulkan: no entry point " #name);
  GPU_VK_INSTANCE_FUNCS(LOAD)
#undef LOAD
  vk->vkGetPhysicalDeviceCooperativeMatrixPropertiesNV =
      (PFN_vkGetPhysicalDeviceCooperativeMatrixPropertiesNV)vk->vkGetInstanceProcAddr(
          instance, "vkGetPhysicalDeviceCooperativeMatrixPropertiesNV");
  vk->vkGetPhysicalDeviceFeatures2 = (PFN_vkGetPhysicalDeviceFeatures2)vk->vkGetInstanceProcAddr(
      instance, "vkGetPhysicalDeviceFeatures2");
  return NBRDF_OK;
}

nbrdf_status gpu_vk_load_device(gpu_vk *vk, VkDevice device, nbrdf_error *err) {
#define LOAD(name)                                                                                 \
  vk->name = (PFN_##name)vk->vkGetDeviceProcAddr(device, #name);                                  \
  if (!vk->name) return core_fail(err, NBRDF_ERR_UNSUPPORTED, "Vulkan: no entry point " #name);
  GPU_VK_DEVICE_FUNCS(LOAD)
#undef LOAD
  return NBRDF_OK;
}

/* The loader stays mapped once loaded (dlopen counts references; a second context reuses it):
 * ICDs such as Mesa's keep process-wide state (LLVM's one-time initialisation, atexit
 * handlers) that must not be unmapped under them, and LeakSanitizer can only name, and so
 * suppress (tests/lsan.supp), a driver's one-time allocations while the driver is mapped. */
void gpu_vk_unload(gpu_vk *vk) { memset(vk, 0, sizeof *vk); }

const char *gpu_vk_result_name(VkResult r) {
  switch (r) {
  case VK_SUCCESS: return "VK_SUCCESS";
  case VK_NOT_READY: return "VK_NOT_READY";
  case VK_TIMEOUT: return "VK_TIMEOUT";
  case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
  case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
  case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
  case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
  case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
  case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
  case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
  case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
  default: return "VkResult error";
  }
}
