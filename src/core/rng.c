#include "core/rng.h"

#include <math.h>

static const uint64_t PCG_MULT = 6364136223846793005ULL;

uint64_t nbrdf_hash64(uint64_t a, uint64_t b) {
  uint64_t z = a + 0x9e3779b97f4a7c15ULL * (b + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

void nbrdf_rng_init(nbrdf_rng *rng, uint64_t seed, uint64_t stream) {
  rng->state = 0;
  rng->inc = (nbrdf_hash64(stream, 0x5eed) << 1u) | 1u;
  nbrdf_rng_u32(rng);
  rng->state += nbrdf_hash64(seed, stream);
  nbrdf_rng_u32(rng);
}

uint32_t nbrdf_rng_u32(nbrdf_rng *rng) {
  uint64_t old = rng->state;
  rng->state = old * PCG_MULT + rng->inc;
  uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  uint32_t rot = (uint32_t)(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
}

double nbrdf_rng_uniform(nbrdf_rng *rng) {
  uint64_t hi = nbrdf_rng_u32(rng), lo = nbrdf_rng_u32(rng);
  uint64_t bits = ((hi << 32) | lo) >> 11;
  return (double)bits * 0x1.0p-53;
}

float nbrdf_rng_uniformf(nbrdf_rng *rng) {
  return (float)(nbrdf_rng_u32(rng) >> 8) * 0x1.0p-24f;
}

double nbrdf_rng_normal(nbrdf_rng *rng) {
  double u1 = 1.0 - nbrdf_rng_uniform(rng); /* (0, 1]: log is finite */
  double u2 = nbrdf_rng_uniform(rng);
  return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}
