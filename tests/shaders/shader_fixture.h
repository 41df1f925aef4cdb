/* Shared by the shader tests and bench_shader: random query directions (grazing ones
 * included) and one call that runs nbrdf_decode.comp on a packed decoder. */
#ifndef NBRDF_TESTS_SHADER_FIXTURE_H
#define NBRDF_TESTS_SHADER_FIXTURE_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/rng.h"
#include "nbrdf/gpu_pack.h"
#include "nbrdf_tiled.h"
#include "vk_harness.h"

/* A unit direction on the upper hemisphere in float: a quarter of them grazing
 * (cos θ in [1e-4, 1e-2]), the rest uniform in cos θ over (0.01, 1]. */
static inline void fixture_direction(core_rng *rng, float out[3]) {
  double u = core_rng_uniform(rng), z;
  if (u < 0.25)
    z = 1e-4 + (1e-2 - 1e-4) * core_rng_uniform(rng);
  else
    z = 0.01 + 0.99 * core_rng_uniform(rng);
  double phi = 2.0 * M_PI * core_rng_uniform(rng), s = sqrt(fmax(0.0, 1.0 - z * z));
  out[0] = (float)(s * cos(phi));
  out[1] = (float)(s * sin(phi));
  out[2] = (float)z;
}

/* Runs nbrdf_decode.comp: queries [n x (6 + dim)] (ωi, ωo, latent) -> out [n x 2] (f, raw
 * output). Returns 0 or -1 (message in vkh_error). *seconds (may be NULL) gets the
 * dispatch's wall time. */
static inline int fixture_run_decoder(vkh *vk, const uint32_t *words, size_t n_words,
                                      const float *queries, size_t n, float *out, double *seconds) {
  int dim = (int)words[NBRDF_GPU_W_LATENT_DIM];
  uint32_t spec[1] = {words[NBRDF_GPU_W_MAX_WIDTH]};
  vkh_buffer wb, qb, ob;
  vkh_kernel k;
  int rc = vkh_buffer_create(vk, n_words * 4, &wb);
  if (!rc) rc = vkh_buffer_create(vk, n * (6 + dim) * sizeof(float), &qb);
  if (!rc) rc = vkh_buffer_create(vk, n * 2 * sizeof(float), &ob);
  if (!rc) rc = vkh_kernel_create(vk, "nbrdf_decode.spv", 3, 4, 1, spec, &k);
  if (rc) return -1;
  memcpy(wb.map, words, n_words * 4);
  memcpy(qb.map, queries, n * (6 + dim) * sizeof(float));
  vkh_buffer *bind[3] = {&wb, &qb, &ob};
  vkh_kernel_bind(vk, &k, bind);
  uint32_t count = (uint32_t)n;
  rc = vkh_run(vk, &k, &count, (uint32_t)((n + 63) / 64), seconds);
  if (!rc) memcpy(out, ob.map, n * 2 * sizeof(float));
  vkh_kernel_destroy(vk, &k);
  vkh_buffer_destroy(vk, &ob);
  vkh_buffer_destroy(vk, &qb);
  vkh_buffer_destroy(vk, &wb);
  return rc;
}

/* The same with a tiled kernel: nbrdf_decode_tiled.spv (coop = 0), the tensor-core
 * nbrdf_decode_coop.spv (coop = 1) or its emulation nbrdf_decode_coopemu.spv (coop = 2),
 * tile sized for this device (shaders/nbrdf_tiled.h). -2 when no tile fits the device. */
static inline int fixture_run_tiled(vkh *vk, const uint32_t *words, size_t n_words,
                                    const float *queries, size_t n, float *out, int coop,
                                    nbrdf_tile_config *used) {
  int dim = (int)words[NBRDF_GPU_W_LATENT_DIM];
  nbrdf_tile_config cfg;
  if (nbrdf_tile_config_make(words, vkh_max_shared(vk), vkh_max_invocations(vk), coop != 0, &cfg))
    return -2; /* no tile fits this device's shared memory */
  if (used) *used = cfg;
  vkh_buffer wb, qb, ob;
  vkh_kernel k;
  /* the fp16 kernels read the weights' fp16 copy appended to the words */
  size_t wn = coop ? nbrdf_tile_f16_words(words, n_words) : n_words;
  int rc = vkh_buffer_create(vk, wn * 4, &wb);
  if (!rc) rc = vkh_buffer_create(vk, n * (6 + dim) * sizeof(float), &qb);
  if (!rc) rc = vkh_buffer_create(vk, n * 2 * sizeof(float), &ob);
  if (!rc)
    rc = vkh_kernel_create(vk,
                           coop == 2   ? "nbrdf_decode_coopemu.spv"
                           : coop == 1 ? "nbrdf_decode_coop.spv"
                                       : "nbrdf_decode_tiled.spv",
                           3, 4, 7, cfg.spec, &k);
  if (rc) return -1;
  if (coop)
    nbrdf_tile_f16_pack(words, n_words, wb.map);
  else
    memcpy(wb.map, words, n_words * 4);
  memcpy(qb.map, queries, n * (6 + dim) * sizeof(float));
  vkh_buffer *bind[3] = {&wb, &qb, &ob};
  vkh_kernel_bind(vk, &k, bind);
  uint32_t count = (uint32_t)n;
  rc = vkh_run(vk, &k, &count, (uint32_t)((n + cfg.rows - 1) / cfg.rows), NULL);
  if (!rc) memcpy(out, ob.map, n * 2 * sizeof(float));
  vkh_kernel_destroy(vk, &k);
  vkh_buffer_destroy(vk, &ob);
  vkh_buffer_destroy(vk, &qb);
  vkh_buffer_destroy(vk, &wb);
  return rc;
}

#endif
