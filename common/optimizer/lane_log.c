/* common/optimizer/lane_log.c — an isolated lane's logs of statistics adds and collapse queue
 * changes, and their replay at the merge (lane_log.h). */
#include "common/optimizer/lane_log.h"

#include <stdlib.h>

#include "common/grow.h"
#include "common/mesh_topology.h"

void lm_lane_log_init(lm_lane_log *log)
{
    *log = (lm_lane_log){0};
}

void lm_lane_log_free(lm_lane_log *log)
{
    free(log->adds);
    free(log->queue);
    lm_lane_log_init(log);
}

void lm_lane_log_clear(lm_lane_log *log)
{
    log->n_adds = 0;
    log->n_queue = 0;
}

lm_status lm_lane_log_add(lm_lane_log *log, uint32_t kind, int level, double x, double t,
                          uint64_t now)
{
    if (!LM_GROW32(&log->adds, &log->cap_adds, (size_t)log->n_adds + 1, 64))
        return lm_fail(LM_E_NOMEM, "out of memory for a lane's statistics log");
    log->adds[log->n_adds++] = (lm_lane_stat_add){kind, level, x, t, now};
    return LM_OK;
}

void lm_lane_log_queue(void *ctx, const lm_cq_entry *e, int present)
{
    lm_lane_log *log = ctx;
    bool grown = LM_GROW32(&log->queue, &log->cap_queue, (size_t)log->n_queue + 1, 256);
    LM_ASSERT(grown);
    log->queue[log->n_queue++] = (lm_lane_queue_change){*e, present};
}

void lm_lane_log_replay_stats(const lm_lane_log *log, lm_move_stats *stats, lm_stat *improve,
                              double improve_half_life)
{
    for (uint32_t i = 0; i < log->n_adds; i++) {
        const lm_lane_stat_add *a = &log->adds[i];
        if (a->kind == LM_LANE_LOG_IMPROVE)
            lm_stat_add(&improve[a->level], a->x, a->t, a->now, improve_half_life);
        else
            lm_move_stats_add(stats, (lm_move_kind)a->kind, a->level, a->x, a->t, a->now);
    }
}

lm_status lm_lane_log_replay_queue(const lm_lane_log *log, lm_cq *q, const lm_mesh *m,
                                   lm_lane_log_map map, const void *map_ctx)
{
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < log->n_queue && !st; i++) {
        const lm_lane_queue_change *c = &log->queue[i];
        uint32_t a = map(map_ctx, c->e.a), b = map(map_ctx, c->e.b);
        if (a == UINT32_MAX || b == UINT32_MAX || a == b)
            continue;
        if (!c->present)
            lm_cq_remove(q, a, b);
        else if (lm_mesh_edge_exists(m, a, b))
            st = lm_cq_set(q, a, b, c->e.est, c->e.level, (int)c->e.in_heap);
    }
    return st;
}
