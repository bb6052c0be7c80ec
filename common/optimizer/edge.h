/* common/optimizer/edge.h — optimising one edge, on the optimizer's mesh or a lane's copy.
 * Not for other folders. */
#ifndef LM_COMMON_OPTIMIZER_EDGE_H
#define LM_COMMON_OPTIMIZER_EDGE_H

#include "common/optimizer/optimizer_internal.h"

struct lm_lane_log; /* lane_log.h */

/* Where an edge is optimised: the optimizer (statistics, collapse queue, counters), the mesh the
 * moves act on and their workspace. An isolated lane (lanes.h) gives its own copies of the
 * statistics, the teleport state, the touched set and the progress counters, and a log of its
 * statistics adds; NULL fields are the optimizer's own (o may be NULL when none is: a lane run
 * away from the optimizer, lane_host.h). */
typedef struct lm_edge_ctx {
    lm_optimizer *o;
    lm_mesh *mesh;
    lm_moves *mv;
    lm_move_stats *stats;
    lm_teleport *tp;
    lm_idset *touched;
    struct lm_lane_log *log;
    lm_progress *prog; /* where attempted[]/accepted[] are counted (NULL: the optimizer's) */
    int deferred;      /* a lane: energy is counted when its changes are merged */
    uint64_t accepted[LM_MOVE_KINDS]; /* moves accepted through this context */
} lm_edge_ctx;

/* The operations on edge (a, b); *total the ΔE they committed (to the context's views). */
lm_status lm_edge_optimise(lm_edge_ctx *c, uint32_t a, uint32_t b, int64_t *total);

#endif
