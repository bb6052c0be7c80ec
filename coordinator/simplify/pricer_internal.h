/* coordinator/simplify/pricer_internal.h — the pricer's state, shared by pricer.c (the object,
 * the image method) and pricer_shard.c. Not for other files. */
#ifndef LM_COORDINATOR_SIMPLIFY_PRICER_INTERNAL_H
#define LM_COORDINATOR_SIMPLIFY_PRICER_INTERNAL_H

#include "coordinator/simplify/pricer.h"

struct co_pricer {
    co_price_method method;
    lm_views *views;
    const lm_view_set *vs;
    uint32_t max_batch;
    co_pricer_stats stats;
    /* shard: groups of edges rendered together */
    uint32_t *group; /* [edges]: group of each edge of the batch */
    uint32_t *order; /* edges sorted by group */
    uint32_t cap_group;
    lm_tri_data *tris; /* the union of one group's shards */
    uint32_t cap_tris;
    lm_patch *patches; /* one group's patches (shallow copies) */
    int64_t *delta;
    uint32_t cap_patches;
};

lm_status co_pricer_evaluate(co_pricer *p, const lm_patch *patches, uint32_t n, int64_t *delta);
lm_status co_shard_price(co_pricer *p, co_cands *c, co_eq *q);
void co_shard_free(co_pricer *p);

#endif
