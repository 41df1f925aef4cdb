/* Pipeline constants of the tiled decoder kernels (shaders/nbrdf_tiled.glsl): header-only C
 * for a renderer (and tests/shaders, bench/bench_shader.c).
 *
 *   nbrdf_tile_config cfg;
 *   nbrdf_tile_config_make(words, limits.maxComputeSharedMemorySize,
 *                          limits.maxComputeWorkGroupInvocations, coop, &cfg);
 *   specialization constants 0..6 = cfg.spec[0..6] (32-bit each);
 *   dispatch ceil(rows / cfg.rows) workgroups (rows = queries x colours for the shade kernel)
 *
 * `coop` = 0 for nbrdf_{decode,shade}_tiled.spv (fp32, any Vulkan 1.1 device), 1 for
 * nbrdf_{decode,shade}_coop.spv (fp16 tensor cores: needs VK_NV_cooperative_matrix with a
 * 16x16x16 fp16 x fp16 + fp32 subgroup shape, shaderFloat16 and vulkanMemoryModel; a
 * subgroup size of 32). The tile is the largest (128 .. 4 rows fp32, 64 .. 16 coop) whose
 * activations plus a useful chunk of a layer's weights fit the shared memory: on a
 * 48 KiB device the 96-wide default decoder gets 64 rows (fp32) / 32 rows (coop), on
 * lavapipe's 32 KiB 32 rows (fp32). */
#ifndef NBRDF_SHADERS_TILED_H
#define NBRDF_SHADERS_TILED_H

#include <stdint.h>

typedef struct nbrdf_tile_config {
  uint32_t spec[7];      /* specialization constants 0..6 (nbrdf_tiled.glsl's list) */
  uint32_t rows;         /* rows (queries, or query x colour) per workgroup */
  uint32_t threads;      /* workgroup size */
  uint32_t shared_bytes; /* shared memory the kernel declares */
} nbrdf_tile_config;

static inline uint32_t nbrdf_tile_round_(uint32_t v, uint32_t m) { return (v + m - 1) / m * m; }

/* 0 on success, -1 when no tile fits (a network far wider than the `paper` preset). */
static inline int nbrdf_tile_config_make(const uint32_t *words, uint32_t max_shared,
                                         uint32_t max_threads, int coop, nbrdf_tile_config *c) {
  uint32_t inputs = words[2], layers = words[3];
  uint32_t xw = inputs, hw = 4, nmax = 1, kmax = inputs, keep = 0;
  for (uint32_t l = 0; l < layers; l++) {
    const uint32_t *r = words + 16 + 16 * l;
    uint32_t in = r[1], out = r[2], hidden = r[3];
    if (out > xw) xw = out;
    if (out > nmax) nmax = out;
    if (in > kmax) kmax = in;
    if (r[0] == 5u) { /* residual */
      if (hidden > hw) hw = hidden;
      if (hidden > nmax) nmax = hidden;
    }
    if (r[4] != 0xffffffffu) keep = 1;
  }
  for (int i = 0; i < 7; i++)
    c->spec[i] = 0;
  if (!coop) {
    const uint32_t tiles[6] = {128, 64, 32, 16, 8, 4};
    uint32_t XW = nbrdf_tile_round_(xw, 4), HW = nbrdf_tile_round_(hw, 4);
    uint32_t INW = keep ? nbrdf_tile_round_(inputs, 4) : 4, np = nbrdf_tile_round_(nmax, 4);
    for (int t = 0; t < 6; t++) {
      uint32_t T = tiles[t], act = T * (XW + HW + INW);
      if (4 * act >= max_shared) continue;
      /* weights [k][npp]: npp = np + 4 where np is a multiple of 8 (nbrdf_tiled.glsl) */
      uint32_t npp = np % 8 == 0 ? np + 4 : np;
      uint32_t room = (max_shared / 4 - act) & ~3u, full = npp * kmax;
      uint32_t need = npp * (kmax < 16 ? kmax : 16);
      uint32_t wch = room < full ? room : full;
      if (wch < need) continue;
      uint32_t threads = 2 * T < 64 ? 64 : 2 * T;
      if (threads > max_threads) threads = max_threads;
      uint32_t blocks = (T / 4) * (np / 4);
      c->spec[0] = XW, c->spec[1] = threads, c->spec[2] = T, c->spec[3] = HW;
      c->spec[4] = INW, c->spec[5] = wch, c->spec[6] = (blocks + threads - 1) / threads;
      c->rows = T, c->threads = threads, c->shared_bytes = 4 * (act + wch);
      return 0;
    }
    return -1;
  }
  const uint32_t tiles[3] = {64, 32, 16};
  uint32_t XW = nbrdf_tile_round_(xw, 16), HW = nbrdf_tile_round_(hw, 16);
  uint32_t XS = XW + 4, HS = HW + 4, INW = keep ? nbrdf_tile_round_(inputs, 16) : 4;
  uint32_t AS = (XW > HW ? XW : HW) + 8, np = nbrdf_tile_round_(nmax, 16);
  uint32_t kp = nbrdf_tile_round_(kmax, 16);
  for (int t = 0; t < 3; t++) {
    uint32_t T = tiles[t];
    uint32_t f32 = 4 * T * (XS + HS + INW), f16 = 2 * T * (AS + INW + 16);
    if (f32 + f16 >= max_shared) continue;
    uint32_t room = (max_shared - f32 - f16) / 2, full = np * kp;
    uint32_t wch = room < full ? room : full;
    if (wch < np * 16) continue;
    uint32_t ntiles = (T / 16) * (np / 16), sg = (ntiles + 3) / 4, threads = 128;
    while (threads < 32 * sg)
      threads *= 2;
    if (threads > max_threads) continue;
    c->spec[0] = XS, c->spec[1] = threads, c->spec[2] = T, c->spec[3] = HS;
    c->spec[4] = INW, c->spec[5] = wch, c->spec[6] = AS;
    c->rows = T, c->threads = threads, c->shared_bytes = f32 + f16 + 2 * wch;
    return 0;
  }
  return -1;
}

#endif
