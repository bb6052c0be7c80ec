/* coordinator/optimizer/edge.h — optimising one edge, on the optimizer's mesh or a lane's copy.
 * Not for other folders. */
#ifndef LM_COORDINATOR_OPTIMIZER_EDGE_H
#define LM_COORDINATOR_OPTIMIZER_EDGE_H

#include "coordinator/optimizer/optimizer_internal.h"

/* Where an edge is optimised: the optimizer (statistics, collapse queue, counters), the mesh the
 * moves act on and their workspace. */
typedef struct co_edge_ctx {
    co_optimizer *o;
    lm_mesh *mesh;
    co_moves *mv;
    int deferred;                     /* a lane: energy is counted when its changes are merged */
    uint64_t accepted[CO_MOVE_KINDS]; /* moves accepted through this context */
} co_edge_ctx;

/* The operations on edge (a, b); *total the ΔE they committed (to the context's views). */
lm_status co_edge_optimise(co_edge_ctx *c, uint32_t a, uint32_t b, int64_t *total);

#endif
