/* coordinator/optimizer/optimizer_internal.h — the optimizer object, shared by optimizer.c (the
 * edge loop) and optimizer_state.c (checkpoint save/load). Not for other files. */
#ifndef LM_COORDINATOR_OPTIMIZER_INTERNAL_H
#define LM_COORDINATOR_OPTIMIZER_INTERNAL_H

#include "coordinator/optimizer/move_stats.h"
#include "coordinator/optimizer/moves.h"
#include "coordinator/optimizer/optimizer.h"
#include "coordinator/optimizer/optimizer_tuning.h"
#include "coordinator/optimizer/oracle.h"
#include "coordinator/optimizer/rng.h"
#include "coordinator/optimizer/teleport.h"

typedef struct co_iteration {
    int active;
    uint32_t pos, n_plan;
    co_planned_edge *plan; /* [edges_per_iteration] */
    double gain[2];        /* energy reductions by source: 0 random, 1 oracle */
    uint32_t count[2];
    uint64_t *no_progress; /* edges that gained nothing [edges_per_iteration] */
    uint32_t n_no_progress;
    co_idset touched; /* vertices around the moves accepted in this iteration */
} co_iteration;

typedef struct co_lanes co_lanes; /* lanes.h */

struct co_optimizer {
    lm_mesh *mesh;
    lm_views *views;   /* what the moves price against: the caller's, or surface over them */
    lm_views *surface; /* the geometric term over the caller's views (owned); NULL = none */
    co_params params;
    co_moves_config moves_cfg; /* every move workspace's (the optimizer's, its lanes') */
    co_lanes *lanes;           /* edges in flight (NULL when one at a time) */
    co_tuning tuning;          /* resolved (no zero fields) */
    uint32_t attrs;            /* effective optimised attributes */
    co_moves *mv;
    co_move_stats stats;
    co_teleport tp;
    co_oracle oracle;
    co_rng rng;
    co_progress prog; /* evals is kept in mv */
    co_iteration it;
};

#endif
