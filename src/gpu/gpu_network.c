/* gpu_network: one network's weights and activations on the device, and its forward pass as
 * one command buffer per chunk of rows (gpu.h). The plan mirrors src/nn/forward.c's inference:
 * ping-pong activations, skip sources kept, GEMM then row pass per linear map. */
#include "gpu/gpu.h"

#if NBRDF_HAVE_GPU
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/gpu_internal.h"
#include "gpu/gpu_plan.h"
#include "nn/internal.h"

struct gpu_network {
  gpu_context *ctx;
  gpu_precision precision;
  int in, out, chunk;
  gpu_plan plan;
  gpu_buffer params;
  /* Two slots: while the device runs chunk k from one, the host fills the other with chunk
   * k + 1 (and reads chunk k - 1's results out of it). */
  gpu_buffer stage_in[2], stage_out[2];
  gpu_buffer buf[GPU_PLAN_MAX_BUFFERS];
  VkDescriptorPool pool;
  VkDescriptorSet sets[GPU_PLAN_MAX_STEPS];
  VkCommandPool cmd_pool;
  VkCommandBuffer cmd[2];
  VkFence fence[2];
  VkQueryPool timestamps; /* 2 per slot: before the first layer, after the last */
  double device_s;        /* of the last forward; < 0: no timestamps */
};

/* Rows per chunk: the activations of a chunk take at most ~1/4 of the device's memory
 * (1 GiB at most; 64 MiB on a CPU device), each buffer within maxStorageBufferRange. */
static int chunk_rows(const gpu_context *c, const gpu_plan *plan, int max_rows) {
  const gpu_limits *l = gpu_context_limits(c);
  uint64_t budget = gpu_context_is_cpu(c) ? (64u << 20) : l->device_bytes / 4;
  if (budget > (1u << 30)) budget = 1u << 30;
  uint64_t rows = budget / (4 * (uint64_t)plan->floats_per_row);
  uint64_t by_range = l->max_buffer_bytes / (4 * (uint64_t)plan->max_width);
  if (rows > by_range) rows = by_range;
  if (rows > 262144) rows = 262144;
  rows &= ~(uint64_t)255;
  if (rows < 256) rows = 256;
  if (max_rows > 0 && (uint64_t)max_rows < rows) rows = (uint64_t)max_rows;
  return (int)rows;
}

static nbrdf_status create_sets(gpu_network *g, nbrdf_error *err) {
  gpu_context *c = g->ctx;
  uint32_t n = (uint32_t)(g->plan.n_steps ? g->plan.n_steps : 1);
  VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, n * GPU_BINDINGS};
  VkDescriptorPoolCreateInfo pci = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pci.maxSets = n;
  pci.poolSizeCount = 1;
  pci.pPoolSizes = &size;
  if (c->vk.vkCreateDescriptorPool(c->device, &pci, NULL, &g->pool) != VK_SUCCESS)
    return core_fail(err, NBRDF_ERR_INTERNAL, "GPU: cannot create a descriptor pool");
  for (int s = 0; s < g->plan.n_steps; s++) {
    const gpu_step *st = &g->plan.steps[s];
    if (st->kind == GPU_STEP_COPY) continue;
    VkDescriptorSetAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = g->pool;
    ai.descriptorSetCount = 1;
    ai.pSetLayouts = &c->set_layout;
    if (c->vk.vkAllocateDescriptorSets(c->device, &ai, &g->sets[s]) != VK_SUCCESS)
      return core_fail(err, NBRDF_ERR_INTERNAL, "GPU: cannot allocate descriptor sets");
    int which[GPU_BINDINGS] = {st->x, -1, st->y, st->a1, st->a2};
    VkDescriptorBufferInfo info[GPU_BINDINGS];
    VkWriteDescriptorSet w[GPU_BINDINGS];
    for (int b = 0; b < GPU_BINDINGS; b++) {
      const gpu_buffer *buf = which[b] >= 0 ? &g->buf[which[b]] : &g->params;
      info[b] = (VkDescriptorBufferInfo){buf->buffer, 0, VK_WHOLE_SIZE};
      w[b] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
      w[b].dstSet = g->sets[s];
      w[b].dstBinding = (uint32_t)b;
      w[b].descriptorCount = 1;
      w[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      w[b].pBufferInfo = &info[b];
    }
    c->vk.vkUpdateDescriptorSets(c->device, GPU_BINDINGS, w, 0, NULL);
  }
  return NBRDF_OK;
}

static void barrier(gpu_context *c, VkCommandBuffer cmd, VkPipelineStageFlags dst_stage,
                    VkAccessFlags dst_access) {
  VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = dst_access;
  c->vk.vkCmdPipelineBarrier(cmd,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                             dst_stage, 0, 1, &mb, 0, NULL, 0, NULL);
}

static nbrdf_status upload_params(gpu_network *g, const nn_network *nn, nbrdf_error *err) {
  gpu_context *c = g->ctx;
  size_t bytes = sizeof(float) * nn->n_params;
  gpu_buffer stage;
  nbrdf_status st = gpu_buffer_create(c, bytes, 0, &g->params, err);
  if (st == NBRDF_OK) st = gpu_buffer_create(c, bytes, 1, &stage, err);
  if (st != NBRDF_OK) return st;
  memcpy(stage.map, nn->params, bytes);
  gpu_buffer_flush(c, &stage);
  VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  c->vk.vkResetCommandBuffer(g->cmd[0], 0);
  c->vk.vkBeginCommandBuffer(g->cmd[0], &bi);
  VkBufferCopy region = {0, 0, bytes ? bytes : 16};
  c->vk.vkCmdCopyBuffer(g->cmd[0], stage.buffer, g->params.buffer, 1, &region);
  c->vk.vkEndCommandBuffer(g->cmd[0]);
  st = gpu_submit(c, g->cmd[0], g->fence[0], err);
  if (st == NBRDF_OK) st = gpu_wait(c, g->fence[0], err);
  gpu_buffer_destroy(c, &stage);
  return st;
}

nbrdf_status gpu_network_create(gpu_context *c, const nn_network *nn, gpu_precision precision,
                                int max_rows, gpu_network **out, nbrdf_error *err) {
  *out = NULL;
  if (precision == GPU_FP16_COOP && !c->limits.coop_matrix)
    return core_fail(err, NBRDF_ERR_UNSUPPORTED,
                     "GPU %s: no VK_NV_cooperative_matrix with fp16 16x16x16 shapes",
                     c->props.deviceName);
  gpu_network *g = calloc(1, sizeof *g);
  if (!g) return core_fail(err, NBRDF_ERR_MEMORY, "GPU: out of memory");
  g->ctx = c;
  g->precision = precision;
  g->in = nn->widths[0];
  g->out = nn->widths[nn->spec.n_layers];
  nbrdf_status st = gpu_plan_make(nn, &g->plan, err);
  if (st == NBRDF_OK) {
    g->chunk = chunk_rows(c, &g->plan, max_rows);
    VkCommandPoolCreateInfo cp = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    cp.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    cp.queueFamilyIndex = c->family;
    VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 2;
    if (c->vk.vkCreateCommandPool(c->device, &cp, NULL, &g->cmd_pool) != VK_SUCCESS ||
        (ai.commandPool = g->cmd_pool,
         c->vk.vkAllocateCommandBuffers(c->device, &ai, g->cmd) != VK_SUCCESS) ||
        c->vk.vkCreateFence(c->device, &fi, NULL, &g->fence[0]) != VK_SUCCESS ||
        c->vk.vkCreateFence(c->device, &fi, NULL, &g->fence[1]) != VK_SUCCESS)
      st = core_fail(err, NBRDF_ERR_INTERNAL, "GPU: cannot create a command buffer");
  }
  for (int b = 0; st == NBRDF_OK && b < g->plan.n_buffers; b++)
    st = gpu_buffer_create(c, sizeof(float) * (VkDeviceSize)g->chunk * g->plan.buffer_width[b], 0,
                           &g->buf[b], err);
  for (int s = 0; s < 2; s++) {
    if (st == NBRDF_OK)
      st = gpu_buffer_create(c, sizeof(float) * (VkDeviceSize)g->chunk * g->in, 1, &g->stage_in[s],
                             err);
    if (st == NBRDF_OK)
      st = gpu_buffer_create(c, sizeof(float) * (VkDeviceSize)g->chunk * g->out, 1,
                             &g->stage_out[s], err);
  }
  if (st == NBRDF_OK && c->timestamp_ns > 0.0) {
    VkQueryPoolCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = 4;
    if (c->vk.vkCreateQueryPool(c->device, &qi, NULL, &g->timestamps) != VK_SUCCESS)
      g->timestamps = VK_NULL_HANDLE; /* timing only: go on without */
  }
  if (st == NBRDF_OK) st = upload_params(g, nn, err);
  if (st == NBRDF_OK) st = create_sets(g, err);
  if (st != NBRDF_OK) {
    gpu_network_destroy(g);
    return st;
  }
  *out = g;
  return NBRDF_OK;
}

void gpu_network_destroy(gpu_network *g) {
  if (!g) return;
  gpu_context *c = g->ctx;
  c->vk.vkDeviceWaitIdle(c->device);
  for (int b = 0; b < GPU_PLAN_MAX_BUFFERS; b++)
    gpu_buffer_destroy(c, &g->buf[b]);
  gpu_buffer_destroy(c, &g->params);
  for (int s = 0; s < 2; s++) {
    gpu_buffer_destroy(c, &g->stage_in[s]);
    gpu_buffer_destroy(c, &g->stage_out[s]);
    if (g->fence[s]) c->vk.vkDestroyFence(c->device, g->fence[s], NULL);
  }
  if (g->pool) c->vk.vkDestroyDescriptorPool(c->device, g->pool, NULL);
  if (g->timestamps) c->vk.vkDestroyQueryPool(c->device, g->timestamps, NULL);
  if (g->cmd_pool) c->vk.vkDestroyCommandPool(c->device, g->cmd_pool, NULL);
  free(g);
}

int gpu_network_chunk_rows(const gpu_network *g) { return g->chunk; }
double gpu_network_device_seconds(const gpu_network *g) { return g->device_s; }
int gpu_network_inputs(const gpu_network *g) { return g->in; }
int gpu_network_outputs(const gpu_network *g) { return g->out; }

static uint32_t ceil_div(uint32_t a, uint32_t b) { return (a + b - 1) / b; }

/* Records the whole forward pass of `rows` rows from/to staging slot `slot`. */
static void record(gpu_network *g, int slot, uint32_t rows) {
  gpu_context *c = g->ctx;
  VkCommandBuffer cmd = g->cmd[slot];
  const VkPipelineStageFlags any = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                                   VK_PIPELINE_STAGE_TRANSFER_BIT;
  const VkAccessFlags rw = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                           VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  c->vk.vkResetCommandBuffer(cmd, 0);
  c->vk.vkBeginCommandBuffer(cmd, &bi);
  if (g->timestamps) c->vk.vkCmdResetQueryPool(cmd, g->timestamps, 2u * (uint32_t)slot, 2);
  /* The previous chunk (earlier in submission order) is done with the shared activation
   * buffers before this one overwrites them. */
  barrier(c, cmd, any, rw);
  VkBufferCopy in = {0, 0, sizeof(float) * (VkDeviceSize)rows * g->in};
  c->vk.vkCmdCopyBuffer(cmd, g->stage_in[slot].buffer, g->buf[g->plan.input].buffer, 1, &in);
  barrier(c, cmd, any, rw);
  if (g->timestamps)
    c->vk.vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, g->timestamps,
                              2u * (uint32_t)slot);
  const int coop = g->precision == GPU_FP16_COOP;
  const uint32_t bm = coop ? 64u : (uint32_t)c->bm, bn = coop ? 64u : (uint32_t)c->bn;
  for (int s = 0; s < g->plan.n_steps; s++) {
    const gpu_step *st = &g->plan.steps[s];
    if (st->kind == GPU_STEP_COPY) {
      VkBufferCopy r = {0, 0, sizeof(float) * (VkDeviceSize)rows * st->push.N};
      c->vk.vkCmdCopyBuffer(cmd, g->buf[st->x].buffer, g->buf[st->y].buffer, 1, &r);
    } else {
      gpu_kernel k = st->kind == GPU_STEP_ROWNORM ? GPU_K_ROWNORM
                     : coop                       ? GPU_K_GEMM_COOP
                                                  : GPU_K_GEMM;
      gpu_push push = st->push;
      push.rows = rows;
      c->vk.vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, c->pipe[k]);
      c->vk.vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, c->layout, 0, 1,
                                    &g->sets[s], 0, NULL);
      c->vk.vkCmdPushConstants(cmd, c->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
      if (k == GPU_K_ROWNORM)
        c->vk.vkCmdDispatch(cmd, rows < 8192u ? rows : 8192u, 1, 1);
      else
        c->vk.vkCmdDispatch(cmd, ceil_div(push.N, bn), ceil_div(rows, bm), 1);
    }
    barrier(c, cmd, any, rw);
  }
  if (g->timestamps)
    c->vk.vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, g->timestamps,
                              2u * (uint32_t)slot + 1u);
  VkBufferCopy out = {0, 0, sizeof(float) * (VkDeviceSize)rows * g->out};
  c->vk.vkCmdCopyBuffer(cmd, g->buf[g->plan.output].buffer, g->stage_out[slot].buffer, 1,
                        &out);
  barrier(c, cmd, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
  c->vk.vkEndCommandBuffer(cmd);
}

/* Waits for slot s's chunk (rows [done, done + m)) and copies its results out. */
static nbrdf_status drain(gpu_network *g, int s, size_t done, size_t m, float *y,
                          nbrdf_error *err) {
  nbrdf_status st = gpu_wait(g->ctx, g->fence[s], err);
  if (st != NBRDF_OK) return st;
  uint64_t t[2];
  if (g->timestamps &&
      g->ctx->vk.vkGetQueryPoolResults(g->ctx->device, g->timestamps, 2u * (uint32_t)s, 2, sizeof t,
                                       t, sizeof t[0], VK_QUERY_RESULT_64_BIT) == VK_SUCCESS &&
      t[1] >= t[0])
    g->device_s += (double)(t[1] - t[0]) * g->ctx->timestamp_ns * 1e-9;
  gpu_buffer_invalidate(g->ctx, &g->stage_out[s]);
  memcpy(y + done * (size_t)g->out, g->stage_out[s].map, sizeof(float) * m * (size_t)g->out);
  return NBRDF_OK;
}

nbrdf_status gpu_network_forward(gpu_network *g, const float *x, size_t rows, float *y,
                                 nbrdf_error *err) {
  if (!g || (rows && (!x || !y)))
    return core_fail(err, NBRDF_ERR_ARGUMENT, "GPU forward: NULL %s",
                     !g ? "network" : !x ? "input" : "output");
  const size_t chunk = (size_t)g->chunk;
  g->device_s = g->timestamps ? 0.0 : -1.0;
  size_t pending_at[2] = {0, 0}, pending_m[2] = {0, 0}; /* m = 0: nothing in flight */
  nbrdf_status st = NBRDF_OK;
  for (size_t done = 0, k = 0; st == NBRDF_OK && done < rows; done += chunk, k++) {
    const int s = (int)(k & 1);
    size_t m = rows - done < chunk ? rows - done : chunk;
    if (pending_m[s]) st = drain(g, s, pending_at[s], pending_m[s], y, err);
    pending_m[s] = 0;
    if (st != NBRDF_OK) break;
    memcpy(g->stage_in[s].map, x + done * (size_t)g->in, sizeof(float) * m * (size_t)g->in);
    gpu_buffer_flush(g->ctx, &g->stage_in[s]);
    record(g, s, (uint32_t)m);
    st = gpu_submit(g->ctx, g->cmd[s], g->fence[s], err);
    if (st == NBRDF_OK) pending_at[s] = done, pending_m[s] = m;
  }
  /* In submission order: the older slot first. */
  size_t k_last = rows ? (rows - 1) / chunk : 0;
  for (int t = 0; t < 2; t++) {
    int s = (int)((k_last + 1 + (size_t)t) & 1);
    if (!pending_m[s]) continue;
    nbrdf_status d = drain(g, s, pending_at[s], pending_m[s], y, err);
    if (st == NBRDF_OK) st = d;
  }
  return st;
}
#else
typedef int gpu_network_unused;
#endif
