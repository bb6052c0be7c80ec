/* coordinator/simplify/pricer.h — who says what a candidate collapse costs, through the views
 * (common/views_api.h) only:
 *   image  ΔE against the original's images (Lindstrom & Turk): the views hold the current mesh;
 *          a batch's patches go to views->ops->evaluate in chunks of at most max_batch, so worker
 *          processes behind the views share every chunk; a collapse is committed to the views.
 *   shard  Pfeiffer's localised cost: each edge's shard (the triangles its collapse changes) is
 *          rendered alone and the collapse priced against that render (incremental difference, no
 *          images of the original anywhere). Shards whose footprints meet in no view and share no
 *          triangle are rendered together: set_mesh of their union, retarget (the render becomes
 *          the target), evaluate. Needs views that offer retarget (in process).
 * Both are exact int64 sums, so the choices do not depend on how the views are split. */
#ifndef LM_COORDINATOR_SIMPLIFY_PRICER_H
#define LM_COORDINATOR_SIMPLIFY_PRICER_H

#include <stdint.h>

#include "common/view.h"
#include "common/views_api.h"
#include "coordinator/simplify/candidates.h"

typedef enum co_price_method { CO_PRICE_IMAGE, CO_PRICE_SHARD } co_price_method;

typedef struct co_pricer_stats {
    uint64_t evaluations; /* patches priced */
    uint64_t calls;       /* evaluate calls */
    uint64_t renders;     /* shard renders (set_mesh + retarget) */
} co_pricer_stats;

typedef struct co_pricer co_pricer;

/* views: borrowed. vs: the views' view set (shard footprints). max_batch 0 = 256. */
lm_status co_pricer_create(co_price_method method, lm_views *views, const lm_view_set *vs,
                           uint32_t max_batch, co_pricer **out);
void co_pricer_destroy(co_pricer *p);

/* c->delta[i] for every patch of c (built by co_cands_build with the same queue). */
lm_status co_pricer_price(co_pricer *p, co_cands *c, co_eq *q);
/* A collapse was made: image views take the patch; shard views need nothing. */
lm_status co_pricer_commit(co_pricer *p, const lm_patch *patch);
/* 1 when a cost depends only on the edge's own triangles (shard): no footprint staleness. */
int co_pricer_is_local(const co_pricer *p);
void co_pricer_stats_get(const co_pricer *p, co_pricer_stats *out);

#endif
