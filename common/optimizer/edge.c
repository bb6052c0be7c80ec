/* common/optimizer/edge.c — the operations on one edge (paper §5.3): no-op (levels 1-3),
 * swap (0-3) and teleport (0-3) in that order, each attempted when Inequality 3 says so, with the
 * statistics, the collapse queue, the touched vertices and the progress counters kept up to date.
 * The moves act on the context's mesh: the optimizer's own, or a lane's copy (lanes.c). */
#include "common/optimizer/edge.h"

#include "common/optimizer/lane_log.h"

static lm_move_stats *stats_of(const lm_edge_ctx *c)
{
    return c->stats ? c->stats : &c->o->stats;
}

static lm_teleport *tp_of(const lm_edge_ctx *c)
{
    return c->tp ? c->tp : &c->o->tp;
}

static lm_progress *prog_of(const lm_edge_ctx *c)
{
    return c->prog ? c->prog : &c->o->prog;
}

/* ---- one operation --------------------------------------------------------------------------- */

typedef struct op_outcome {
    int legal, accepted;
    int64_t delta; /* committed ΔE (0 when rejected) */
    uint32_t evals;
} op_outcome;

static lm_status run_teleport(lm_edge_ctx *c, int level, uint32_t a, uint32_t b, op_outcome *r)
{
    lm_progress *prog = prog_of(c);
    lm_teleport_result t;
    lm_status st = lm_teleport_try(tp_of(c), c->mv, level, a, b, &t);
    *r = (op_outcome){t.legal, t.accepted, t.accepted ? t.delta : 0, t.evals};
    prog->attempted[LM_MOVE_COLLAPSE] += t.collapse_attempts;
    prog->accepted[LM_MOVE_COLLAPSE] += t.accepted ? 1 : 0;
    c->accepted[LM_MOVE_COLLAPSE] += t.accepted ? 1 : 0;
    return st;
}

/* The edge and the vertices of the triangles around the last accepted change. */
static lm_status mark_touched(lm_edge_ctx *c, uint32_t a, uint32_t b)
{
    lm_idset *touched = c->touched ? c->touched : &c->o->it.touched;
    const uint32_t *before, *now;
    uint32_t nb, nn;
    lm_moves_last_change(c->mv, &before, &nb, &now, &nn);
    lm_status st = lm_idset_add(touched, a);
    if (!st)
        st = lm_idset_add(touched, b);
    for (uint32_t i = 0; i < nn && !st; i++)
        if (c->mesh->tri_alive[now[i]])
            for (int k = 0; k < 3 && !st; k++)
                st = lm_idset_add(touched, lm_tri_vertex(c->mesh, now[i], k));
    return st;
}

static lm_status run_op(lm_edge_ctx *c, lm_move_kind kind, int level, uint32_t a, uint32_t b,
                        op_outcome *r)
{
    lm_progress *prog = prog_of(c);
    lm_status st;
    if (kind == LM_MOVE_SPLIT) {
        st = run_teleport(c, level, a, b, r);
    } else {
        lm_move_result mr;
        st = lm_moves_try(c->mv, kind, level, a, b, 0, &mr);
        *r = (op_outcome){mr.legal, mr.accepted, mr.accepted ? mr.delta : 0, mr.evals};
        if (!st && mr.accepted) {
            const uint32_t *before, *now;
            uint32_t nb, nn;
            lm_moves_last_change(c->mv, &before, &nb, &now, &nn);
            st = lm_teleport_note_change(tp_of(c), c->mesh, now, nn);
        }
    }
    if (!st && r->accepted)
        st = mark_touched(c, a, b);
    if (st || !r->legal)
        return st;
    prog->attempted[kind]++;
    prog->accepted[kind] += r->accepted ? 1 : 0;
    c->accepted[kind] += r->accepted ? 1 : 0;
    if (!c->deferred)
        prog->energy += r->delta;
    uint64_t now = lm_moves_clock(c->mv);
    lm_move_stats_add(stats_of(c), kind, level, (double)r->delta, r->evals, now);
    return c->log ? lm_lane_log_add(c->log, kind, level, (double)r->delta, r->evals, now) : LM_OK;
}

/* ---- one edge (paper §5.3) ----------------------------------------------------------------- */

static const lm_move_kind edge_moves[3] = {LM_MOVE_NOOP, LM_MOVE_SWAP, LM_MOVE_SPLIT};

/* Operations in their fixed order, each when Inequality 3 holds; a connectivity change that is
 * accepted ends the edge (it no longer exists). */
static lm_status edge_ops(lm_edge_ctx *c, uint32_t a, uint32_t b, int64_t *total, int *tried)
{
    for (int k = 0; k < 3; k++) {
        lm_move_kind kind = edge_moves[k];
        for (int level = kind == LM_MOVE_NOOP ? 1 : 0; level < LM_LEVELS; level++) {
            if (!lm_mesh_edge_exists(c->mesh, a, b))
                return LM_OK;
            uint64_t now = lm_moves_clock(c->mv);
            if (!lm_move_stats_should_try(stats_of(c), kind, level, (double)*total, now))
                continue;
            op_outcome r;
            lm_status st = run_op(c, kind, level, a, b, &r);
            if (st)
                return st;
            if (!r.legal)
                break;
            *tried = 1;
            *total += r.delta;
            if (r.accepted && kind != LM_MOVE_NOOP)
                return LM_OK;
        }
    }
    return LM_OK;
}

lm_status lm_edge_optimise(lm_edge_ctx *c, uint32_t a, uint32_t b, int64_t *total)
{
    *total = 0;
    if (!lm_mesh_edge_exists(c->mesh, a, b))
        return LM_OK;
    int tried = 0;
    lm_status st = edge_ops(c, a, b, total, &tried);
    if (!st && !tried) {
        /* Nothing looked worth it: try the most efficient operation anyway, so that the clock
         * (and with it the attenuation of the statistics) always moves on. */
        lm_move_kind kind = LM_MOVE_NOOP;
        int level = 1;
        lm_move_stats_best(stats_of(c), lm_moves_clock(c->mv), &kind, &level);
        op_outcome r;
        st = run_op(c, kind, level, a, b, &r);
        if (!st && !r.legal)
            st = run_op(c, LM_MOVE_NOOP, 1, a, b, &r);
        if (!st && r.legal)
            *total += r.delta;
    }
    lm_moves_forget(c->mv);
    return st;
}
