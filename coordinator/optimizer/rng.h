/* coordinator/optimizer/rng.h — the optimizer's deterministic pseudo-random numbers: xoshiro256**
 * seeded through splitmix64. The state is a plain value inside its owner (no globals), so it can be
 * checkpointed and a resumed run draws the same numbers as an uninterrupted one. */
#ifndef LM_COORDINATOR_RNG_H
#define LM_COORDINATOR_RNG_H

#include <stdint.h>

typedef struct co_rng {
    uint64_t s[4];
} co_rng;

void co_rng_seed(co_rng *r, uint64_t seed);
uint64_t co_rng_next(co_rng *r);
/* Uniform integer in [0, n) without modulo bias; n > 0. */
uint64_t co_rng_below(co_rng *r, uint64_t n);
/* Uniform double in [0, 1) with 53 random bits. */
double co_rng_unit(co_rng *r);

#endif
