/* common/optimizer/optimizer_internal.h — the optimizer object, shared by optimizer.c (the
 * edge loop) and optimizer_state.c (checkpoint save/load). Not for other files. */
#ifndef LM_COMMON_OPTIMIZER_OPTIMIZER_INTERNAL_H
#define LM_COMMON_OPTIMIZER_OPTIMIZER_INTERNAL_H

#include "common/optimizer/move_stats.h"
#include "common/optimizer/moves.h"
#include "common/optimizer/optimizer.h"
#include "common/optimizer/optimizer_tuning.h"
#include "common/optimizer/oracle.h"
#include "common/optimizer/rng.h"
#include "common/optimizer/teleport.h"

typedef struct lm_iteration {
    int active;
    uint32_t pos, n_plan;
    lm_planned_edge *plan; /* [edges_per_iteration] */
    double gain[2];        /* energy reductions by source: 0 random, 1 oracle */
    uint32_t count[2];
    uint64_t *no_progress; /* edges that gained nothing [edges_per_iteration] */
    uint32_t n_no_progress;
    lm_idset touched; /* vertices around the moves accepted in this iteration */
} lm_iteration;

typedef struct lm_lanes lm_lanes; /* lanes.h */

struct lm_optimizer {
    lm_mesh *mesh;
    lm_views *views;   /* what the moves price against: the caller's, or surface over them */
    lm_views *surface; /* the geometric term over the caller's views (owned); NULL = none */
    lm_params params;
    lm_moves_config moves_cfg; /* every move workspace's (the optimizer's, its lanes') */
    lm_lanes *lanes;           /* edges in flight (NULL when one at a time) */
    int64_t *totals;           /* ΔE of each edge of the group in flight [edges_in_flight] */
    lm_tuning tuning;          /* resolved (no zero fields) */
    uint32_t attrs;            /* effective optimised attributes */
    lm_moves *mv;
    lm_move_stats stats;
    lm_teleport tp;
    lm_oracle oracle;
    lm_rng rng;
    lm_progress prog; /* evals is kept in mv */
    lm_iteration it;
};

#endif
