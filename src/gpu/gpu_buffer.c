/* Device buffers and mapped host buffers (gpu_internal.h). */
#include "gpu/gpu.h"

#if NBRDF_HAVE_GPU
#include <string.h>

#include "core/error.h"
#include "gpu/gpu_internal.h"

/* The first memory type allowed by `bits` with all of `need`, preferring those with `like`
 * too; -1 if none. */
static int memory_type(const gpu_context *c, uint32_t bits, VkMemoryPropertyFlags need,
                       VkMemoryPropertyFlags like) {
  int found = -1;
  for (uint32_t i = 0; i < c->mem.memoryTypeCount; i++) {
    VkMemoryPropertyFlags f = c->mem.memoryTypes[i].propertyFlags;
    if (!(bits & (1u << i)) || (f & need) != need) continue;
    if ((f & like) == like) return (int)i;
    if (found < 0) found = (int)i;
  }
  return found;
}

nbrdf_status gpu_buffer_create(gpu_context *c, VkDeviceSize size, int host_visible, gpu_buffer *b,
                               nbrdf_error *err) {
  memset(b, 0, sizeof *b);
  if (size == 0) size = 16;
  b->size = size;
  VkBufferCreateInfo bci = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = size;
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
              VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkResult r = c->vk.vkCreateBuffer(c->device, &bci, NULL, &b->buffer);
  if (r != VK_SUCCESS)
    return core_fail(err, NBRDF_ERR_MEMORY, "GPU: cannot create a buffer of %llu bytes (%s)",
                     (unsigned long long)size, gpu_vk_result_name(r));
  VkMemoryRequirements req;
  c->vk.vkGetBufferMemoryRequirements(c->device, b->buffer, &req);
  int type;
  if (host_visible)
    type = memory_type(c, req.memoryTypeBits,
                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                       VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  else
    type = memory_type(c, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0);
  if (type < 0) type = memory_type(c, req.memoryTypeBits, 0, 0);
  VkMemoryAllocateInfo mai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = (uint32_t)(type < 0 ? 0 : type);
  r = type < 0 ? VK_ERROR_OUT_OF_DEVICE_MEMORY
               : c->vk.vkAllocateMemory(c->device, &mai, NULL, &b->memory);
  if (r == VK_SUCCESS) r = c->vk.vkBindBufferMemory(c->device, b->buffer, b->memory, 0);
  if (r == VK_SUCCESS && host_visible) {
    b->coherent = (c->mem.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
    r = c->vk.vkMapMemory(c->device, b->memory, 0, VK_WHOLE_SIZE, 0, &b->map);
  }
  if (r != VK_SUCCESS) {
    gpu_buffer_destroy(c, b);
    return core_fail(err, NBRDF_ERR_MEMORY, "GPU %s: cannot allocate %llu bytes of %s memory (%s)",
                     c->props.deviceName, (unsigned long long)size,
                     host_visible ? "host-visible" : "device", gpu_vk_result_name(r));
  }
  return NBRDF_OK;
}

void gpu_buffer_destroy(gpu_context *c, gpu_buffer *b) {
  if (b->map) c->vk.vkUnmapMemory(c->device, b->memory);
  if (b->buffer) c->vk.vkDestroyBuffer(c->device, b->buffer, NULL);
  if (b->memory) c->vk.vkFreeMemory(c->device, b->memory, NULL);
  memset(b, 0, sizeof *b);
}

static VkMappedMemoryRange whole(const gpu_buffer *b) {
  VkMappedMemoryRange m = {.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE};
  m.memory = b->memory;
  m.size = VK_WHOLE_SIZE;
  return m;
}

void gpu_buffer_flush(gpu_context *c, gpu_buffer *b) {
  if (b->coherent) return;
  VkMappedMemoryRange m = whole(b);
  c->vk.vkFlushMappedMemoryRanges(c->device, 1, &m);
}

void gpu_buffer_invalidate(gpu_context *c, gpu_buffer *b) {
  if (b->coherent) return;
  VkMappedMemoryRange m = whole(b);
  c->vk.vkInvalidateMappedMemoryRanges(c->device, 1, &m);
}
#else
typedef int gpu_buffer_unused;
#endif
