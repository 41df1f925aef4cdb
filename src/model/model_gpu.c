/* model_gpu.h, and the public names of nbrdf_device. */
#include "model/model_gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "model/bundle.h"

static const char *const device_names[] = {"cpu", "auto", "gpu"};

const char *nbrdf_device_name(nbrdf_device device) {
  return device >= NBRDF_DEVICE_CPU && device <= NBRDF_DEVICE_GPU ? device_names[device] : "?";
}

int nbrdf_device_parse(const char *name) {
  for (int i = 0; name && i < 3; i++)
    if (!strcmp(name, device_names[i])) return i;
  return -1;
}

void model_gpu_close(model_gpu *g) {
  if (!g) return;
  gpu_network_destroy(g->layering);
  gpu_network_destroy(g->sampler);
  gpu_network_destroy(g->decoder);
  gpu_context_close(g->ctx);
  free(g);
}

static nbrdf_status open_gpu(const nbrdf_model *m, const nbrdf_model *dm, nbrdf_device device,
                             unsigned nets, model_gpu **out, nbrdf_error *err) {
  model_gpu *g = calloc(1, sizeof *g);
  if (!g) return core_fail(err, NBRDF_ERR_MEMORY, "GPU: out of memory");
  nbrdf_status st = gpu_context_open(device == NBRDF_DEVICE_GPU ? GPU_CHOICE_GPU : GPU_CHOICE_AUTO,
                                     &g->ctx, err);
  /* A CPU device (lavapipe, asked for by name) gets small chunks: it runs the layering
   * network at ~200 rows/s, and cancel is seen between chunks. */
  int cap = st == NBRDF_OK && gpu_context_is_cpu(g->ctx) ? 128 : 0;
  if (st == NBRDF_OK && (nets & MODEL_GPU_LAYERING))
    st = gpu_network_create(g->ctx, m->layering->nn, GPU_FP32, cap, &g->layering, err);
  if (st == NBRDF_OK && (nets & MODEL_GPU_SAMPLER))
    st = gpu_network_create(g->ctx, m->sampler->nn, GPU_FP32, cap, &g->sampler, err);
  if (st == NBRDF_OK && (nets & MODEL_GPU_DECODER))
    st = gpu_network_create(g->ctx, dm->decoder->nn, GPU_FP32, cap, &g->decoder, err);
  if (st != NBRDF_OK) {
    model_gpu_close(g);
    return st;
  }
  g->batch = (size_t)(g->layering   ? gpu_network_chunk_rows(g->layering)
                      : g->decoder  ? gpu_network_chunk_rows(g->decoder)
                      : g->sampler  ? gpu_network_chunk_rows(g->sampler)
                                    : 256);
  *out = g;
  return NBRDF_OK;
}

nbrdf_status model_gpu_open(const nbrdf_model *model, const nbrdf_model *decoder_model,
                            nbrdf_device device, unsigned nets, model_gpu **out, char *note,
                            size_t note_size, nbrdf_error *err) {
  *out = NULL;
  if (note && note_size) note[0] = '\0';
  if (device == NBRDF_DEVICE_CPU) return NBRDF_OK;
  if (device != NBRDF_DEVICE_AUTO && device != NBRDF_DEVICE_GPU)
    return core_fail(err, NBRDF_ERR_ARGUMENT, "device %d is not cpu, auto or gpu", (int)device);
  nbrdf_error why;
  nbrdf_status st = open_gpu(model, decoder_model ? decoder_model : model, device, nets, out, &why);
  if (st == NBRDF_OK) {
    if (note)
      snprintf(note, note_size, "networks on the GPU: %s (Vulkan)", gpu_context_name((*out)->ctx));
    return NBRDF_OK;
  }
  if (device == NBRDF_DEVICE_GPU)
    return core_fail(err, st, "device gpu: %s", why.message);
  if (note) snprintf(note, note_size, "no GPU for the networks (%.400s): they run on the CPU", why.message);
  return NBRDF_OK;
}

nbrdf_status model_gpu_runner(gpu_network *gpu, int max_batch, model_runner *runner,
                              nbrdf_error *err) {
  memset(runner, 0, sizeof *runner);
  runner->gpu = gpu;
  runner->max_batch = max_batch;
  runner->x = malloc(sizeof(float) * (size_t)max_batch * (size_t)gpu_network_inputs(gpu));
  runner->y = malloc(sizeof(float) * (size_t)max_batch * (size_t)gpu_network_outputs(gpu));
  if (!runner->x || !runner->y) {
    model_runner_destroy(runner);
    return core_fail(err, NBRDF_ERR_MEMORY, "out of memory for a batch of %d rows", max_batch);
  }
  return NBRDF_OK;
}
