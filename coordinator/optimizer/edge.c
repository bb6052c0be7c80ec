/* coordinator/optimizer/edge.c — the operations on one edge (paper §5.3): no-op (levels 1-3),
 * swap (0-3) and teleport (0-3) in that order, each attempted when Inequality 3 says so, with the
 * statistics, the collapse queue, the touched vertices and the progress counters kept up to date.
 * The moves act on the context's mesh: the optimizer's own, or a lane's copy (lanes.c). */
#include "coordinator/optimizer/edge.h"

/* ---- one operation --------------------------------------------------------------------------- */

typedef struct op_outcome {
    int legal, accepted;
    int64_t delta; /* committed ΔE (0 when rejected) */
    uint32_t evals;
} op_outcome;

static lm_status run_teleport(co_edge_ctx *c, int level, uint32_t a, uint32_t b, op_outcome *r)
{
    co_optimizer *o = c->o;
    co_teleport_result t;
    lm_status st = co_teleport_try(&o->tp, c->mv, level, a, b, &t);
    *r = (op_outcome){t.legal, t.accepted, t.accepted ? t.delta : 0, t.evals};
    o->prog.attempted[CO_MOVE_COLLAPSE] += t.collapse_attempts;
    o->prog.accepted[CO_MOVE_COLLAPSE] += t.accepted ? 1 : 0;
    c->accepted[CO_MOVE_COLLAPSE] += t.accepted ? 1 : 0;
    return st;
}

/* The edge and the vertices of the triangles around the last accepted change. */
static lm_status mark_touched(co_edge_ctx *c, uint32_t a, uint32_t b)
{
    co_optimizer *o = c->o;
    const uint32_t *before, *now;
    uint32_t nb, nn;
    co_moves_last_change(c->mv, &before, &nb, &now, &nn);
    lm_status st = co_idset_add(&o->it.touched, a);
    if (!st)
        st = co_idset_add(&o->it.touched, b);
    for (uint32_t i = 0; i < nn && !st; i++)
        if (c->mesh->tri_alive[now[i]])
            for (int k = 0; k < 3 && !st; k++)
                st = co_idset_add(&o->it.touched, lm_tri_vertex(c->mesh, now[i], k));
    return st;
}

static lm_status run_op(co_edge_ctx *c, co_move_kind kind, int level, uint32_t a, uint32_t b,
                        op_outcome *r)
{
    co_optimizer *o = c->o;
    lm_status st;
    if (kind == CO_MOVE_SPLIT) {
        st = run_teleport(c, level, a, b, r);
    } else {
        co_move_result mr;
        st = co_moves_try(c->mv, kind, level, a, b, 0, &mr);
        *r = (op_outcome){mr.legal, mr.accepted, mr.accepted ? mr.delta : 0, mr.evals};
        if (!st && mr.accepted) {
            const uint32_t *before, *now;
            uint32_t nb, nn;
            co_moves_last_change(c->mv, &before, &nb, &now, &nn);
            st = co_teleport_note_change(&o->tp, c->mesh, now, nn);
        }
    }
    if (!st && r->accepted)
        st = mark_touched(c, a, b);
    if (st || !r->legal)
        return st;
    o->prog.attempted[kind]++;
    o->prog.accepted[kind] += r->accepted ? 1 : 0;
    c->accepted[kind] += r->accepted ? 1 : 0;
    if (!c->deferred)
        o->prog.energy += r->delta;
    co_move_stats_add(&o->stats, kind, level, (double)r->delta, r->evals, co_moves_clock(c->mv));
    return LM_OK;
}

/* ---- one edge (paper §5.3) ----------------------------------------------------------------- */

static const co_move_kind edge_moves[3] = {CO_MOVE_NOOP, CO_MOVE_SWAP, CO_MOVE_SPLIT};

/* Operations in their fixed order, each when Inequality 3 holds; a connectivity change that is
 * accepted ends the edge (it no longer exists). */
static lm_status edge_ops(co_edge_ctx *c, uint32_t a, uint32_t b, int64_t *total, int *tried)
{
    co_optimizer *o = c->o;
    for (int k = 0; k < 3; k++) {
        co_move_kind kind = edge_moves[k];
        for (int level = kind == CO_MOVE_NOOP ? 1 : 0; level < CO_LEVELS; level++) {
            if (!lm_mesh_edge_exists(c->mesh, a, b))
                return LM_OK;
            uint64_t now = co_moves_clock(c->mv);
            if (!co_move_stats_should_try(&o->stats, kind, level, (double)*total, now))
                continue;
            op_outcome r;
            lm_status st = run_op(c, kind, level, a, b, &r);
            if (st)
                return st;
            if (!r.legal)
                break;
            *tried = 1;
            *total += r.delta;
            if (r.accepted && kind != CO_MOVE_NOOP)
                return LM_OK;
        }
    }
    return LM_OK;
}

lm_status co_edge_optimise(co_edge_ctx *c, uint32_t a, uint32_t b, int64_t *total)
{
    *total = 0;
    if (!lm_mesh_edge_exists(c->mesh, a, b))
        return LM_OK;
    int tried = 0;
    lm_status st = edge_ops(c, a, b, total, &tried);
    if (!st && !tried) {
        /* Nothing looked worth it: try the most efficient operation anyway, so that the clock
         * (and with it the attenuation of the statistics) always moves on. */
        co_move_kind kind = CO_MOVE_NOOP;
        int level = 1;
        co_move_stats_best(&c->o->stats, co_moves_clock(c->mv), &kind, &level);
        op_outcome r;
        st = run_op(c, kind, level, a, b, &r);
        if (!st && !r.legal)
            st = run_op(c, CO_MOVE_NOOP, 1, a, b, &r);
        if (!st && r.legal)
            *total += r.delta;
    }
    co_moves_forget(c->mv);
    return st;
}
