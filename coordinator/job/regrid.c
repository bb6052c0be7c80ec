/* coordinator/job/regrid.c — sub-pixel offsets of the training views per draw (regrid.h). */
#include "coordinator/job/regrid.h"

#include <math.h>

#include "common/optimizer/rng.h"

/* The R2 sequence's steps: 1/g and 1/g² with g the plastic number (Roberts 2018). */
#define R2_A1 0.7548776662466927
#define R2_A2 0.5698402909980532

uint32_t co_regrid_draw(uint64_t evals, uint64_t every)
{
    if (!every)
        return 0;
    uint64_t d = evals / every;
    return d > UINT32_MAX ? UINT32_MAX : (uint32_t)d;
}

uint64_t co_regrid_next(uint32_t draw, uint64_t every)
{
    if (!every || (uint64_t)draw + 1 > UINT64_MAX / every)
        return UINT64_MAX;
    return ((uint64_t)draw + 1) * every;
}

void co_regrid_offset(uint64_t seed, uint32_t draw, uint32_t view, double off[2])
{
    off[0] = off[1] = 0.0;
    if (!draw)
        return;
    lm_rng r;
    lm_rng_seed(&r, seed ^ 0x7265677269642d31ull ^ ((uint64_t)view << 32));
    double u = lm_rng_unit(&r), v = lm_rng_unit(&r);
    double k = (double)draw;
    off[0] = fmod(u + k * R2_A1, 1.0) - 0.5;
    off[1] = fmod(v + k * R2_A2, 1.0) - 0.5;
}

void co_regrid_apply(lm_view_set *s, uint64_t seed, uint32_t draw)
{
    for (uint32_t i = 0; i < s->count && draw; i++) {
        double off[2];
        co_regrid_offset(seed, draw, i, off);
        lm_view_shift(&s->views[i], off[0], off[1]);
    }
}
