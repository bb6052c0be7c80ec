/* common/optimizer/lanes.h — several edges in flight at once (the optimizer's `edges in
 * flight` parameter K > 1). Not for other folders.
 *
 * A group is a set of planned edges, taken in plan order from the next few, whose neighbourhoods
 * (two rings) do not meet.
 * Each edge of a group is optimised in a lane: a fiber (fiber.h) with its own copy of the mesh and
 * its own move workspace, whose views are lm_lane_views (lane_views.h). Lanes run one at a time,
 * on the optimizer's thread, handing a baton in a fixed order: all run until they wait for an
 * evaluation, their requests go to the real views as ONE batch, the answers come back, and they run
 * again in order — so every decision depends only on the plan, the seed and K, never on timing or
 * on how many workers answered. Nothing is committed to the real views during a group: every
 * evaluation of the group is priced against its start. Then the lanes' changes are merged in lane
 * order: each lane's accepted operations are done again on the optimizer's mesh (lm_moves_replay),
 * the patch of that replay goes to the views; the first lane to change anything commits with its
 * exact ΔE (its copy and the replay are the same mesh, checked), every later one is evaluated again
 * against the state the merges before it left (re-validated) and committed only if it still pays
 * (ΔE < 0, or no worse than the lane found), else rolled back. Fibers never run concurrently, so
 * the optimizer's statistics, collapse queue and counters are shared without locks and without
 * races; a handoff costs no system call.
 *
 * Isolated lanes (lm_params.lane_isolation): each lane sees only the group's start and its own
 * actions, so that its decisions do not depend on the other lanes (nor on which process runs it):
 * at the group's start it takes its own copies of the clock (then the start + its own
 * evaluations), the statistics, the teleport state with the collapse queue, and sees only the
 * group's start stamps (its accepted collapses claim nothing for the others). The merge, in lane
 * order, first replays or rolls back the lane's operations as above, then replays its logs onto
 * the optimizer: statistics adds and improve[] adds, the queue changes (vertex ids through the
 * split map, dropped where the edge is not in the merged mesh), the teleport's last collapse (of
 * the last lane that completed one), the counters, the touched vertices (mapped), its evaluations;
 * then the queue notes the merged patch. What the merge takes of a lane is its lm_lane_result
 * (lane_work.h) alone; an isolated lane can also run away from the optimizer from an
 * lm_lane_request (lane_host.h, lm_lanes_set_detached) and merge to the same bytes. */
#ifndef LM_COMMON_OPTIMIZER_LANES_H
#define LM_COMMON_OPTIMIZER_LANES_H

#include <stdint.h>

#include "common/optimizer/lane_runner.h"
#include "common/optimizer/optimizer_internal.h"

typedef struct lm_lanes lm_lanes;

/* k lanes (2..LM_MAX_EDGES_IN_FLIGHT) for optimizer o (its mesh, views, moves config, clock). */
lm_status lm_lanes_create(lm_optimizer *o, uint32_t k, lm_lanes **out);
void lm_lanes_destroy(lm_lanes *l);
/* The optimizer's views changed (lm_optimizer_replace_views): what the lanes' own views ask for
 * their info. Between groups only. */
void lm_lanes_set_views(lm_lanes *l, lm_views *views);

/* The next group of plan[0..n): up to k planned edges, taken in plan order from the next few
 * (GROUP_WINDOW x k) whose neighbourhoods do not meet, moved to the front of plan (the others keep
 * their order after them). Returns their count (at least 1). */
uint32_t lm_lanes_group(lm_lanes *l, lm_planned_edge *plan, uint32_t n);

/* Optimise plan[0..n) (a group) and merge; totals[i] the ΔE edge i's lane committed (0 when its
 * changes were rolled back at the merge). */
lm_status lm_lanes_run(lm_lanes *l, const lm_planned_edge *plan, uint32_t n, int64_t *totals);

/* For tests: the order in which the lanes of each group run and send their requests (0 lane
 * order, 1 reversed, else a shuffle seeded by it); the merge stays in lane order. */
void lm_lanes_set_run_order(lm_lanes *l, uint64_t order);

/* lm_optimizer_set_lanes_detached, lm_optimizer_lane_traffic. */
lm_status lm_lanes_set_detached(lm_lanes *l, int on);
void lm_lanes_traffic(const lm_lanes *l, lm_lane_traffic *out);
/* lm_optimizer_set_lane_runner. */
void lm_lanes_set_runner(lm_lanes *l, const lm_lane_runner *runner);

/* For measurements (tests/bench/bench_scaling --schedule lanes): what a group did, reported at
 * the points of lm_lanes_run. Nothing it reports changes a decision. */
enum {
    LM_LANES_BEGIN,  /* the group begins (before the lanes' snapshots) */
    LM_LANES_RUN,    /* its lanes begin (the snapshots taken) */
    LM_LANES_MERGE,  /* every lane done: the merge begins */
    LM_LANES_MERGED, /* the merge done */
};
enum {
    LM_LANE_NOTHING,              /* no operation to merge */
    LM_LANE_KEPT_EXACT,           /* the first to change anything: its own exact ΔE */
    LM_LANE_KEPT_REVALIDATED,     /* re-validated against the merges before it, kept */
    LM_LANE_DROPPED_REPLAY,       /* its operations no longer fit the merged mesh */
    LM_LANE_DROPPED_REVALIDATION, /* re-validated, no longer pays */
};
typedef struct lm_lane_report {
    uint32_t index;
    int outcome;            /* LM_LANE_* */
    uint64_t evals;         /* its evaluations (isolated lanes; 0 for shared ones) */
    uint32_t ops, x_values; /* accepted operations; their parameters (doubles) */
    uint32_t stat_adds, queue_changes, touched; /* isolated lanes' logs and touched set */
} lm_lane_report;
typedef struct lm_lanes_probe {
    void (*phase)(void *ctx, int phase, uint32_t n);  /* LM_LANES_*; n the group's size */
    void (*lane)(void *ctx, const lm_lane_report *r); /* in the merge, lane order */
    void *ctx;
} lm_lanes_probe;
/* probe NULL: none (the default). */
void lm_lanes_set_probe(lm_lanes *l, const lm_lanes_probe *probe);

#endif
