/* common/optimizer/rng.h — the optimizer's deterministic pseudo-random numbers: xoshiro256**
 * seeded through splitmix64. The state is a plain value inside its owner (no globals), so it can be
 * checkpointed and a resumed run draws the same numbers as an uninterrupted one. */
#ifndef LM_COMMON_OPTIMIZER_RNG_H
#define LM_COMMON_OPTIMIZER_RNG_H

#include <stdint.h>

typedef struct lm_rng {
    uint64_t s[4];
} lm_rng;

void lm_rng_seed(lm_rng *r, uint64_t seed);
uint64_t lm_rng_next(lm_rng *r);
/* Uniform integer in [0, n) without modulo bias; n > 0. */
uint64_t lm_rng_below(lm_rng *r, uint64_t n);
/* Uniform double in [0, 1) with 53 random bits. */
double lm_rng_unit(lm_rng *r);

#endif
