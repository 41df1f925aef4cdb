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

#include <stddef.h>
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
    (void)kp; /* the weights are read from the buffer's fp16 copy: nothing staged */
    uint32_t ntiles = (T / 16) * (np / 16), sg = (ntiles + 3) / 4, threads = 128;
    while (threads < 32 * sg)
      threads *= 2;
    if (threads > max_threads) continue;
    c->spec[0] = XS, c->spec[1] = threads, c->spec[2] = T, c->spec[3] = HS;
    c->spec[4] = INW, c->spec[5] = 0, c->spec[6] = AS;
    c->rows = T, c->threads = threads, c->shared_bytes = f32 + f16;
    return 0;
  }
  return -1;
}

/* The fp16 copy of the weights the tensor-core kernels read (nbrdf_{decode,shade}_coop.spv
 * and _coopemu.spv; the fp32 kernels ignore it): the packed words, then, 64-byte aligned,
 * per layer the GEMM matrices w1, w2 (residual) and wskip (a projected skip) as fp16 (round
 * to nearest even, clamped to +-65504), each [round16(N)][round16(K)] halfs, zero-padded,
 * row n = output n (the column-major B = W^T coopMatLoadNV reads; two halfs a word, the
 * first in the low bits). Word 15 of a layer's record = the word offset of its first
 * matrix (0: the layer has none). Pack once per decoder, upload that buffer instead:
 *   n = nbrdf_tile_f16_words(words, n_words); out = malloc(4 * n);
 *   nbrdf_tile_f16_pack(words, n_words, out); */
static inline uint16_t nbrdf_tile_half_(float f) {
  union {
    float f;
    uint32_t u;
  } v;
  v.f = f > 65504.0f ? 65504.0f : f < -65504.0f ? -65504.0f : f;
  uint32_t x = v.u & 0x7fffffffu, sign = (v.u >> 16) & 0x8000u;
  if (x >= 0x38800000u) { /* a normal half: round the mantissa to 10 bits, rebias */
    x += 0xfffu + ((x >> 13) & 1u);
    return (uint16_t)(sign | ((x - 0x38000000u) >> 13));
  }
  if (x < 0x33000000u) return (uint16_t)sign; /* below half of the smallest subnormal */
  uint32_t e = x >> 23, m = (x & 0x7fffffu) | 0x800000u, shift = 126u - e;
  uint32_t h = m >> shift, rem = m & ((1u << shift) - 1u), half = 1u << (shift - 1u);
  if (rem > half || (rem == half && (h & 1u))) h++;
  return (uint16_t)(sign | h);
}

/* The GEMM matrices of layer record r, in the kernel's order: (parameter offset, K, N)
 * triples in shapes; returns their count (0..3). */
static inline uint32_t nbrdf_tile_f16_layer_(const uint32_t *r, uint32_t *shapes) {
  uint32_t n = 0, kind = r[0], in = r[1], out = r[2], hidden = r[3];
  if (kind == 1u || kind == 4u || kind == 5u) { /* linear, plain, residual */
    shapes[3 * n] = r[6], shapes[3 * n + 1] = in, shapes[3 * n + 2] = kind == 5u ? hidden : out;
    n++;
    if (kind == 5u) shapes[3 * n] = r[10], shapes[3 * n + 1] = hidden, shapes[3 * n + 2] = out, n++;
    if (r[4] != 0xffffffffu && r[14] != 0xffffffffu)
      shapes[3 * n] = r[14], shapes[3 * n + 1] = r[5], shapes[3 * n + 2] = out, n++;
  }
  return n;
}

static inline size_t nbrdf_tile_f16_words(const uint32_t *words, size_t n_words) {
  size_t total = nbrdf_tile_round_((uint32_t)n_words, 16);
  for (uint32_t l = 0; l < words[3]; l++) {
    uint32_t shapes[9], n = nbrdf_tile_f16_layer_(words + 16 + 16 * l, shapes);
    for (uint32_t i = 0; i < n; i++)
      total +=
          nbrdf_tile_round_(shapes[3 * i + 1], 16) * nbrdf_tile_round_(shapes[3 * i + 2], 16) / 2;
  }
  return total;
}

static inline void nbrdf_tile_f16_pack(const uint32_t *words, size_t n_words, uint32_t *out) {
  size_t at = nbrdf_tile_round_((uint32_t)n_words, 16), base = words[10];
  for (size_t i = 0; i < at; i++)
    out[i] = i < n_words ? words[i] : 0u;
  for (uint32_t l = 0; l < words[3]; l++) {
    uint32_t shapes[9], n = nbrdf_tile_f16_layer_(words + 16 + 16 * l, shapes);
    out[16 + 16 * l + 15] = n ? (uint32_t)at : 0u;
    for (uint32_t i = 0; i < n; i++) {
      uint32_t K = shapes[3 * i + 1], N = shapes[3 * i + 2];
      uint32_t kp = nbrdf_tile_round_(K, 16), np = nbrdf_tile_round_(N, 16);
      const uint32_t *w = words + base + shapes[3 * i];
      for (uint32_t o = 0; o < np; o++)
        for (uint32_t k = 0; k < kp; k += 2) {
          uint32_t h[2] = {0, 0};
          for (uint32_t d = 0; d < 2; d++)
            if (o < N && k + d < K) {
              union {
                uint32_t u;
                float f;
              } v;
              v.u = w[o * K + k + d];
              h[d] = nbrdf_tile_half_(v.f);
            }
          out[at++] = h[0] | h[1] << 16;
        }
    }
  }
}

#endif
