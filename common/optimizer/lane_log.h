/* common/optimizer/lane_log.h — what an isolated lane (lm_params.lane_isolation, lanes.h) did to
 * the state the optimizer's lanes otherwise share, kept in the order the lane did it so that the
 * merge replays it onto the optimizer in lane order: the statistics' adds (the operations' and the
 * teleport's level improvements, floating-point sums whose order matters) and the collapse
 * queue's changes (each entry as the change left it). Not for other folders. */
#ifndef LM_COMMON_OPTIMIZER_LANE_LOG_H
#define LM_COMMON_OPTIMIZER_LANE_LOG_H

#include <stdint.h>

#include "common/optimizer/collapse_queue.h"
#include "common/optimizer/move_stats.h"

#define LM_LANE_LOG_IMPROVE LM_MOVE_KINDS /* an add's kind: the teleport's improve[level] */

typedef struct lm_lane_stat_add {
    uint32_t kind; /* lm_move_kind, or LM_LANE_LOG_IMPROVE */
    int32_t level;
    double x, t;
    uint64_t now;
} lm_lane_stat_add;

typedef struct lm_lane_queue_change {
    lm_cq_entry e;
    int present; /* 0: removed */
} lm_lane_queue_change;

typedef struct lm_lane_log {
    lm_lane_stat_add *adds;
    uint32_t n_adds, cap_adds;
    lm_lane_queue_change *queue;
    uint32_t n_queue, cap_queue;
} lm_lane_log;

void lm_lane_log_init(lm_lane_log *log);
void lm_lane_log_free(lm_lane_log *log);
void lm_lane_log_clear(lm_lane_log *log);

/* One statistics add, as lm_stat_add takes it. */
lm_status lm_lane_log_add(lm_lane_log *log, uint32_t kind, int level, double x, double t,
                          uint64_t now);
/* An lm_cq_observer: ctx is the log (out of memory stops the job: the log must be whole). */
void lm_lane_log_queue(void *ctx, const lm_cq_entry *e, int present);

/* Vertex ids of the lane's mesh as the optimizer's mesh has them after the merge (UINT32_MAX:
 * none, the entry is dropped). */
typedef uint32_t (*lm_lane_log_map)(const void *ctx, uint32_t v);

/* The statistics adds again, in order, onto stats and improve[] (half life improve_half_life). */
void lm_lane_log_replay_stats(const lm_lane_log *log, lm_move_stats *stats, lm_stat *improve,
                              double improve_half_life);
/* The queue changes again, in order, onto q, their vertices mapped; a change that leaves an entry
 * is dropped when its edge is not in m (a removal always goes through). */
lm_status lm_lane_log_replay_queue(const lm_lane_log *log, lm_cq *q, const lm_mesh *m,
                                   lm_lane_log_map map, const void *map_ctx);

#endif
