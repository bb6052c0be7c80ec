/* common/optimizer/teleport.c — vertex teleport = edge split paid for by the cheapest collapse
 * found in the priority queue of collapse estimates (paper §5.3), and the queue's upkeep. */
#include "common/optimizer/teleport.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/mesh_topology.h"
#include "common/optimizer/binio.h"
#include "common/optimizer/lane_log.h"

typedef struct search {
    lm_teleport *tp;
    lm_moves *mv;
    const lm_mesh *m;
    int64_t gain;   /* a collapse is acceptable when its ΔE is below this */
    uint64_t start; /* evaluation clock at the start */
    int has_best;
    lm_cq_entry best; /* cheapest collapse evaluated (est = its ΔE, level = its level) */
    lm_cq_entry *parked;
    uint32_t n_parked, cap_parked;
    int found;
    int64_t found_delta;
    uint32_t attempts;
} search;

void lm_teleport_config_defaults(lm_teleport_config *c)
{
    if (!(c->threshold_half_life > 0))
        c->threshold_half_life = 20000;
    if (!(c->stats_half_life > 0))
        c->stats_half_life = 50000;
    if (!c->max_search_evals)
        c->max_search_evals = 3000;
}

lm_status lm_teleport_init(lm_teleport *tp, const lm_teleport_config *cfg, const lm_mesh *m)
{
    memset(tp, 0, sizeof *tp);
    if (cfg)
        tp->cfg = *cfg;
    lm_teleport_config_defaults(&tp->cfg);
    lm_status st = lm_cq_create(&tp->queue);
    if (st || !m)
        return st;
    uint32_t(*e)[2];
    size_t n;
    if ((st = lm_mesh_list_edges(m, &e, &n)))
        return st;
    for (size_t i = 0; i < n && !st; i++)
        st = lm_cq_reset(tp->queue, e[i][0], e[i][1]);
    free(e);
    return st;
}

void lm_teleport_free(lm_teleport *tp)
{
    lm_cq_destroy(tp->queue);
    tp->queue = NULL;
}

int64_t lm_teleport_threshold(const lm_teleport *tp, uint64_t now)
{
    if (tp->last_collapse <= 0)
        return 0;
    double age = now > tp->last_time ? (double)(now - tp->last_time) : 0.0;
    return (int64_t)llround((double)tp->last_collapse * exp2(-age / tp->cfg.threshold_half_life));
}

lm_status lm_teleport_note_change(lm_teleport *tp, const lm_mesh *m, const uint32_t *now,
                                  uint32_t n_now)
{
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n_now && !st; i++) {
        uint32_t t = now[i];
        if (t >= m->n_tris || !m->tri_alive[t])
            continue;
        for (int k = 0; k < 3 && !st; k++) {
            uint32_t a = lm_tri_vertex(m, t, k), b = lm_tri_vertex(m, t, (k + 1) % 3);
            if (a != b)
                st = lm_cq_reset(tp->queue, a, b);
        }
    }
    return st;
}

static lm_status note_last(lm_teleport *tp, const lm_moves *mv, const lm_mesh *m)
{
    const uint32_t *before, *now;
    uint32_t nb, nn;
    lm_moves_last_change(mv, &before, &nb, &now, &nn);
    return lm_teleport_note_change(tp, m, now, nn);
}

/* ---- collapse search ------------------------------------------------------------------------- */

static lm_status park(search *s, const lm_cq_entry *e)
{
    if (s->n_parked == s->cap_parked &&
        !LM_GROW32(&s->parked, &s->cap_parked, (size_t)s->n_parked + 1, 64))
        return lm_fail(LM_E_NOMEM, "out of memory in the collapse search");
    s->parked[s->n_parked++] = *e;
    return LM_OK;
}

/* An edge the collapse search must leave alone (another lane's neighbourhood). */
static int vetoed(const lm_teleport *tp, const lm_cq_entry *e)
{
    return tp->veto && tp->veto(tp->veto_ctx, e->a, e->b);
}

/* 3σ rule: even a lucky level increase would not bring the estimate under the gain. */
static int hopeless(const search *s, const lm_cq_entry *e, uint64_t now)
{
    lm_stat_view v;
    lm_stat_get(&s->tp->improve[e->level], now, s->tp->cfg.stats_half_life, &v);
    if (v.f < 1.0)
        return 0;
    return (double)e->est + v.mean - 3.0 * v.sigma >= (double)s->gain;
}

static void note_best(search *s, const lm_cq_entry *e, int64_t delta, int level)
{
    if (s->has_best && delta >= s->best.est)
        return;
    s->has_best = 1;
    s->best = (lm_cq_entry){.a = e->a, .b = e->b, .est = delta, .level = level, .in_heap = 1};
}

/* Evaluate the collapse of e at level L; update queue, statistics, best. */
static lm_status attempt(search *s, const lm_cq_entry *e, int L, int64_t accept_below)
{
    lm_teleport *tp = s->tp;
    lm_move_result r;
    lm_status st = lm_moves_try(s->mv, LM_MOVE_COLLAPSE, L, e->a, e->b, accept_below, &r);
    s->attempts++;
    tp->collapses_tried++;
    if (st)
        return st;
    if (!r.legal)
        return lm_cq_set(tp->queue, e->a, e->b, INT64_MAX, 3, 0);
    uint64_t now = lm_moves_clock(s->mv);
    if (e->level >= 0 && L == e->level + 1 && e->est != INT64_MAX) {
        double x = (double)r.delta - (double)e->est;
        lm_stat_add(&tp->improve[e->level], x, r.evals, now, tp->cfg.stats_half_life);
        if (tp->log &&
            (st = lm_lane_log_add(tp->log, LM_LANE_LOG_IMPROVE, e->level, x, r.evals, now)))
            return st;
    }
    if (r.accepted) {
        s->found = 1;
        s->found_delta = r.delta;
        return note_last(tp, s->mv, s->m);
    }
    note_best(s, e, r.delta, L);
    return lm_cq_set(tp->queue, e->a, e->b, r.delta, L, 1);
}

static lm_status search_step(search *s, int *done)
{
    lm_cq *q = s->tp->queue;
    lm_cq_entry e;
    if (!lm_cq_pop(q, &e)) {
        *done = 1;
        return LM_OK;
    }
    if (!lm_mesh_edge_exists(s->m, e.a, e.b)) {
        lm_cq_remove(q, e.a, e.b);
        return LM_OK;
    }
    if (vetoed(s->tp, &e))
        return park(s, &e);
    int L;
    if (e.level < 0) {
        L = 0;
    } else if (e.est < s->gain) {
        L = e.level;
    } else if (e.level >= 3) {
        return park(s, &e);
    } else if (hopeless(s, &e, lm_moves_clock(s->mv))) {
        *done = 1;
        return lm_cq_set(q, e.a, e.b, e.est, e.level, 1);
    } else {
        L = e.level + 1;
    }
    return attempt(s, &e, L, s->gain);
}

/* Parked entries go back into the queue as they were. */
static lm_status unpark(search *s, lm_status st)
{
    for (uint32_t i = 0; i < s->n_parked && !st; i++) {
        const lm_cq_entry *e = &s->parked[i];
        st = lm_cq_set(s->tp->queue, e->a, e->b, e->est, e->level, 1);
    }
    s->n_parked = 0;
    return st;
}

static lm_status run_search(search *s)
{
    lm_status st = LM_OK;
    int done = 0;
    while (!st && !done && !s->found &&
           lm_moves_evals(s->mv) - s->start < s->tp->cfg.max_search_evals)
        st = search_step(s, &done);
    return unpark(s, st);
}

/* No collapse paid for the split: collapse the cheapest one anyway (an uphill move). */
static lm_status fallback(search *s)
{
    lm_status st = LM_OK;
    if (s->has_best) {
        lm_cq_entry e = s->best;
        e.level = -2; /* not a level increase: no statistics */
        if ((st = attempt(s, &e, s->best.level, INT64_MAX)) || s->found)
            return st;
    }
    for (int tries = 0; tries < 64 && !st && !s->found; tries++) {
        lm_cq_entry e;
        if (!lm_cq_pop(s->tp->queue, &e))
            break;
        if (!lm_mesh_edge_exists(s->m, e.a, e.b)) {
            lm_cq_remove(s->tp->queue, e.a, e.b);
            continue;
        }
        if (vetoed(s->tp, &e)) {
            st = park(s, &e);
            continue;
        }
        int L = e.level < 0 ? 0 : e.level;
        e.level = -2;
        st = attempt(s, &e, L, INT64_MAX);
    }
    return unpark(s, st);
}

lm_status lm_teleport_try(lm_teleport *tp, lm_moves *mv, int level, uint32_t a, uint32_t b,
                          lm_teleport_result *res)
{
    memset(res, 0, sizeof *res);
    uint64_t e0 = lm_moves_evals(mv);
    int64_t thr = lm_teleport_threshold(tp, lm_moves_clock(mv));
    size_t mark = lm_moves_mark(mv);
    lm_move_result r;
    lm_status st = lm_moves_try(mv, LM_MOVE_SPLIT, level, a, b, -thr, &r);
    res->legal = r.legal;
    res->evals = r.evals;
    if (st || !r.accepted)
        return st;
    search s = {.tp = tp, .mv = mv, .m = lm_moves_mesh(mv), .gain = -r.delta};
    s.start = lm_moves_evals(mv);
    tp->searches++;
    st = note_last(tp, mv, s.m);
    if (!st)
        st = run_search(&s);
    if (!st && !s.found) {
        tp->searches_failed++;
        st = fallback(&s);
    }
    free(s.parked);
    res->collapse_attempts = s.attempts;
    if (!st && !s.found)
        st = lm_moves_revert(mv, mark);
    else if (!st) {
        res->accepted = 1;
        res->delta = r.delta + s.found_delta;
        tp->last_collapse = s.found_delta > 0 ? s.found_delta : 0;
        tp->last_time = lm_moves_clock(mv);
    }
    res->evals = (uint32_t)(lm_moves_evals(mv) - e0);
    return st;
}

/* ---- checkpoint ------------------------------------------------------------------------------ */

#define TP_MAGIC 0x54504c54u /* "TLPT" */

lm_status lm_teleport_save(const lm_teleport *tp, FILE *fp)
{
    lm_bin b;
    lm_bin_init(&b, fp, "teleport state");
    lm_put_u32(&b, TP_MAGIC);
    lm_put_i64(&b, tp->last_collapse);
    lm_put_u64(&b, tp->last_time);
    lm_put_u64(&b, tp->searches);
    lm_put_u64(&b, tp->searches_failed);
    lm_put_u64(&b, tp->collapses_tried);
    for (int l = 0; l < LM_LEVELS; l++)
        lm_stat_save(&b, &tp->improve[l]);
    lm_cq_entry *e;
    uint32_t n;
    lm_status st = lm_cq_export(tp->queue, &e, &n);
    if (st)
        return st;
    lm_put_u32(&b, n);
    for (uint32_t i = 0; i < n; i++) {
        lm_put_u32(&b, e[i].a);
        lm_put_u32(&b, e[i].b);
        lm_put_i64(&b, e[i].est);
        lm_put_u32(&b, (uint32_t)e[i].level);
        lm_put_u32(&b, e[i].in_heap);
    }
    free(e);
    return b.status;
}

lm_status lm_teleport_load(lm_teleport *tp, FILE *fp)
{
    lm_bin b;
    lm_bin_init(&b, fp, "teleport state");
    if (lm_get_u32(&b) != TP_MAGIC)
        return lm_bin_bad(&b, "bad section marker");
    tp->last_collapse = lm_get_i64(&b);
    tp->last_time = lm_get_u64(&b);
    tp->searches = lm_get_u64(&b);
    tp->searches_failed = lm_get_u64(&b);
    tp->collapses_tried = lm_get_u64(&b);
    for (int l = 0; l < LM_LEVELS; l++)
        lm_stat_load(&b, &tp->improve[l]);
    uint32_t n = lm_get_u32(&b);
    if (b.status)
        return b.status;
    lm_cq_clear(tp->queue);
    for (uint32_t i = 0; i < n && !b.status; i++) {
        uint32_t a = lm_get_u32(&b), c = lm_get_u32(&b);
        int64_t est = lm_get_i64(&b);
        int32_t level = (int32_t)lm_get_u32(&b);
        uint32_t in_heap = lm_get_u32(&b);
        if (b.status)
            break;
        if (a >= c || level < -1 || level > 3 || in_heap > 1)
            return lm_bin_bad(&b, "bad queue entry %u", i);
        lm_status st = lm_cq_set(tp->queue, a, c, est, level, (int)in_heap);
        if (st)
            return st;
    }
    return b.status;
}
