/* Headless Vulkan compute (vk_harness.h). Synchronous and simple on purpose: the tests
 * compare numbers, the bench times whole dispatches. */
#include "vk_harness.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if defined(__SANITIZE_ADDRESS__)
#include <dlfcn.h>
/* Mesa 22.3's lavapipe (or its LLVM) leaks one 128-byte block per process. The loader
 * unloads the driver at vkDestroyInstance, which leaves the leak's stack unsymbolised, so
 * vkh_open pins the driver (keep_driver_loaded) and the suppression names its modules:
 * leaks of our own code are still reported. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libvulkan_lvp.so\nleak:libLLVM\n"; }
static void keep_driver_loaded(void) { (void)dlopen("libvulkan_lvp.so", RTLD_LAZY | RTLD_NOLOAD); }
#else
static void keep_driver_loaded(void) {}
#endif

#ifndef NBRDF_SPIRV_DIR
#define NBRDF_SPIRV_DIR "."
#endif

struct vkh {
  VkInstance instance;
  VkPhysicalDevice physical;
  VkPhysicalDeviceProperties props;
  VkPhysicalDeviceMemoryProperties mem;
  VkDevice device;
  VkQueue queue;
  uint32_t family;
  VkCommandPool pool;
  VkCommandBuffer cmd;
  VkFence fence;
  VkQueryPool timestamps; /* 2 queries, when the queue family has timestamps */
  uint32_t subgroup_size;
  int f16;  /* shaderFloat16 enabled, quad subgroup operations: the emulated kernels run */
  int coop; /* VK_NV_cooperative_matrix enabled with a 16x16x16 fp16/fp32 subgroup shape */
  char msg[512];
};

static int fail(vkh *ctx, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(ctx->msg, sizeof ctx->msg, fmt, ap);
  va_end(ap);
  return -1;
}

const char *vkh_error(const vkh *ctx) { return ctx->msg; }
const char *vkh_device_name(const vkh *ctx) { return ctx->props.deviceName; }
uint32_t vkh_max_shared(const vkh *ctx) { return ctx->props.limits.maxComputeSharedMemorySize; }
uint32_t vkh_max_invocations(const vkh *ctx) {
  return ctx->props.limits.maxComputeWorkGroupInvocations;
}
uint32_t vkh_subgroup_size(const vkh *ctx) { return ctx->subgroup_size; }
int vkh_has_coop(const vkh *ctx) { return ctx->coop; }
int vkh_has_f16(const vkh *ctx) { return ctx->f16; }
int vkh_device_is_cpu(const vkh *ctx) {
  return ctx->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

static int pick_device(vkh *ctx) {
  uint32_t n = 0;
  if (vkEnumeratePhysicalDevices(ctx->instance, &n, NULL) != VK_SUCCESS || n == 0)
    return fail(ctx, "no Vulkan device (install mesa-vulkan-drivers for lavapipe)");
  VkPhysicalDevice devs[16];
  if (n > 16) n = 16;
  vkEnumeratePhysicalDevices(ctx->instance, &n, devs);
  const char *want = getenv("NBRDF_VK_DEVICE");
  int chosen = -1;
  for (uint32_t i = 0; i < n && chosen < 0; i++) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devs[i], &p);
    if (want && *want ? strstr(p.deviceName, want) != NULL
                      : p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU)
      chosen = (int)i;
  }
  if (chosen < 0 && want && *want)
    return fail(ctx, "no Vulkan device name contains NBRDF_VK_DEVICE=\"%s\"", want);
  if (chosen < 0) chosen = 0;
  ctx->physical = devs[chosen];
  vkGetPhysicalDeviceProperties(ctx->physical, &ctx->props);
  vkGetPhysicalDeviceMemoryProperties(ctx->physical, &ctx->mem);
  uint32_t nf = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical, &nf, NULL);
  VkQueueFamilyProperties fam[16];
  if (nf > 16) nf = 16;
  vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical, &nf, fam);
  for (uint32_t f = 0; f < nf; f++)
    if (fam[f].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      ctx->family = f;
      return 0;
    }
  return fail(ctx, "%s has no compute queue", ctx->props.deviceName);
}

static int has_extension(const vkh *ctx, const char *name) {
  uint32_t n = 0;
  if (vkEnumerateDeviceExtensionProperties(ctx->physical, NULL, &n, NULL) != VK_SUCCESS) return 0;
  VkExtensionProperties *e = calloc(n ? n : 1, sizeof *e);
  int found = 0;
  if (e && vkEnumerateDeviceExtensionProperties(ctx->physical, NULL, &n, e) == VK_SUCCESS)
    for (uint32_t i = 0; i < n && !found; i++) found = !strcmp(e[i].extensionName, name);
  free(e);
  return found;
}

/* shaderFloat16 (VK_KHR_shader_float16_int8) and quad subgroup operations: what the
 * emulated tensor-core kernels (nbrdf_*_coopemu.spv) need. */
static int f16_capable(vkh *ctx) {
  VkPhysicalDeviceSubgroupProperties sub = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  p2.pNext = &sub;
  vkGetPhysicalDeviceProperties2(ctx->physical, &p2);
  if (!has_extension(ctx, VK_KHR_SHADER_FLOAT16_INT8_EXTENSION_NAME) ||
      !(sub.supportedOperations & VK_SUBGROUP_FEATURE_QUAD_BIT) || sub.subgroupSize < 8 ||
      sub.subgroupSize > 64)
    return 0;
  VkPhysicalDeviceShaderFloat16Int8FeaturesKHR f16 = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_FLOAT16_INT8_FEATURES_KHR};
  VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &f16;
  vkGetPhysicalDeviceFeatures2(ctx->physical, &f2);
  return f16.shaderFloat16 == VK_TRUE;
}

/* Subgroup size, and whether the tensor-core kernels (nbrdf_*_coop.spv) can run: the
 * extensions, the features and a 16x16x16 fp16 x fp16 + fp32 subgroup shape.
 * NBRDF_VK_NO_COOP=1 pretends they cannot (to compare on one device). */
static int coop_capable(vkh *ctx) {
  VkPhysicalDeviceSubgroupProperties sub = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceProperties2 p2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  p2.pNext = &sub;
  vkGetPhysicalDeviceProperties2(ctx->physical, &p2);
  ctx->subgroup_size = sub.subgroupSize;
  const char *off = getenv("NBRDF_VK_NO_COOP");
  if ((off && *off && strcmp(off, "0")) || sub.subgroupSize != 32 ||
      !(sub.supportedOperations & VK_SUBGROUP_FEATURE_QUAD_BIT) ||
      !has_extension(ctx, VK_NV_COOPERATIVE_MATRIX_EXTENSION_NAME) ||
      !has_extension(ctx, VK_KHR_SHADER_FLOAT16_INT8_EXTENSION_NAME) ||
      !has_extension(ctx, VK_KHR_VULKAN_MEMORY_MODEL_EXTENSION_NAME))
    return 0;
  VkPhysicalDeviceCooperativeMatrixFeaturesNV coop = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_COOPERATIVE_MATRIX_FEATURES_NV};
  VkPhysicalDeviceShaderFloat16Int8FeaturesKHR f16 = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_FLOAT16_INT8_FEATURES_KHR};
  VkPhysicalDeviceVulkanMemoryModelFeaturesKHR vmm = {
      .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_MEMORY_MODEL_FEATURES_KHR};
  VkPhysicalDeviceFeatures2 f2 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &coop;
  coop.pNext = &f16;
  f16.pNext = &vmm;
  vkGetPhysicalDeviceFeatures2(ctx->physical, &f2);
  if (!coop.cooperativeMatrix || !f16.shaderFloat16 || !vmm.vulkanMemoryModel) return 0;
  PFN_vkGetPhysicalDeviceCooperativeMatrixPropertiesNV get =
      (PFN_vkGetPhysicalDeviceCooperativeMatrixPropertiesNV)vkGetInstanceProcAddr(
          ctx->instance, "vkGetPhysicalDeviceCooperativeMatrixPropertiesNV");
  uint32_t n = 0;
  if (!get || get(ctx->physical, &n, NULL) != VK_SUCCESS || n == 0) return 0;
  VkCooperativeMatrixPropertiesNV *p = calloc(n, sizeof *p);
  int ok = 0;
  for (uint32_t i = 0; p && i < n; i++) p[i].sType = VK_STRUCTURE_TYPE_COOPERATIVE_MATRIX_PROPERTIES_NV;
  if (p && get(ctx->physical, &n, p) == VK_SUCCESS)
    for (uint32_t i = 0; i < n && !ok; i++)
      ok = p[i].MSize == 16 && p[i].NSize == 16 && p[i].KSize == 16 &&
           p[i].AType == VK_COMPONENT_TYPE_FLOAT16_NV && p[i].BType == VK_COMPONENT_TYPE_FLOAT16_NV &&
           p[i].CType == VK_COMPONENT_TYPE_FLOAT32_NV && p[i].DType == VK_COMPONENT_TYPE_FLOAT32_NV &&
           p[i].scope == VK_SCOPE_SUBGROUP_NV;
  free(p);
  return ok;
}

int vkh_open(vkh **out, char *msg, size_t msg_size) {
  *out = NULL;
  vkh *ctx = calloc(1, sizeof *ctx);
  if (!ctx) {
    snprintf(msg, msg_size, "out of memory");
    return -1;
  }
  VkApplicationInfo app = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "nbrdf-shader-tests";
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo ici = {.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  int rc = 0;
  VkResult r = vkCreateInstance(&ici, NULL, &ctx->instance);
  if (r != VK_SUCCESS)
    rc = fail(ctx, "vkCreateInstance failed (%d): is libvulkan1 + an ICD installed?", (int)r);
  if (!rc) keep_driver_loaded();
  if (!rc) rc = pick_device(ctx);
  if (!rc) {
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = ctx->family;
    qci.queueCount = 1;
    qci.pQueuePriorities = &prio;
    VkDeviceCreateInfo dci = {.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    const char *exts[3];
    VkPhysicalDeviceCooperativeMatrixFeaturesNV coop = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_COOPERATIVE_MATRIX_FEATURES_NV};
    VkPhysicalDeviceShaderFloat16Int8FeaturesKHR f16 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_FLOAT16_INT8_FEATURES_KHR};
    VkPhysicalDeviceVulkanMemoryModelFeaturesKHR vmm = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_MEMORY_MODEL_FEATURES_KHR};
    VkPhysicalDeviceFeatures2 feats = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    if (coop_capable(ctx)) {
      exts[0] = VK_KHR_SHADER_FLOAT16_INT8_EXTENSION_NAME;
      exts[1] = VK_NV_COOPERATIVE_MATRIX_EXTENSION_NAME;
      exts[2] = VK_KHR_VULKAN_MEMORY_MODEL_EXTENSION_NAME;
      coop.cooperativeMatrix = VK_TRUE;
      f16.shaderFloat16 = VK_TRUE;
      vmm.vulkanMemoryModel = VK_TRUE;
      coop.pNext = &f16;
      f16.pNext = &vmm;
      feats.pNext = &coop;
      dci.pNext = &feats;
      dci.enabledExtensionCount = 3;
      dci.ppEnabledExtensionNames = exts;
      ctx->coop = ctx->f16 = 1;
    } else if (f16_capable(ctx)) {
      exts[0] = VK_KHR_SHADER_FLOAT16_INT8_EXTENSION_NAME;
      f16.shaderFloat16 = VK_TRUE;
      feats.pNext = &f16;
      dci.pNext = &feats;
      dci.enabledExtensionCount = 1;
      dci.ppEnabledExtensionNames = exts;
      ctx->f16 = 1;
    }
    if (vkCreateDevice(ctx->physical, &dci, NULL, &ctx->device) != VK_SUCCESS)
      rc = fail(ctx, "vkCreateDevice failed on %s", ctx->props.deviceName);
  }
  if (!rc) {
    vkGetDeviceQueue(ctx->device, ctx->family, 0, &ctx->queue);
    VkCommandPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = ctx->family;
    VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (vkCreateCommandPool(ctx->device, &pci, NULL, &ctx->pool) != VK_SUCCESS ||
        (cai.commandPool = ctx->pool,
         vkAllocateCommandBuffers(ctx->device, &cai, &ctx->cmd) != VK_SUCCESS) ||
        vkCreateFence(ctx->device, &fci, NULL, &ctx->fence) != VK_SUCCESS)
      rc = fail(ctx, "command pool / fence creation failed");
  }
  if (!rc) {
    uint32_t nf = 0;
    VkQueueFamilyProperties fam[16];
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical, &nf, NULL);
    if (nf > 16) nf = 16;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical, &nf, fam);
    VkQueryPoolCreateInfo qpi = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qpi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qpi.queryCount = 2;
    if (fam[ctx->family].timestampValidBits > 0 && ctx->props.limits.timestampPeriod > 0 &&
        vkCreateQueryPool(ctx->device, &qpi, NULL, &ctx->timestamps) != VK_SUCCESS)
      ctx->timestamps = VK_NULL_HANDLE;
  }
  if (rc) {
    snprintf(msg, msg_size, "%s", ctx->msg);
    vkh_close(ctx);
    return -1;
  }
  *out = ctx;
  return 0;
}

void vkh_close(vkh *ctx) {
  if (!ctx) return;
  if (ctx->device) {
    vkDeviceWaitIdle(ctx->device);
    if (ctx->fence) vkDestroyFence(ctx->device, ctx->fence, NULL);
    if (ctx->timestamps) vkDestroyQueryPool(ctx->device, ctx->timestamps, NULL);
    if (ctx->pool) vkDestroyCommandPool(ctx->device, ctx->pool, NULL);
    vkDestroyDevice(ctx->device, NULL);
  }
  if (ctx->instance) vkDestroyInstance(ctx->instance, NULL);
  free(ctx);
}

/* Host-visible coherent memory, device-local too where the device has such a heap (a GPU
 * with resizable BAR), so that a benchmark on a GPU does not read weights over PCIe. */
static int memory_type(const vkh *ctx, uint32_t allowed) {
  const VkMemoryPropertyFlags need =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  int fallback = -1;
  for (uint32_t i = 0; i < ctx->mem.memoryTypeCount; i++) {
    VkMemoryPropertyFlags f = ctx->mem.memoryTypes[i].propertyFlags;
    if (!(allowed & (1u << i)) || (f & need) != need) continue;
    if (f & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) return (int)i;
    if (fallback < 0) fallback = (int)i;
  }
  return fallback;
}

int vkh_buffer_create(vkh *ctx, size_t bytes, vkh_buffer *b) {
  memset(b, 0, sizeof *b);
  if (bytes == 0) bytes = 4;
  VkBufferCreateInfo bci = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = bytes;
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  if (vkCreateBuffer(ctx->device, &bci, NULL, &b->buffer) != VK_SUCCESS)
    return fail(ctx, "vkCreateBuffer(%zu bytes) failed", bytes);
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx->device, b->buffer, &req);
  int type = memory_type(ctx, req.memoryTypeBits);
  VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = (uint32_t)type;
  if (type < 0 || vkAllocateMemory(ctx->device, &mai, NULL, &b->memory) != VK_SUCCESS ||
      vkBindBufferMemory(ctx->device, b->buffer, b->memory, 0) != VK_SUCCESS ||
      vkMapMemory(ctx->device, b->memory, 0, VK_WHOLE_SIZE, 0, &b->map) != VK_SUCCESS) {
    vkh_buffer_destroy(ctx, b);
    return fail(ctx, "no host-visible memory for a %zu-byte buffer", bytes);
  }
  b->bytes = bytes;
  return 0;
}

void vkh_buffer_destroy(vkh *ctx, vkh_buffer *b) {
  if (b->memory) vkFreeMemory(ctx->device, b->memory, NULL);
  if (b->buffer) vkDestroyBuffer(ctx->device, b->buffer, NULL);
  memset(b, 0, sizeof *b);
}

static uint32_t *read_spirv(vkh *ctx, const char *name, size_t *bytes) {
  const char *dir = getenv("NBRDF_SPIRV_DIR");
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir && *dir ? dir : NBRDF_SPIRV_DIR, name);
  FILE *f = fopen(path, "rb");
  if (!f) {
    fail(ctx, "%s: cannot open the SPIR-V kernel (was the build's shader step run?)", path);
    return NULL;
  }
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  uint32_t *code = n > 0 && n % 4 == 0 ? malloc((size_t)n) : NULL;
  if (!code || fread(code, 1, (size_t)n, f) != (size_t)n) {
    free(code);
    code = NULL;
    fail(ctx, "%s: not a SPIR-V file (%ld bytes)", path, n);
  }
  fclose(f);
  *bytes = (size_t)n;
  return code;
}

int vkh_kernel_create(vkh *ctx, const char *spv_name, int n_buffers, uint32_t push_bytes,
                      int n_spec, const uint32_t *spec, vkh_kernel *k) {
  memset(k, 0, sizeof *k);
  if (n_buffers < 1 || n_buffers > VKH_MAX_BINDINGS || n_spec < 0 || n_spec > 8)
    return fail(ctx, "%s: %d buffers, %d constants", spv_name, n_buffers, n_spec);
  size_t bytes = 0;
  uint32_t *code = read_spirv(ctx, spv_name, &bytes);
  if (!code) return -1;
  VkShaderModuleCreateInfo smi = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smi.codeSize = bytes;
  smi.pCode = code;
  VkResult r = vkCreateShaderModule(ctx->device, &smi, NULL, &k->module);
  free(code);
  if (r != VK_SUCCESS) return fail(ctx, "%s: vkCreateShaderModule failed (%d)", spv_name, (int)r);

  VkDescriptorSetLayoutBinding binds[VKH_MAX_BINDINGS];
  memset(binds, 0, sizeof binds);
  for (int i = 0; i < n_buffers; i++) {
    binds[i].binding = (uint32_t)i;
    binds[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    binds[i].descriptorCount = 1;
    binds[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo dli = {.sType =
                                             VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dli.bindingCount = (uint32_t)n_buffers;
  dli.pBindings = binds;
  VkPushConstantRange range = {VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  VkPipelineLayoutCreateInfo pli = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pushConstantRangeCount = push_bytes ? 1 : 0;
  pli.pPushConstantRanges = &range;
  VkSpecializationMapEntry entries[8];
  for (int i = 0; i < n_spec; i++) {
    entries[i].constantID = (uint32_t)i;
    entries[i].offset = (uint32_t)(4 * i);
    entries[i].size = 4;
  }
  VkSpecializationInfo si = {(uint32_t)n_spec, entries, (size_t)4 * n_spec, spec};
  VkComputePipelineCreateInfo cpi = {.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cpi.flags = VK_PIPELINE_CREATE_DISPATCH_BASE_BIT; /* vkh_run splits large batches */
  cpi.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cpi.stage.module = k->module;
  cpi.stage.pName = "main";
  cpi.stage.pSpecializationInfo = n_spec ? &si : NULL;
  VkDescriptorPoolSize ps = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, (uint32_t)n_buffers};
  VkDescriptorPoolCreateInfo dpi = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dpi.maxSets = 1;
  dpi.poolSizeCount = 1;
  dpi.pPoolSizes = &ps;
  VkDescriptorSetAllocateInfo dsa = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  dsa.descriptorSetCount = 1;
  if (vkCreateDescriptorSetLayout(ctx->device, &dli, NULL, &k->set_layout) != VK_SUCCESS ||
      (pli.pSetLayouts = &k->set_layout,
       vkCreatePipelineLayout(ctx->device, &pli, NULL, &k->layout) != VK_SUCCESS) ||
      (cpi.layout = k->layout, vkCreateComputePipelines(ctx->device, VK_NULL_HANDLE, 1, &cpi, NULL,
                                                        &k->pipeline) != VK_SUCCESS) ||
      vkCreateDescriptorPool(ctx->device, &dpi, NULL, &k->pool) != VK_SUCCESS ||
      (dsa.descriptorPool = k->pool, dsa.pSetLayouts = &k->set_layout,
       vkAllocateDescriptorSets(ctx->device, &dsa, &k->set) != VK_SUCCESS)) {
    vkh_kernel_destroy(ctx, k);
    return fail(ctx, "%s: pipeline creation failed", spv_name);
  }
  k->n_buffers = n_buffers;
  k->push_bytes = push_bytes;
  return 0;
}

void vkh_kernel_destroy(vkh *ctx, vkh_kernel *k) {
  if (k->pool) vkDestroyDescriptorPool(ctx->device, k->pool, NULL);
  if (k->pipeline) vkDestroyPipeline(ctx->device, k->pipeline, NULL);
  if (k->layout) vkDestroyPipelineLayout(ctx->device, k->layout, NULL);
  if (k->set_layout) vkDestroyDescriptorSetLayout(ctx->device, k->set_layout, NULL);
  if (k->module) vkDestroyShaderModule(ctx->device, k->module, NULL);
  memset(k, 0, sizeof *k);
}

void vkh_kernel_bind(vkh *ctx, vkh_kernel *k, vkh_buffer *const *buffers) {
  VkDescriptorBufferInfo info[VKH_MAX_BINDINGS];
  VkWriteDescriptorSet w[VKH_MAX_BINDINGS];
  memset(w, 0, sizeof w);
  for (int i = 0; i < k->n_buffers; i++) {
    info[i].buffer = buffers[i]->buffer;
    info[i].offset = 0;
    info[i].range = buffers[i]->bytes;
    w[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    w[i].dstSet = k->set;
    w[i].dstBinding = (uint32_t)i;
    w[i].descriptorCount = 1;
    w[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w[i].pBufferInfo = &info[i];
  }
  vkUpdateDescriptorSets(ctx->device, (uint32_t)k->n_buffers, w, 0, NULL);
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Records `reps` dispatches of `groups` workgroups (serialised by barriers), between two
 * timestamps when the device has them. */
static int record(vkh *ctx, vkh_kernel *k, const void *push, uint32_t groups, int reps) {
  VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkResetCommandBuffer(ctx->cmd, 0);
  if (vkBeginCommandBuffer(ctx->cmd, &bi) != VK_SUCCESS) return fail(ctx, "vkBeginCommandBuffer");
  if (ctx->timestamps) {
    vkCmdResetQueryPool(ctx->cmd, ctx->timestamps, 0, 2);
    vkCmdWriteTimestamp(ctx->cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, ctx->timestamps, 0);
  }
  vkCmdBindPipeline(ctx->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, k->pipeline);
  vkCmdBindDescriptorSets(ctx->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, k->layout, 0, 1, &k->set, 0,
                          NULL);
  if (k->push_bytes)
    vkCmdPushConstants(ctx->cmd, k->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, k->push_bytes, push);
  /* Large batches go as several dispatches with a base group (Vulkan 1.1). */
  uint32_t limit = ctx->props.limits.maxComputeWorkGroupCount[0];
  for (int r = 0; r < reps; r++) {
    if (r > 0) {
      VkMemoryBarrier cb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
      cb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
      cb.dstAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT;
      vkCmdPipelineBarrier(ctx->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &cb, 0, NULL, 0, NULL);
    }
    for (uint32_t g0 = 0; g0 < groups; g0 += limit) {
      uint32_t g = groups - g0 < limit ? groups - g0 : limit;
      vkCmdDispatchBase(ctx->cmd, g0, 0, 0, g, 1, 1);
    }
  }
  if (ctx->timestamps)
    vkCmdWriteTimestamp(ctx->cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, ctx->timestamps, 1);
  VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(ctx->cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                       0, 1, &mb, 0, NULL, 0, NULL);
  if (vkEndCommandBuffer(ctx->cmd) != VK_SUCCESS) return fail(ctx, "vkEndCommandBuffer");
  return 0;
}

static int submit(vkh *ctx, double *seconds) {
  VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &ctx->cmd;
  double t0 = now();
  vkResetFences(ctx->device, 1, &ctx->fence);
  VkResult r = vkQueueSubmit(ctx->queue, 1, &si, ctx->fence);
  if (r == VK_SUCCESS) r = vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, UINT64_MAX);
  if (seconds) *seconds = now() - t0;
  return r == VK_SUCCESS ? 0 : fail(ctx, "submit/wait failed (%d)", (int)r);
}

int vkh_run(vkh *ctx, vkh_kernel *k, const void *push, uint32_t groups, double *seconds) {
  if (record(ctx, k, push, groups, 1)) return -1;
  return submit(ctx, seconds);
}

int vkh_time(vkh *ctx, vkh_kernel *k, const void *push, uint32_t groups, int reps,
             double *seconds, int *from_timestamps) {
  double wall = 0;
  if (reps < 1) reps = 1;
  if (record(ctx, k, push, groups, reps) || submit(ctx, &wall)) return -1;
  *seconds = wall / reps;
  *from_timestamps = 0;
  uint64_t ts[2];
  if (ctx->timestamps &&
      vkGetQueryPoolResults(ctx->device, ctx->timestamps, 0, 2, sizeof ts, ts, sizeof ts[0],
                            VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS &&
      ts[1] > ts[0]) {
    *seconds = (double)(ts[1] - ts[0]) * ctx->props.limits.timestampPeriod * 1e-9 / reps;
    *from_timestamps = 1;
  }
  return 0;
}
