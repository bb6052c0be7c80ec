/* common/optimizer/lane_work.h — one isolated lane (lanes.h) as data: what it needs at its
 * group's start (the request) and what it hands to the merge (the result), so that a lane can be
 * run away from the optimizer object (lane_host.h) and its result merged as if run in process.
 * Their wire form is lane_wire.h. Not for other folders than common/optimizer and its users.
 *
 * The request holds what an isolated lane reads of the optimizer's state during its edge (see
 * coordinator/OPTIMIZER.md, "Running a lane on a worker"), nothing else: the mesh replica at the
 * group's start and the views priced at it are the host's, and the job's constants (moves config)
 * too. */
#ifndef LM_COMMON_OPTIMIZER_LANE_WORK_H
#define LM_COMMON_OPTIMIZER_LANE_WORK_H

#include <stdint.h>

#include "common/optimizer/collapse_queue.h"
#include "common/optimizer/idset.h"
#include "common/optimizer/lane_log.h"
#include "common/optimizer/move_stats.h"
#include "common/optimizer/teleport.h"

typedef struct lm_lane_request {
    uint32_t index, n_group; /* the lane's share of the collapse search: hash(edge) % n_group */
    uint32_t a, b;           /* its edge */
    uint32_t n_verts;        /* the group's start mesh's vertex slots (ids in the request below) */
    uint64_t clock;   /* the evaluation clock at the group's start (Inequality 3, threshold) */
    uint32_t *vetoed; /* sorted: vertices of the other members' start neighbourhoods (the
                         collapse search leaves them alone) */
    uint32_t n_vetoed, cap_vetoed;
    lm_move_stats stats;       /* the operations' statistics at the group's start (Inequality 3) */
    lm_teleport_config tp_cfg; /* the teleport's constants (threshold half life, search budget) */
    int64_t last_collapse;     /* the teleport's threshold: last completed collapse and its time */
    uint64_t last_time;
    lm_stat improve[LM_LEVELS]; /* the collapse search's level improvements (its stop rule) */
    lm_cq_entry *queue;         /* the collapse queue, every entry, sorted by edge */
    uint32_t n_queue;
} lm_lane_request;

/* An accepted operation as lm_moves_replay takes it (r.x unset: its parameters are xs[x_at..]). */
typedef struct lm_lane_op {
    lm_move_record r;
    uint32_t x_at;
    int64_t d_acc_0; /* the lane's ΔE before it: the running lane's own (not sent) */
} lm_lane_op;

typedef struct lm_lane_result {
    lm_status status; /* of the lane's run (LM_OK, or why it failed: msg) */
    char msg[256];
    lm_lane_op *ops; /* accepted operations in the order made (reverted ones taken out) */
    uint32_t n_ops, cap_ops;
    double *xs;
    uint32_t n_xs, cap_xs;
    int64_t d_acc;      /* the lane's exact composite ΔE against the group's start */
    uint64_t mesh_hash; /* lm_mesh_hash of its mesh at the end (first-lane rule; 0 without ops) */
    int64_t total;      /* the edge's ΔE as the lane saw it */
    uint64_t evals;     /* evaluations it spent */
    uint64_t attempted[LM_MOVE_KINDS], accepted[LM_MOVE_KINDS]; /* progress counters it added */
    uint64_t searches, searches_failed, collapses_tried;        /* teleport counters it added */
    int64_t last_collapse; /* its teleport state at the end (taken when it accepted a collapse) */
    uint64_t last_time;
    lm_lane_log log;  /* statistics and improve[] adds, queue changes, in order */
    lm_idset touched; /* vertices around its accepted changes (its mesh's ids), in order */
} lm_lane_result;

void lm_lane_request_init(lm_lane_request *q);
void lm_lane_request_free(lm_lane_request *q);
/* v joins the vetoed list (callers add in ascending order). */
lm_status lm_lane_request_veto(lm_lane_request *q, uint32_t v);
/* Is v in the vetoed list. */
int lm_lane_request_vetoed(const lm_lane_request *q, uint32_t v);

/* Is edge (a, b) in the collapse search's share of lane `index` of a group of n (a hash of the
 * edge modulo n: scattered over the mesh, the same whichever order or process runs the lanes). */
int lm_lane_share(uint32_t a, uint32_t b, uint32_t n, uint32_t index);

void lm_lane_result_init(lm_lane_result *r);
void lm_lane_result_free(lm_lane_result *r);
/* Empty, ready for a new edge (keeps its memory). */
void lm_lane_result_clear(lm_lane_result *r);
/* An accepted operation (an lm_moves observer's), d_acc the lane's ΔE before it. */
lm_status lm_lane_result_accepted(lm_lane_result *res, const lm_move_record *r, int64_t d_acc);
/* A revert to journal position mark: the operations after it are forgotten; returns the lane's
 * ΔE before the first of them (d_acc when none). */
int64_t lm_lane_result_reverted(lm_lane_result *res, size_t mark, int64_t d_acc);

#endif
