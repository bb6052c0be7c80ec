/* coordinator/frog/frog_internal.h — what the frog's geometry (frog.c) and its texture
 * (common/frog_texture.c) must agree on: the texture atlas charts and the seeded random stream. */
#ifndef LM_COMMON_FROG_INTERNAL_H
#define LM_COMMON_FROG_INTERNAL_H

#include <stdint.h>

/* Texture charts in UV space (u0, v0, u1, v1), 4 texels of padding around each so bilinear
 * filtering never mixes charts. The body gets the left half, legs and eyes share the right. */
enum { CO_FROG_CHART_BODY, CO_FROG_CHART_LEGS, CO_FROG_CHART_EYES, CO_FROG_CHARTS };
#define CO_FROG_PAD (4.0f / 1024.0f)
static const float co_frog_charts[CO_FROG_CHARTS][4] = {
    {CO_FROG_PAD, CO_FROG_PAD, 0.5f - CO_FROG_PAD, 1.0f - CO_FROG_PAD},
    {0.5f + CO_FROG_PAD, CO_FROG_PAD, 1.0f - CO_FROG_PAD, 0.5f - CO_FROG_PAD},
    {0.5f + CO_FROG_PAD, 0.5f + CO_FROG_PAD, 1.0f - CO_FROG_PAD, 1.0f - CO_FROG_PAD},
};

/* Chart-local coordinates: s runs around a part (0 and 1 at its underside seam, 0.5 on top),
 * f along it (0 at the start pole: back / hip / inside the head; 1 at the end: snout / toes /
 * the eye's pupil). */

/* splitmix64: a seeded stream, no global state. */
typedef struct co_frog_rng {
    uint64_t s;
} co_frog_rng;

static inline uint64_t co_frog_next(co_frog_rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [lo, hi). */
static inline double co_frog_uniform(co_frog_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * (double)(co_frog_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

#endif
