/* gpu.h in a build without the Vulkan backend (no glslang or Vulkan headers at build time, or
 * -DNBRDF_BUILD_SHADERS=OFF): every open says so; the callers run the networks on the CPU. */
#include "gpu/gpu.h"

#if !NBRDF_HAVE_GPU
#include "core/error.h"

int gpu_built(void) { return 0; }

nbrdf_status gpu_context_open(gpu_choice choice, gpu_context **out, nbrdf_error *err) {
  (void)choice;
  *out = NULL;
  return core_fail(err, NBRDF_ERR_UNSUPPORTED, "this nbrdf was built without GPU support");
}
void gpu_context_close(gpu_context *ctx) { (void)ctx; }
const char *gpu_context_name(const gpu_context *ctx) { return "none"; }
int gpu_context_is_cpu(const gpu_context *ctx) { return 0; }
const gpu_limits *gpu_context_limits(const gpu_context *ctx) { return NULL; }
nbrdf_status gpu_network_create(gpu_context *ctx, const nn_network *nn, gpu_precision precision,
                                int max_rows, gpu_network **out, nbrdf_error *err) {
  *out = NULL;
  return core_fail(err, NBRDF_ERR_UNSUPPORTED, "this nbrdf was built without GPU support");
}
void gpu_network_destroy(gpu_network *net) { (void)net; }
int gpu_network_chunk_rows(const gpu_network *net) { return 0; }
int gpu_network_inputs(const gpu_network *net) { return 0; }
int gpu_network_outputs(const gpu_network *net) { return 0; }
double gpu_network_device_seconds(const gpu_network *net) { return -1.0; }
nbrdf_status gpu_network_forward(gpu_network *net, const float *x, size_t rows, float *y,
                                 nbrdf_error *err) {
  return core_fail(err, NBRDF_ERR_UNSUPPORTED, "this nbrdf was built without GPU support");
}
#else
typedef int gpu_stub_unused;
#endif
