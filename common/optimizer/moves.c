/* common/optimizer/moves.c — one optimisation operation on one edge (paper §5.2, Table 1): the
 * connectivity change, the vertex set of its level, the patch of affected triangles, the downhill
 * simplex against views->ops->evaluate, and accept (commit) or reject (journal rollback). */
#include "common/optimizer/moves.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "common/optimizer/moves_internal.h"

#define LM_PENALTY 1e300 /* value of points that are refused without evaluation */

void lm_moves_config_defaults(lm_moves_config *c)
{
    if (!c->evals_per_dim)
        c->evals_per_dim = 32;
    if (!c->max_set_verts)
        c->max_set_verts = 8;
    if (!c->max_dim)
        c->max_dim = 160;
    if (!(c->pos_step > 0))
        c->pos_step = 0.2;
    if (!(c->normal_step > 0))
        c->normal_step = 0.15;
    if (!(c->uv_step > 0))
        c->uv_step = 0.2;
    if (!(c->color_step > 0))
        c->color_step = 0.05;
    if (!(c->size_tol > 0))
        c->size_tol = 0.25;
}

static lm_status alloc_buffers(lm_moves *mv)
{
    uint32_t d = mv->cfg.max_dim;
    mv->x = malloc((size_t)d * sizeof *mv->x);
    mv->step = malloc((size_t)d * sizeof *mv->step);
    mv->patches = calloc((size_t)d + 1, sizeof *mv->patches);
    mv->deltas = malloc(((size_t)d + 1) * sizeof *mv->deltas);
    mv->slot = malloc(((size_t)d + 1) * sizeof *mv->slot);
    mv->buf = malloc((size_t)LM_MOVES_BUF * sizeof *mv->buf);
    if (!mv->x || !mv->step || !mv->patches || !mv->deltas || !mv->slot || !mv->buf)
        return lm_fail(LM_E_NOMEM, "out of memory creating the move workspace");
    for (uint32_t i = 0; i <= d; i++)
        lm_patch_init(&mv->patches[i]);
    lm_status s = lm_journal_create(&mv->j);
    return s ? s : lm_simplex_create(d, &mv->simplex);
}

lm_status lm_moves_create(lm_mesh *mesh, lm_views *views, const lm_moves_config *cfg,
                          lm_moves **out)
{
    lm_moves *mv = calloc(1, sizeof *mv);
    if (!mv)
        return lm_fail(LM_E_NOMEM, "out of memory creating the move workspace");
    mv->m = mesh;
    mv->views = views;
    mv->clock = &mv->evals;
    mv->cfg = *cfg;
    lm_moves_config_defaults(&mv->cfg);
    uint32_t a = mv->cfg.attrs;
    mv->derived_normals = !(a & LM_ATTR_NORMAL);
    mv->wattrs =
        (a & LM_ATTR_NORMAL ? 3 : 0) + (a & LM_ATTR_UV ? 2 : 0) + (a & LM_ATTR_COLOR ? 3 : 0);
    lm_idset *sets[] = {&mv->V, &mv->W, &mv->ops, &mv->R, &mv->B, &mv->T};
    for (size_t i = 0; i < sizeof sets / sizeof *sets; i++)
        lm_idset_init(sets[i]);
    lm_status s = alloc_buffers(mv);
    if (s) {
        lm_moves_destroy(mv);
        return s;
    }
    *out = mv;
    return LM_OK;
}

void lm_moves_destroy(lm_moves *mv)
{
    if (!mv)
        return;
    if (mv->patches)
        for (uint32_t i = 0; i <= mv->cfg.max_dim; i++)
            lm_patch_free(&mv->patches[i]);
    free(mv->patches);
    free(mv->x);
    free(mv->step);
    free(mv->deltas);
    free(mv->slot);
    free(mv->buf);
    lm_idset *sets[] = {&mv->V, &mv->W, &mv->ops, &mv->R, &mv->B, &mv->T};
    for (size_t i = 0; i < sizeof sets / sizeof *sets; i++)
        lm_idset_free(sets[i]);
    lm_journal_destroy(mv->j);
    lm_simplex_destroy(mv->simplex);
    free(mv);
}

void lm_moves_set_views(lm_moves *mv, lm_views *views)
{
    mv->views = views;
}

const lm_mesh *lm_moves_mesh(const lm_moves *mv)
{
    return mv->m;
}

uint64_t lm_moves_evals(const lm_moves *mv)
{
    return mv->evals;
}

void lm_moves_set_evals(lm_moves *mv, uint64_t evals)
{
    mv->evals = evals;
}

uint64_t lm_moves_clock(const lm_moves *mv)
{
    return *mv->clock;
}

void lm_moves_share_clock(lm_moves *mv, uint64_t *clock)
{
    mv->clock = clock ? clock : &mv->evals;
}

void lm_moves_observe(lm_moves *mv, const lm_moves_observer *obs)
{
    if (obs)
        mv->obs = *obs;
    else
        memset(&mv->obs, 0, sizeof mv->obs);
}

const lm_journal *lm_moves_journal(const lm_moves *mv)
{
    return mv->j;
}

size_t lm_moves_mark(const lm_moves *mv)
{
    return lm_journal_mark(mv->j);
}

void lm_moves_rollback(lm_moves *mv, size_t mark)
{
    lm_journal_rollback(mv->m, mv->j, mark);
}

uint64_t *lm_moves_clock_ptr(lm_moves *mv)
{
    return mv->clock;
}

void lm_moves_forget(lm_moves *mv)
{
    lm_journal_clear(mv->j);
}

lm_status lm_moves_revert(lm_moves *mv, size_t mark)
{
    if (mv->obs.reverted)
        mv->obs.reverted(mv->obs.ctx, mark);
    lm_journal_rollback(mv->m, mv->j, mark);
    return lm_views_set_mesh_from(mv->views, mv->m);
}

void lm_moves_last_change(const lm_moves *mv, const uint32_t **before, uint32_t *n_before,
                          const uint32_t **now, uint32_t *n_now)
{
    *before = mv->B.ids;
    *n_before = mv->B.n;
    *now = mv->T.ids;
    *n_now = mv->T.n;
}

/* ---- vertex sets (Table 1) --------------------------------------------------------------------
 */

static lm_status add_opt(lm_idset *s, uint32_t v)
{
    return v == LM_NONE ? LM_OK : lm_idset_add(s, v);
}

/* v's neighbours in ascending order (v itself must already be in the set if wanted). */
static lm_status add_ring(lm_idset *s, const lm_mesh *m, uint32_t v)
{
    if (v == LM_NONE)
        return LM_OK;
    uint32_t nb[1024];
    uint32_t n = lm_mesh_vertex_neighbors(m, v, nb, 1024);
    if (n > 1024)
        return lm_fail(LM_E_RANGE, "vertex %u has %u neighbours (limit 1024)", v, n);
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n && !st; i++)
        st = lm_idset_add(s, nb[i]);
    return st;
}

static lm_status add4(lm_idset *s, uint32_t p, uint32_t q, uint32_t r, uint32_t t)
{
    lm_status st = add_opt(s, p);
    if (!st)
        st = add_opt(s, q);
    if (!st)
        st = add_opt(s, r);
    return st ? st : add_opt(s, t);
}

lm_status lm_moves_vertex_set(const lm_mesh *m, const lm_move_site *site, int level, lm_idset *out)
{
    lm_idset_clear(out);
    const lm_move_site *s = site;
    lm_status st = LM_OK;
    switch (s->kind) {
    case LM_MOVE_NOOP:
        st = level == 1   ? add4(out, s->a, s->b, LM_NONE, LM_NONE)
             : level == 2 ? add4(out, s->a, s->b, s->c, s->d)
             : level == 3 ? add4(out, s->a, s->b, LM_NONE, LM_NONE)
                          : LM_OK;
        if (!st && level == 3 && !(st = add_ring(out, m, s->a)))
            st = add_ring(out, m, s->b);
        break;
    case LM_MOVE_SWAP:
        st = level == 1 || level == 3 ? add4(out, s->c, s->d, LM_NONE, LM_NONE)
             : level == 2             ? add4(out, s->c, s->d, s->a, s->b)
                                      : LM_OK;
        if (!st && level == 3 && !(st = add_ring(out, m, s->c)))
            st = add_ring(out, m, s->d);
        break;
    case LM_MOVE_SPLIT:
    case LM_MOVE_COLLAPSE:
        st = level == 2 ? add4(out, s->v, s->c, s->d, LM_NONE) : add_opt(out, s->v);
        if (!st && level == 3 && s->kind == LM_MOVE_SPLIT &&
            !(st = add4(out, s->a, s->b, LM_NONE, LM_NONE)) && !(st = add_ring(out, m, s->a)))
            st = add_ring(out, m, s->b);
        if (!st && level == 3 && s->kind == LM_MOVE_COLLAPSE)
            st = add_ring(out, m, s->v);
        break;
    default:
        return lm_fail(LM_E_INVALID, "unknown move kind %d", (int)s->kind);
    }
    return st;
}

/* ---- the connectivity change ---------------------------------------------------------------- */

static void find_site(const lm_mesh *m, lm_move_kind kind, uint32_t a, uint32_t b, lm_move_site *s)
{
    *s = (lm_move_site){.kind = kind, .a = a, .b = b, .c = LM_NONE, .d = LM_NONE, .v = LM_NONE};
    uint32_t t[2];
    uint32_t n = lm_mesh_edge_tris(m, a, b, t, 2);
    for (uint32_t i = 0; i < n && i < 2; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t x = lm_tri_vertex(m, t[i], k);
            if (x != a && x != b)
                *(i == 0 ? &s->c : &s->d) = x;
        }
}

static lm_status do_op(lm_moves *mv, int *legal)
{
    lm_move_site *s = &mv->site;
    lm_mesh *m = mv->m;
    lm_status st = LM_OK;
    *legal = 1;
    switch (s->kind) {
    case LM_MOVE_NOOP:
        *legal = lm_mesh_edge_exists(m, s->a, s->b);
        return LM_OK;
    case LM_MOVE_SWAP:
        st = lm_mesh_swap_edge(m, s->a, s->b, mv->j);
        break;
    case LM_MOVE_SPLIT:
        st = lm_mesh_split_edge(m, s->a, s->b, &s->v, mv->j);
        break;
    case LM_MOVE_COLLAPSE: {
        float mid[3];
        for (int k = 0; k < 3; k++)
            mid[k] = 0.5f * (m->pos[s->a][k] + m->pos[s->b][k]);
        st = lm_mesh_collapse_edge(m, s->a, s->b, mid, mv->j);
        s->v = s->a;
        break;
    }
    default:
        return lm_fail(LM_E_INVALID, "unknown move kind %d", (int)s->kind);
    }
    if (st == LM_E_ILLEGAL || st == LM_E_RANGE) {
        *legal = 0;
        lm_clear_error();
        return LM_OK;
    }
    *legal = st == LM_OK;
    return st;
}

/* Vertices of the triangles the connectivity change touched (derived normals), or the vertices
 * whose triangles it touched (optimised normals). */
static lm_status gather_ops(lm_moves *mv)
{
    lm_move_site *s = &mv->site;
    lm_idset_clear(&mv->ops);
    switch (s->kind) {
    case LM_MOVE_SWAP:
        return add4(&mv->ops, s->a, s->b, s->c, s->d);
    case LM_MOVE_SPLIT:
        if (!mv->derived_normals)
            return add_opt(&mv->ops, s->v);
        {
            lm_status st = add4(&mv->ops, s->a, s->b, s->c, s->d);
            return st ? st : add_opt(&mv->ops, s->v);
        }
    case LM_MOVE_COLLAPSE: {
        lm_status st = add_opt(&mv->ops, s->v);
        return st || !mv->derived_normals ? st : add_ring(&mv->ops, mv->m, s->v);
    }
    default:
        return LM_OK;
    }
}

/* R: vertices whose triangles render differently: ops ∪ V, and with derived normals every vertex
 * whose normal changes, ops ∪ ⌊⌈V⌉⌋. */
static lm_status gather_render_set(lm_moves *mv)
{
    lm_idset_clear(&mv->R);
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < mv->ops.n && !st; i++)
        st = lm_idset_add(&mv->R, mv->ops.ids[i]);
    for (uint32_t i = 0; i < mv->V.n && !st; i++) {
        st = lm_idset_add(&mv->R, mv->V.ids[i]);
        if (!st && mv->derived_normals)
            st = add_ring(&mv->R, mv->m, mv->V.ids[i]);
    }
    return st;
}

/* Alive triangles incident to any vertex of `verts` (plus extra) into `out`. */
static lm_status incident_tris(lm_moves *mv, const lm_idset *verts, uint32_t x, uint32_t y,
                               lm_idset *out)
{
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < verts->n + 2 && !st; i++) {
        uint32_t v = i < verts->n ? verts->ids[i] : i == verts->n ? x : y;
        if (v == LM_NONE || v >= mv->m->n_verts || !mv->m->vert_alive[v])
            continue;
        uint32_t n = lm_mesh_vertex_tris(mv->m, v, mv->buf, LM_MOVES_BUF);
        if (n > LM_MOVES_BUF)
            return lm_fail(LM_E_RANGE, "vertex %u has %u triangles (limit %u)", v, n, LM_MOVES_BUF);
        for (uint32_t k = 0; k < n && !st; k++)
            st = lm_idset_add(out, mv->buf[k]);
    }
    return st;
}

/* ---- one operation ------------------------------------------------------------------------- */

static lm_status redo_op(lm_moves *mv)
{
    uint32_t v = mv->site.v;
    int legal;
    lm_status st = do_op(mv, &legal);
    if (!st && (!legal || mv->site.v != v))
        st = lm_fail(LM_E_INTERNAL, "re-applying move %d on edge (%u, %u) gave another result",
                     (int)mv->site.kind, mv->site.a, mv->site.b);
    return st;
}

/* After the connectivity change: vertex set, parameters, and the triangle ids before (found by
 * briefly rolling the change back) and now. */
static lm_status prepare(lm_moves *mv, int level, size_t mark0)
{
    lm_status st = lm_moves_vertex_set(mv->m, &mv->site, level, &mv->V);
    if (st)
        return st;
    if (level == 0)
        lm_idset_clear(&mv->V);
    lm_idset_truncate(&mv->V, mv->cfg.max_set_verts);
    if ((st = lm_params_layout(mv)) || (st = gather_ops(mv)) || (st = gather_render_set(mv)))
        return st;
    lm_idset_clear(&mv->B);
    if (mv->site.kind != LM_MOVE_NOOP) {
        lm_journal_rollback(mv->m, mv->j, mark0);
        st = incident_tris(mv, &mv->R, mv->site.a, mv->site.b, &mv->B);
        lm_status s2 = redo_op(mv);
        st = st ? st : s2;
    } else {
        st = incident_tris(mv, &mv->R, LM_NONE, LM_NONE, &mv->B);
    }
    lm_idset_clear(&mv->T);
    if (!st)
        st = incident_tris(mv, &mv->R, LM_NONE, LM_NONE, &mv->T);
    for (uint32_t i = 0; i < mv->B.n && !st; i++)
        if (mv->m->tri_alive[mv->B.ids[i]])
            st = lm_idset_add(&mv->T, mv->B.ids[i]);
    lm_idset_sort(&mv->B);
    lm_idset_sort(&mv->T);
    return st;
}

static lm_status eval_batch(void *ctx, const double *pts, uint32_t n, double *vals)
{
    lm_moves *mv = ctx;
    LM_ASSERT(n <= mv->cfg.max_dim + 1);
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++) {
        const double *x = pts + (size_t)i * mv->dim;
        mv->slot[i] = LM_NONE;
        if (!lm_params_valid(mv, x))
            continue;
        size_t mark = lm_journal_mark(mv->j);
        lm_params_apply(mv, x);
        lm_status st =
            lm_patch_build(&mv->patches[k], mv->m, mv->B.ids, mv->B.n, mv->T.ids, mv->T.n);
        lm_journal_rollback(mv->m, mv->j, mark);
        if (st)
            return st;
        mv->slot[i] = k++;
    }
    if (k) {
        lm_status st = mv->views->ops->evaluate(mv->views, mv->patches, k, mv->deltas);
        if (st == LM_E_POISON) { /* every worker failed on it: these points are refused */
            lm_warn("%s: %u candidate moves refused", lm_last_error(), k);
            lm_clear_error();
            for (uint32_t i = 0; i < n; i++)
                mv->slot[i] = LM_NONE;
            st = LM_OK;
        }
        if (st)
            return st;
        mv->evals += k;
        if (mv->clock != &mv->evals)
            *mv->clock += k;
    }
    for (uint32_t i = 0; i < n; i++)
        vals[i] = mv->slot[i] == LM_NONE ? LM_PENALTY : (double)mv->deltas[mv->slot[i]];
    return LM_OK;
}

static lm_status optimise(lm_moves *mv, int64_t *delta)
{
    lm_simplex_opts o = {.max_evals = mv->cfg.evals_per_dim * mv->dim,
                         .size_tol = mv->cfg.size_tol,
                         .f_rtol = mv->cfg.f_rtol};
    double f0 = 0;
    lm_simplex_result r;
    lm_status st =
        lm_simplex_minimize(mv->simplex, mv->dim, mv->x, mv->step,
                            mv->site.kind == LM_MOVE_NOOP ? &f0 : NULL, &o, eval_batch, mv, &r);
    *delta = st || !(r.f_best < LM_PENALTY) ? INT64_MAX : (int64_t)r.f_best;
    return st;
}

static lm_status accept(lm_moves *mv, int level, size_t mark0, int64_t delta)
{
    lm_params_apply(mv, mv->x);
    lm_status st = lm_patch_build(&mv->patches[0], mv->m, mv->B.ids, mv->B.n, mv->T.ids, mv->T.n);
    if (st == LM_OK && mv->obs.accepted) {
        lm_move_record r = {mv->site.kind, level,   mv->site.a, mv->site.b, mv->site.v,
                            mark0,         mv->dim, mv->x,      delta};
        mv->obs.accepted(mv->obs.ctx, &r);
    }
    return st ? st : mv->views->ops->commit(mv->views, &mv->patches[0]);
}

static int usable_edge(const lm_mesh *m, uint32_t a, uint32_t b)
{
    return a < m->n_verts && b < m->n_verts && a != b && m->vert_alive[a] && m->vert_alive[b];
}

lm_status lm_moves_try(lm_moves *mv, lm_move_kind kind, int level, uint32_t a, uint32_t b,
                       int64_t accept_below, lm_move_result *res)
{
    memset(res, 0, sizeof *res);
    res->delta = INT64_MAX;
    if ((unsigned)kind >= LM_MOVE_KINDS || level < 0 || level > 3 ||
        (kind == LM_MOVE_NOOP && level == 0))
        return lm_fail(LM_E_INVALID, "no operation: move %d at level %d", (int)kind, level);
    if (!usable_edge(mv->m, a, b))
        return LM_OK;
    find_site(mv->m, kind, a, b, &mv->site);
    res->site = mv->site;
    size_t mark0 = lm_journal_mark(mv->j);
    int legal;
    lm_status st = do_op(mv, &legal);
    if (st || !legal)
        return st;
    if ((st = prepare(mv, level, mark0))) {
        lm_journal_rollback(mv->m, mv->j, mark0);
        if (st != LM_E_RANGE)
            return st;
        lm_clear_error();
        return LM_OK;
    }
    res->legal = 1;
    res->site = mv->site;
    res->set_size = mv->V.n;
    uint64_t e0 = mv->evals;
    st = optimise(mv, &res->delta);
    res->evals = (uint32_t)(mv->evals - e0);
    if (!st && res->delta != INT64_MAX && res->delta < accept_below) {
        st = accept(mv, level, mark0, res->delta);
        res->accepted = st == LM_OK;
        return st;
    }
    lm_journal_rollback(mv->m, mv->j, mark0);
    return st;
}

lm_status lm_moves_replay(lm_moves *mv, const lm_move_record *r, uint32_t *v)
{
    *v = LM_NONE;
    if (!usable_edge(mv->m, r->a, r->b))
        return lm_fail(LM_E_ILLEGAL, "edge (%u, %u) is gone", r->a, r->b);
    find_site(mv->m, r->kind, r->a, r->b, &mv->site);
    size_t mark0 = lm_journal_mark(mv->j);
    int legal;
    lm_status st = do_op(mv, &legal);
    if (st || !legal)
        return st ? st
                  : lm_fail(LM_E_ILLEGAL, "move %d on edge (%u, %u) is no longer legal",
                            (int)r->kind, r->a, r->b);
    st = prepare(mv, r->level, mark0);
    if (!st && mv->dim != r->dim)
        st = lm_fail(LM_E_ILLEGAL, "move %d on edge (%u, %u) has %u parameters now, %u then",
                     (int)r->kind, r->a, r->b, mv->dim, r->dim);
    if (st) {
        lm_journal_rollback(mv->m, mv->j, mark0);
        return st == LM_E_RANGE ? lm_fail(LM_E_ILLEGAL, "%s", lm_last_error()) : st;
    }
    memcpy(mv->x, r->x, (size_t)r->dim * sizeof *mv->x);
    lm_params_apply(mv, mv->x);
    *v = mv->site.v;
    return LM_OK;
}
