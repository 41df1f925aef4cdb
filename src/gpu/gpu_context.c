/* gpu_context: loader, instance, device choice, queue (gpu.h). */
#include "gpu/gpu.h"

#if NBRDF_HAVE_GPU
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/gpu_internal.h"

int gpu_built(void) { return 1; }

static const char *type_name(VkPhysicalDeviceType t) {
  switch (t) {
  case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
  case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
  case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
  case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
  default: return "other";
  }
}

/* Rank of a device for the choice (higher is better; 0 = not taken). */
static int rank(gpu_choice choice, VkPhysicalDeviceType t) {
  if (t == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU) return 3;
  if (t == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU) return 2;
  if (t == VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU && choice == GPU_CHOICE_GPU) return 1;
  return 0;
}

static nbrdf_status pick_device(gpu_context *c, gpu_choice choice, nbrdf_error *err) {
  uint32_t n = 0;
  if (c->vk.vkEnumeratePhysicalDevices(c->instance, &n, NULL) != VK_SUCCESS || n == 0)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "no Vulkan device");
  VkPhysicalDevice devs[16];
  if (n > 16) n = 16;
  c->vk.vkEnumeratePhysicalDevices(c->instance, &n, devs);
  const char *want = getenv("NBRDF_VK_DEVICE");
  int chosen = -1, best = 0;
  char seen[256] = "";
  for (uint32_t i = 0; i < n; i++) {
    VkPhysicalDeviceProperties p;
    c->vk.vkGetPhysicalDeviceProperties(devs[i], &p);
    size_t len = strlen(seen);
    if (len + strlen(p.deviceName) + 24 < sizeof seen) {
      if (len) strcat(seen, ", ");
      strcat(seen, p.deviceName);
      strcat(seen, " (");
      strcat(seen, type_name(p.deviceType));
      strcat(seen, ")");
    }
    if (want && *want) {
      if (chosen < 0 && strstr(p.deviceName, want)) chosen = (int)i;
    } else if (rank(choice, p.deviceType) > best) {
      best = rank(choice, p.deviceType);
      chosen = (int)i;
    }
  }
  if (chosen < 0 && want && *want)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                     "no Vulkan device name contains NBRDF_VK_DEVICE=\"%s\" (devices: %s)", want,
                     seen);
  if (chosen < 0)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "no GPU among the Vulkan devices (%s)%s", seen,
                     choice == GPU_CHOICE_GPU ? "; NBRDF_VK_DEVICE=llvmpipe takes lavapipe" : "");
  c->physical = devs[chosen];
  c->vk.vkGetPhysicalDeviceProperties(c->physical, &c->props);
  c->vk.vkGetPhysicalDeviceMemoryProperties(c->physical, &c->mem);
  uint32_t nf = 0;
  c->vk.vkGetPhysicalDeviceQueueFamilyProperties(c->physical, &nf, NULL);
  VkQueueFamilyProperties fam[16];
  if (nf > 16) nf = 16;
  c->vk.vkGetPhysicalDeviceQueueFamilyProperties(c->physical, &nf, fam);
  for (uint32_t f = 0; f < nf; f++)
    if (fam[f].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      c->family = f;
      c->timestamp_ns = fam[f].timestampValidBits ? (double)c->props.limits.timestampPeriod : 0.0;
      return NBRDF_OK;
    }
  return core_fail(err, NBRDF_ERR_UNSUPPORTED, "%s has no compute queue", c->props.deviceName);
}

static int has_extension(gpu_context *c, const char *name) {
  uint32_t n = 0;
  if (c->vk.vkEnumerateDeviceExtensionProperties(c->physical, NULL, &n, NULL) != VK_SUCCESS)
    return 0;
  VkExtensionProperties *e = malloc(sizeof *e * (n ? n : 1));
  if (!e) return 0;
  int found = 0;
  if (c->vk.vkEnumerateDeviceExtensionProperties(c->physical, NULL, &n, e) == VK_SUCCESS)
    for (uint32_t i = 0; i < n && !found; i++)
      found = !strcmp(e[i].extensionName, name);
  free(e);
  return found;
}

/* VK_NV_cooperative_matrix with an fp16 x fp16 + fp32 16x16x16 subgroup shape. */
static int coop_shape(gpu_context *c) {
  char *note = c->limits.coop_note;
  size_t cap = sizeof c->limits.coop_note;
  if (!c->vk.vkGetPhysicalDeviceCooperativeMatrixPropertiesNV || !c->vk.vkGetPhysicalDeviceFeatures2 ||
      !has_extension(c, VK_NV_COOPERATIVE_MATRIX_EXTENSION_NAME)) {
    snprintf(note, cap, "no VK_NV_cooperative_matrix");
    return 0;
  }
  if (!has_extension(c, "VK_KHR_shader_float16_int8") || !has_extension(c, "VK_KHR_16bit_storage")) {
    snprintf(note, cap, "no VK_KHR_shader_float16_int8 or VK_KHR_16bit_storage");
    return 0;
  }
  uint32_t n = 0;
  c->vk.vkGetPhysicalDeviceCooperativeMatrixPropertiesNV(c->physical, &n, NULL);
  VkCooperativeMatrixPropertiesNV props[64];
  if (n > 64) n = 64;
  for (uint32_t i = 0; i < n; i++)
    props[i] = (VkCooperativeMatrixPropertiesNV){
        .sType = VK_STRUCTURE_TYPE_COOPERATIVE_MATRIX_PROPERTIES_NV};
  c->vk.vkGetPhysicalDeviceCooperativeMatrixPropertiesNV(c->physical, &n, props);
  for (uint32_t i = 0; i < n; i++) {
    VkCooperativeMatrixPropertiesNV *p = &props[i];
    if (p->MSize == 16 && p->NSize == 16 && p->KSize == 16 && p->AType == VK_COMPONENT_TYPE_FLOAT16_NV &&
        p->BType == VK_COMPONENT_TYPE_FLOAT16_NV && p->CType == VK_COMPONENT_TYPE_FLOAT32_NV &&
        p->DType == VK_COMPONENT_TYPE_FLOAT32_NV && p->scope == VK_SCOPE_SUBGROUP_NV)
      return 1;
  }
  snprintf(note, cap, "no fp16 x fp16 + fp32 16x16x16 subgroup shape among %u", n);
  return 0;
}

static nbrdf_status create_device(gpu_context *c, nbrdf_error *err) {
  float prio = 1.0f;
  VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = c->family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &prio;
  VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  /* The tensor-core kernel's features, enabled only where the device has them all. */
  const char *ext[3] = {VK_NV_COOPERATIVE_MATRIX_EXTENSION_NAME, "VK_KHR_shader_float16_int8",
                        "VK_KHR_16bit_storage"};
  VkPhysicalDeviceCooperativeMatrixFeaturesNV coop = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_COOPERATIVE_MATRIX_FEATURES_NV};
  VkPhysicalDeviceShaderFloat16Int8Features f16 = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_FLOAT16_INT8_FEATURES, .pNext = &coop};
  VkPhysicalDevice16BitStorageFeatures s16 = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_16BIT_STORAGE_FEATURES, .pNext = &f16};
  VkPhysicalDeviceFeatures2 feat = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
                                    .pNext = &s16};
  if (coop_shape(c)) {
    c->vk.vkGetPhysicalDeviceFeatures2(c->physical, &feat);
    if (coop.cooperativeMatrix && f16.shaderFloat16 && s16.storageBuffer16BitAccess) {
      coop.cooperativeMatrixRobustBufferAccess = VK_FALSE; /* only what the kernel needs */
      f16.shaderInt8 = VK_FALSE;
      s16.uniformAndStorageBuffer16BitAccess = VK_FALSE;
      s16.storagePushConstant16 = VK_FALSE;
      s16.storageInputOutput16 = VK_FALSE;
      dci.pNext = &s16;
      dci.enabledExtensionCount = 3;
      dci.ppEnabledExtensionNames = ext;
      c->limits.coop_matrix = 1;
      snprintf(c->limits.coop_note, sizeof c->limits.coop_note, "enabled");
    } else
      snprintf(c->limits.coop_note, sizeof c->limits.coop_note,
               "the device does not enable cooperativeMatrix, shaderFloat16 or 16-bit storage");
  }
  VkResult r = c->vk.vkCreateDevice(c->physical, &dci, NULL, &c->device);
  if (r != VK_SUCCESS && c->limits.coop_matrix) { /* retry without the tensor-core features */
    c->limits.coop_matrix = 0;
    snprintf(c->limits.coop_note, sizeof c->limits.coop_note,
             "vkCreateDevice with the cooperative-matrix features failed (%s)",
             gpu_vk_result_name(r));
    dci.pNext = NULL;
    dci.enabledExtensionCount = 0;
    r = c->vk.vkCreateDevice(c->physical, &dci, NULL, &c->device);
  }
  if (r != VK_SUCCESS)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED, "vkCreateDevice failed on %s (%s)",
                     c->props.deviceName, gpu_vk_result_name(r));
  nbrdf_status st = gpu_vk_load_device(&c->vk, c->device, err);
  if (st == NBRDF_OK) c->vk.vkGetDeviceQueue(c->device, c->family, 0, &c->queue);
  return st;
}

static void fill_limits(gpu_context *c) {
  const VkPhysicalDeviceLimits *l = &c->props.limits;
  c->limits.shared_bytes = l->maxComputeSharedMemorySize;
  c->limits.max_invocations = l->maxComputeWorkGroupInvocations;
  for (int i = 0; i < 3; i++)
    c->limits.max_groups[i] = l->maxComputeWorkGroupCount[i];
  c->limits.max_buffer_bytes = l->maxStorageBufferRange;
  for (uint32_t h = 0; h < c->mem.memoryHeapCount; h++)
    if ((c->mem.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) &&
        c->mem.memoryHeaps[h].size > c->limits.device_bytes)
      c->limits.device_bytes = c->mem.memoryHeaps[h].size;
}

nbrdf_status gpu_context_open(gpu_choice choice, gpu_context **out, nbrdf_error *err) {
  *out = NULL;
  gpu_context *c = calloc(1, sizeof *c);
  if (!c) return core_fail(err, NBRDF_ERR_MEMORY, "GPU: out of memory");
  pthread_mutex_init(&c->queue_lock, NULL);
  nbrdf_status st = gpu_vk_load(&c->vk, err);
  if (st == NBRDF_OK) {
    VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "nbrdf";
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    VkResult r = c->vk.vkCreateInstance(&ici, NULL, &c->instance);
    if (r != VK_SUCCESS)
      st = core_fail(err, NBRDF_ERR_UNSUPPORTED, "vkCreateInstance failed (%s): no Vulkan driver?",
                     gpu_vk_result_name(r));
  }
  if (st == NBRDF_OK) st = gpu_vk_load_instance(&c->vk, c->instance, err);
  if (st == NBRDF_OK) st = pick_device(c, choice, err);
  if (st == NBRDF_OK) fill_limits(c);
  if (st == NBRDF_OK) st = create_device(c, err);
  if (st == NBRDF_OK) st = gpu_pipelines_create(c, err);
  if (st != NBRDF_OK) {
    gpu_context_close(c);
    return st;
  }
  *out = c;
  return NBRDF_OK;
}

void gpu_context_close(gpu_context *c) {
  if (!c) return;
  if (c->device) {
    c->vk.vkDeviceWaitIdle(c->device);
    gpu_pipelines_destroy(c);
    c->vk.vkDestroyDevice(c->device, NULL);
  }
  if (c->instance) c->vk.vkDestroyInstance(c->instance, NULL);
  gpu_vk_unload(&c->vk);
  pthread_mutex_destroy(&c->queue_lock);
  free(c);
}

const char *gpu_context_name(const gpu_context *c) { return c->props.deviceName; }
int gpu_context_is_cpu(const gpu_context *c) {
  return c->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}
const gpu_limits *gpu_context_limits(const gpu_context *c) { return &c->limits; }

nbrdf_status gpu_submit(gpu_context *c, VkCommandBuffer cmd, VkFence fence, nbrdf_error *err) {
  VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  c->vk.vkResetFences(c->device, 1, &fence);
  pthread_mutex_lock(&c->queue_lock);
  VkResult r = c->vk.vkQueueSubmit(c->queue, 1, &si, fence);
  pthread_mutex_unlock(&c->queue_lock);
  if (r != VK_SUCCESS)
    return core_fail(err, NBRDF_ERR_INTERNAL, "GPU %s: submission failed (%s)",
                     c->props.deviceName, gpu_vk_result_name(r));
  return NBRDF_OK;
}

nbrdf_status gpu_wait(gpu_context *c, VkFence fence, nbrdf_error *err) {
  VkResult r = c->vk.vkWaitForFences(c->device, 1, &fence, VK_TRUE, UINT64_MAX);
  if (r != VK_SUCCESS)
    return core_fail(err, NBRDF_ERR_INTERNAL, "GPU %s: waiting for a submission failed (%s)",
                     c->props.deviceName, gpu_vk_result_name(r));
  return NBRDF_OK;
}
#else
typedef int gpu_context_unused;
#endif
