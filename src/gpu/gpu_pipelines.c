/* The embedded kernels (SPIR-V compiled at build time from the .comp files of src/gpu/kernels by
 * glslangValidator --vn: no shader files at run time) and their pipelines. */
#include "gpu/gpu.h"

#if NBRDF_HAVE_GPU
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/gpu_internal.h"

#include "gpu_spv_nn_gemm.h"
#include "gpu_spv_nn_gemm_coop.h"
#include "gpu_spv_nn_rownorm.h"

/* GEMM tiles from the device's limits (shared memory: 4 BK (BM + BN + 2) bytes, the staged
 * tiles' rows padded by one word): 64 x 64 x 16 (8.3 KiB, 4 x 4 outputs per invocation) fits
 * every Vulkan device (the minimum is 16 KiB; lavapipe has 32 KiB); a GPU with room gets
 * 128 x 64 x 32 (24.8 KiB, 8 x 4 per invocation: twice the reuse of each staged word). */
static void choose_tiles(gpu_context *c) {
  c->bm = 64, c->bn = 64, c->bk = 16, c->tm = 4, c->tn = 4;
  uint32_t big = 4u * 32u * (128u + 64u + 2u), square = 4u * 16u * (128u + 128u + 2u);
  /* NBRDF_GPU_GEMM_TILE=128x128 (benchmarks): 128 x 128 x 16 tiles, 8 x 8 per invocation, on
   * any device with room for them (lavapipe too, so its tests can run that configuration). */
  const char *want = getenv("NBRDF_GPU_GEMM_TILE");
  if (want && !strcmp(want, "128x128") && c->limits.shared_bytes >= square &&
      c->limits.max_invocations >= 256) {
    c->bm = 128, c->bn = 128, c->bk = 16, c->tm = 8, c->tn = 8;
    return;
  }
  if (!gpu_context_is_cpu(c) && c->limits.shared_bytes >= big && c->limits.max_invocations >= 256)
    c->bm = 128, c->bk = 32, c->tm = 8;
}

static nbrdf_status make_pipeline(gpu_context *c, const uint32_t *code, size_t bytes,
                                  const int32_t *spec, uint32_t n_spec, VkPipeline *out,
                                  const char *name, nbrdf_error *err) {
  VkShaderModuleCreateInfo smci = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smci.codeSize = bytes;
  smci.pCode = code;
  VkShaderModule module;
  VkResult r = c->vk.vkCreateShaderModule(c->device, &smci, NULL, &module);
  if (r != VK_SUCCESS)
    return core_fail(err, NBRDF_ERR_INTERNAL, "GPU: kernel %s: vkCreateShaderModule failed (%s)",
                     name, gpu_vk_result_name(r));
  VkSpecializationMapEntry entries[8];
  for (uint32_t i = 0; i < n_spec; i++)
    entries[i] = (VkSpecializationMapEntry){i, i * 4u, 4u};
  VkSpecializationInfo si = {n_spec, entries, n_spec * 4u, spec};
  VkComputePipelineCreateInfo ci = {.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = module;
  ci.stage.pName = "main";
  ci.stage.pSpecializationInfo = n_spec ? &si : NULL;
  ci.layout = c->layout;
  r = c->vk.vkCreateComputePipelines(c->device, VK_NULL_HANDLE, 1, &ci, NULL, out);
  c->vk.vkDestroyShaderModule(c->device, module, NULL);
  if (r != VK_SUCCESS)
    return core_fail(err, NBRDF_ERR_INTERNAL, "GPU: kernel %s: pipeline creation failed (%s)",
                     name, gpu_vk_result_name(r));
  return NBRDF_OK;
}

nbrdf_status gpu_pipelines_create(gpu_context *c, nbrdf_error *err) {
  VkDescriptorSetLayoutBinding b[GPU_BINDINGS];
  for (uint32_t i = 0; i < GPU_BINDINGS; i++)
    b[i] = (VkDescriptorSetLayoutBinding){i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
                                          VK_SHADER_STAGE_COMPUTE_BIT, NULL};
  VkDescriptorSetLayoutCreateInfo dl = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dl.bindingCount = GPU_BINDINGS;
  dl.pBindings = b;
  VkPushConstantRange pc = {VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu_push)};
  VkPipelineLayoutCreateInfo pl = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pl.setLayoutCount = 1;
  pl.pSetLayouts = &c->set_layout;
  pl.pushConstantRangeCount = 1;
  pl.pPushConstantRanges = &pc;
  if (c->vk.vkCreateDescriptorSetLayout(c->device, &dl, NULL, &c->set_layout) != VK_SUCCESS ||
      c->vk.vkCreatePipelineLayout(c->device, &pl, NULL, &c->layout) != VK_SUCCESS)
    return core_fail(err, NBRDF_ERR_INTERNAL, "GPU: cannot create the pipeline layout");
  choose_tiles(c);
  int32_t gemm[6] = {(c->bm / c->tm) * (c->bn / c->tn), c->bm, c->bn, c->bk, c->tm, c->tn};
  nbrdf_status st = make_pipeline(c, gpu_spv_nn_gemm, sizeof gpu_spv_nn_gemm, gemm, 6,
                                  &c->pipe[GPU_K_GEMM], "nn_gemm", err);
  if (st == NBRDF_OK)
    st = make_pipeline(c, gpu_spv_nn_rownorm, sizeof gpu_spv_nn_rownorm, NULL, 0,
                       &c->pipe[GPU_K_ROWNORM], "nn_rownorm", err);
  /* The tensor-core kernel: 4 subgroups of 32, each a 32 x 32 block of the workgroup's 64 x 64
   * tile (nn_gemm_coop.comp); only where gpu_context_open enabled the extension. */
  if (st == NBRDF_OK && c->limits.coop_matrix) {
    nbrdf_error coop_err;
    if (make_pipeline(c, gpu_spv_nn_gemm_coop, sizeof gpu_spv_nn_gemm_coop, NULL, 0,
                      &c->pipe[GPU_K_GEMM_COOP], "nn_gemm_coop", &coop_err) != NBRDF_OK) {
      c->limits.coop_matrix = 0;
      snprintf(c->limits.coop_note, sizeof c->limits.coop_note, "%.150s", coop_err.message);
    }
  }
  return st;
}

void gpu_pipelines_destroy(gpu_context *c) {
  for (int k = 0; k < GPU_K_COUNT; k++)
    if (c->pipe[k]) c->vk.vkDestroyPipeline(c->device, c->pipe[k], NULL);
  if (c->layout) c->vk.vkDestroyPipelineLayout(c->device, c->layout, NULL);
  if (c->set_layout) c->vk.vkDestroyDescriptorSetLayout(c->device, c->set_layout, NULL);
}
#else
typedef int gpu_pipelines_unused;
#endif
