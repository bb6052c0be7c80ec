/* common/optimizer/lane_views.h — what a lane's moves see as "the views" (lanes.c).
 *
 * A lane optimises one edge on its own copy of the mesh while other lanes do the same; none of
 * them commits to the real views until the group is merged, so every evaluation of the group is
 * priced against one state, the group's start. The lane's accepted changes are kept here as one
 * composite patch `acc` (start -> the lane's mesh) with its exact ΔE `d_acc`; a patch P the lane's
 * moves evaluate (relative to the lane's mesh) goes out as compose(acc, P), and its answer comes
 * back as ΔE(compose(acc, P)) - d_acc = E(lane + P) - E(lane), exactly what the views would say
 * had the lane committed. Commit and set_mesh (a revert) only change acc; the ΔE of a commit comes
 * from the move that accepted it (lanes.c's observer), so nothing is evaluated twice.
 * Blocking: evaluate hands its batch to the lanes' scheduler and waits for the answer. */
#ifndef LM_COMMON_OPTIMIZER_LANE_VIEWS_H
#define LM_COMMON_OPTIMIZER_LANE_VIEWS_H

#include <stddef.h>
#include <stdint.h>

#include "common/patch.h"
#include "common/views_api.h"

typedef struct lm_lane lm_lane; /* lanes.c */

typedef struct lm_lane_views {
    lm_views base;
    lm_lane *lane;
    lm_views *real;   /* for info */
    lm_views *direct; /* when set, evaluate asks it at once (a lane run on its own, lane_host.h)
                         instead of handing the request to the lanes' scheduler */
    const lm_tri_data *start; /* the group's start, sorted by id (shared, read only) */
    size_t n_start;
    lm_patch acc, tmp; /* start -> the lane's mesh; removed and added sorted by id */
    int64_t d_acc;     /* its exact ΔE */
    int64_t pending;   /* ΔE of the commit about to come (from the observer) */
    lm_patch *req;     /* the composite patches of the request in flight */
    uint32_t n_req, cap_req;
    int64_t *res; /* their answers */
} lm_lane_views;

void lm_lane_views_init(lm_lane_views *v, lm_lane *lane, lm_views *real);
void lm_lane_views_free(lm_lane_views *v);
/* A new group: the start records, an empty acc. */
void lm_lane_views_reset(lm_lane_views *v, const lm_tri_data *start, size_t n_start);

/* Hand the request (v->req, v->n_req) to the scheduler and wait until v->res holds the answers
 * (implemented by lanes.c). */
lm_status lm_lane_post(lm_lane *lane);

#endif
