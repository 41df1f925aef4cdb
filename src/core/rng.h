/* PCG32 random numbers (O'Neill 2014). Results must not depend on the number
 * of threads, so parallel code seeds one generator per work item with
 * core_rng_init(seed, item_index) instead of sharing a generator. */
#ifndef NBRDF_CORE_RNG_H
#define NBRDF_CORE_RNG_H

#include <stdint.h>

typedef struct core_rng {
  uint64_t state;
  uint64_t inc;
} core_rng;

/* `stream` selects one of 2^63 independent sequences for the same seed. */
void core_rng_init(core_rng *rng, uint64_t seed, uint64_t stream);
uint32_t core_rng_u32(core_rng *rng);
/* Uniform in [0, 1), 53 random bits. */
double core_rng_uniform(core_rng *rng);
/* Uniform in [0, 1) as float, never rounding up to 1. */
float core_rng_uniformf(core_rng *rng);
/* Standard normal (Box–Muller). */
double core_rng_normal(core_rng *rng);
/* Mixes two 64-bit values into a well-distributed seed (splitmix64). */
uint64_t core_hash64(uint64_t a, uint64_t b);

#endif
