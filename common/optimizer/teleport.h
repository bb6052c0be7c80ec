/* common/optimizer/teleport.h — the vertex teleport (paper §5.3): split an edge at its
 * midpoint and optimise (a level of the split move); accept the split only if its ΔE pays for the
 * cheapest collapse elsewhere (a threshold from the energy of the last completed collapse,
 * attenuated over time); then search the priority queue of collapse estimates (levels -1..3) for a
 * collapse whose ΔE is below the split's gain, raising levels of estimates that are too high,
 * stopping when the best remaining estimate has less than a 3σ chance of succeeding; if none is
 * found, collapse the cheapest edge anyway (an occasional uphill move). The vertex count is
 * unchanged afterwards. Also owns the queue upkeep after every accepted move (estimates around it
 * go back to the default state). */
#ifndef LM_COMMON_OPTIMIZER_TELEPORT_H
#define LM_COMMON_OPTIMIZER_TELEPORT_H

#include <stdint.h>
#include <stdio.h>

#include "common/optimizer/collapse_queue.h"
#include "common/optimizer/move_stats.h"
#include "common/optimizer/moves.h"

struct lm_lane_log; /* lane_log.h */

typedef struct lm_teleport_config {
    double threshold_half_life; /* evaluations for the collapse-cost estimate to halve; 0 = 20000 */
    double stats_half_life;     /* of the level-improvement statistics; 0 = 50000 */
    uint32_t max_search_evals;  /* per collapse search; 0 = 3000 */
} lm_teleport_config;

typedef struct lm_teleport {
    lm_teleport_config cfg;
    lm_cq *queue;
    int64_t last_collapse;      /* collapse ΔE when the last teleport completed (>= 0) */
    uint64_t last_time;         /* evaluation clock then */
    lm_stat improve[LM_LEVELS]; /* level l -> l+1: (ΔE at l+1) - (estimate at l) */
    uint64_t searches, searches_failed, collapses_tried;
    /* Edges the collapse search skips (left in the queue as they are), when set: edges in flight
     * keep each lane's collapses out of the other lanes' neighbourhoods (lanes.c). */
    int (*veto)(void *ctx, uint32_t a, uint32_t b);
    void *veto_ctx;
    /* When set (an isolated lane's copy of the state, lanes.c): improve[]'s adds are logged there
     * too, for the merge to replay. */
    struct lm_lane_log *log;
} lm_teleport;

typedef struct lm_teleport_result {
    int legal;      /* the split was possible */
    int accepted;   /* split and collapse both committed */
    int64_t delta;  /* ΔE committed by this teleport (0 if rejected) */
    uint32_t evals; /* evaluations spent (split + search) */
    uint32_t collapse_attempts;
} lm_teleport_result;

/* Every zero field of c takes its default (the values listed above): the one place they live. */
void lm_teleport_config_defaults(lm_teleport_config *c);

/* Every edge of m starts in the default state (m may be NULL: empty queue). */
lm_status lm_teleport_init(lm_teleport *tp, const lm_teleport_config *cfg, const lm_mesh *m);
void lm_teleport_free(lm_teleport *tp);

/* Current threshold: the attenuated cost of the cheapest collapse. */
int64_t lm_teleport_threshold(const lm_teleport *tp, uint64_t now);

/* Teleport at `level` (0..3) on edge (a, b). */
lm_status lm_teleport_try(lm_teleport *tp, lm_moves *mv, int level, uint32_t a, uint32_t b,
                          lm_teleport_result *res);

/* After any accepted move: put the collapse estimates of the edges of the triangles now around it
 * back to the default state. */
lm_status lm_teleport_note_change(lm_teleport *tp, const lm_mesh *m, const uint32_t *now,
                                  uint32_t n_now);

/* Checkpoint (binary, values as raw bits; the queue as entries sorted by edge). */
lm_status lm_teleport_save(const lm_teleport *tp, FILE *fp);
lm_status lm_teleport_load(lm_teleport *tp, FILE *fp);

#endif
