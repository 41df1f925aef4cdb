#include "core/rng.h"

#include <math.h>

static const uint64_t PCG_MULT = 6364136223846793005ULL;

uint64_t core_hash64(uint64_t a, uint64_t b) {
  uint64_t z = a + 0x9e3779b97f4a7c15ULL * (b + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

void core_rng_init(core_rng *rng, uint64_t seed, uint64_t stream) {
  rng->state = 0;
  rng->inc = (core_hash64(stream, 0x5eed) << 1u) | 1u;
  core_rng_u32(rng);
  rng->state += core_hash64(seed, stream);
  core_rng_u32(rng);
}

uint32_t core_rng_u32(core_rng *rng) {
  uint64_t old = rng->state;
  rng->state = old * PCG_MULT + rng->inc;
  uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  uint32_t rot = (uint32_t)(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
}

double core_rng_uniform(core_rng *rng) {
  uint64_t hi = core_rng_u32(rng), lo = core_rng_u32(rng);
  uint64_t bits = ((hi << 32) | lo) >> 11;
  return (double)bits * 0x1.0p-53;
}

float core_rng_uniformf(core_rng *rng) {
  return (float)(core_rng_u32(rng) >> 8) * 0x1.0p-24f;
}

double core_rng_normal(core_rng *rng) {
  double u1 = 1.0 - core_rng_uniform(rng); /* (0, 1]: log is finite */
  double u2 = core_rng_uniform(rng);
  return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}
