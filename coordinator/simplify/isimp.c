/* coordinator/simplify/isimp.c — the greedy loop of image-driven simplification: initial prices,
 * lazy re-pricing of stale entries in batches, collapses with their footprints, stamps and queue
 * updates, and the verify mode the tests use. */
#include "coordinator/simplify/isimp.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/mesh_topology.h"
#include "coordinator/simplify/candidates.h"
#include "coordinator/simplify/collapse_op.h"
#include "coordinator/simplify/edge_queue.h"
#include "coordinator/simplify/fp_index.h"

#define CO_ISIMP_FIRST_CHUNK 512 /* edges priced together in the first pass */
#define CO_ISIMP_MAX_RING 1024

typedef struct isimp {
    lm_mesh *m;
    co_isimp_config cfg;
    co_isimp_stats *stats;
    co_eq *q;
    co_fpx *fpx; /* the clean entries' footprints (image method with footprints), else NULL */
    co_cands cands;
    co_pricer *pricer;
    lm_journal *j;
    lm_patch patch;
    uint32_t commits;
    uint32_t *vstamp; /* [n_verts]: commits done when a collapse last touched the vertex */
    co_rect fp[LM_MAX_VIEWS];
    uint32_t *batch;
    uint32_t cap_batch;
    /* the collapse being made (for the redo callback) */
    co_place place;
} isimp;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static lm_status setup(isimp *s, lm_mesh *m, lm_views *views, const co_isimp_config *cfg)
{
    s->m = m;
    s->cfg = *cfg;
    if (!s->cfg.rebatch_edges)
        s->cfg.rebatch_edges = 64;
    lm_patch_init(&s->patch);
    s->vstamp = calloc((size_t)m->n_verts + 1, sizeof *s->vstamp);
    s->cap_batch =
        CO_ISIMP_FIRST_CHUNK > s->cfg.rebatch_edges ? CO_ISIMP_FIRST_CHUNK : s->cfg.rebatch_edges;
    s->batch = malloc((size_t)s->cap_batch * sizeof *s->batch);
    if (!s->vstamp || !s->batch)
        return lm_fail(LM_E_NOMEM, "out of memory for the image simplifier");
    lm_status st = co_eq_create(cfg->views->count, &s->q);
    if (!st)
        st = co_cands_init(&s->cands);
    if (!st)
        st = lm_journal_create(&s->j);
    if (!st)
        st = co_pricer_create(cfg->method, views, cfg->views, cfg->max_batch, &s->pricer);
    if (!st && !co_pricer_is_local(s->pricer) && !s->cfg.unsafe_no_footprints)
        st = co_fpx_create(cfg->views, &s->fpx);
    return st;
}

static void teardown(isimp *s)
{
    co_pricer_destroy(s->pricer);
    co_fpx_destroy(s->fpx);
    lm_journal_destroy(s->j);
    co_cands_free(&s->cands);
    co_eq_destroy(s->q);
    lm_patch_free(&s->patch);
    free(s->vstamp);
    free(s->batch);
}

/* ---- pricing ------------------------------------------------------------------------------- */

/* The least price of each edge of the batch (ties: the first placement), or INT64_MAX. */
static void best_of(const co_cands *c, uint32_t i, int64_t *cost, uint8_t *place)
{
    const co_cand_edge *e = &c->edges[i];
    *cost = INT64_MAX;
    *place = 0;
    for (uint32_t k = 0; k < e->n; k++)
        if (c->delta[e->patch0 + k] < *cost) {
            *cost = c->delta[e->patch0 + k];
            *place = e->kind[k];
        }
}

static lm_status price_entries(isimp *s, const uint32_t *idx, uint32_t n)
{
    lm_status st =
        co_cands_build(&s->cands, s->m, s->q, s->cfg.views, s->cfg.derived_normals, idx, n);
    if (!st)
        st = co_pricer_price(s->pricer, &s->cands, s->q);
    for (uint32_t i = 0; i < n && !st; i++) {
        co_eq_entry *e = co_eq_at(s->q, idx[i]);
        int64_t cost;
        best_of(&s->cands, i, &cost, &e->place);
        e->state = CO_EQ_CLEAN;
        e->priced = 1;
        e->priced_at = s->commits;
        co_eq_set_cost(s->q, idx[i], cost);
        if (s->fpx)
            st = co_fpx_put(s->fpx, idx[i], co_eq_rects(s->q, idx[i]));
    }
    s->stats->edge_prices += n;
    return st;
}

static lm_status first_prices(isimp *s)
{
    uint32_t(*edges)[2] = NULL;
    size_t n = 0;
    lm_status st = lm_mesh_list_edges(s->m, &edges, &n);
    for (size_t i = 0; i < n && !st; i++)
        st = co_eq_insert(s->q, edges[i][0], edges[i][1], 0, NULL);
    free(edges);
    for (uint32_t i = 0; i < co_eq_size(s->q) && !st; i += CO_ISIMP_FIRST_CHUNK) {
        uint32_t k = 0;
        for (uint32_t x = i; x < co_eq_size(s->q) && k < CO_ISIMP_FIRST_CHUNK; x++)
            s->batch[k++] = x;
        st = price_entries(s, s->batch, k);
        if (st == LM_OK && s->cfg.on_priced)
            st = s->cfg.on_priced(s->cfg.ctx, i + k, co_eq_size(s->q));
    }
    return st;
}

static int is_stale(const isimp *s, const co_eq_entry *e)
{
    if (e->state != CO_EQ_CLEAN)
        return 1;
    for (uint32_t i = 0; i < e->n_verts; i++)
        if (s->vstamp[e->verts[i]] > e->priced_at)
            return 1;
    return 0;
}

/* Take the stale entries off the top of the queue and price them together. Returns how many. */
static lm_status reprice_top(isimp *s, uint32_t *n)
{
    *n = 0;
    for (uint32_t t; *n < s->cfg.rebatch_edges && (t = co_eq_top(s->q)) != UINT32_MAX;) {
        if (!is_stale(s, co_eq_at(s->q, t)))
            break;
        co_eq_detach(s->q, t);
        s->batch[(*n)++] = t;
    }
    s->stats->stale_pops += *n;
    return *n ? price_entries(s, s->batch, *n) : LM_OK;
}

/* Every stale entry anywhere in the queue (when nothing legal is left at the top). */
static lm_status reprice_all(isimp *s, uint32_t *n)
{
    lm_status st = LM_OK;
    *n = 0;
    uint32_t k = 0;
    for (uint32_t i = 0; i < co_eq_size(s->q) && !st; i++) {
        const co_eq_entry *e = co_eq_at(s->q, i);
        if (e->state != CO_EQ_DEAD && is_stale(s, e))
            s->batch[k++] = i;
        if (k == s->cap_batch || (k && i + 1 == co_eq_size(s->q))) {
            st = price_entries(s, s->batch, k);
            *n += k;
            k = 0;
        }
    }
    return st;
}

/* ---- a collapse ---------------------------------------------------------------------------- */

/* With the mesh as it was before the collapse: the removed triangles' corners join the change's
 * footprint and their vertices are stamped with this commit; then the collapse is done again. */
static lm_status before_and_redo(void *ctx)
{
    isimp *s = ctx;
    const lm_patch *p = &s->patch;
    for (uint32_t i = 0; i < p->n_removed; i++) {
        uint32_t t = p->removed[i];
        lm_tri_data d;
        lm_tri_data_from_mesh(s->m, t, &d);
        co_fp_add_tri(s->fp, s->cfg.views, &d);
        for (int k = 0; k < 3; k++)
            s->vstamp[lm_tri_vertex(s->m, t, k)] = s->commits + 1;
    }
    lm_status st = co_collapse_apply(s->m, &s->place, s->cfg.derived_normals, s->j);
    return st == LM_E_ILLEGAL ? lm_fail(LM_E_INTERNAL, "a collapse could not be done again") : st;
}

static lm_status redo_plain(isimp *s, size_t mark)
{
    lm_journal_rollback(s->m, s->j, mark);
    return before_and_redo(s);
}

/* An entry the footprint index names: dirty when clean and its footprint meets the change's; a
 * dirty entry leaves the index (priced again, it comes back with its new footprint). */
static void mark_if_met(void *ctx, uint32_t i)
{
    isimp *s = ctx;
    co_eq_entry *e = co_eq_at(s->q, i);
    if (e->state == CO_EQ_CLEAN && co_fp_meet(co_eq_rects(s->q, i), s->fp, s->cfg.views->count)) {
        e->state = CO_EQ_DIRTY;
        s->stats->marked_stale++;
        co_fpx_drop(s->fpx, i);
    }
}

/* Entries whose footprint meets the committed change's become dirty (image method): those the
 * index names that meet it, which are all the clean entries that meet it (fp_index.h). */
static void mark_footprints(isimp *s)
{
    if (s->fpx)
        co_fpx_query(s->fpx, s->fp, mark_if_met, s);
}

/* The entry leaves the queue, and its footprint the index. */
static void remove_entry(isimp *s, uint32_t i)
{
    co_eq_remove(s->q, i);
    if (s->fpx)
        co_fpx_drop(s->fpx, i);
}

/* The collapsed edge and drop's edges leave the queue; keep's new edges come in dirty, keyed by
 * the cost of the edge they replace. */
static lm_status update_edges(isimp *s, uint32_t entry, const uint32_t *ring, uint32_t n_ring)
{
    uint32_t keep = s->place.keep, drop = s->place.drop;
    remove_entry(s, entry);
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n_ring && !st; i++) {
        uint32_t x = ring[i];
        if (x == keep)
            continue;
        uint32_t old = co_eq_find(s->q, drop, x);
        int64_t cost = old == UINT32_MAX ? 0 : co_eq_at(s->q, old)->cost;
        if (old != UINT32_MAX)
            remove_entry(s, old);
        if (co_eq_find(s->q, keep, x) == UINT32_MAX)
            st = co_eq_insert(s->q, keep, x, cost, NULL);
    }
    return st;
}

static lm_status step_hook(isimp *s, const co_eq_entry *e, co_pm_split *split)
{
    co_pricer_stats ps;
    co_pricer_stats_get(s->pricer, &ps);
    co_isimp_step step = {.index = s->commits - 1,
                          .keep = s->place.keep,
                          .drop = s->place.drop,
                          .place = s->place.kind,
                          .cost = e->cost,
                          .live_verts = s->m->live_verts,
                          .evaluations = ps.evaluations,
                          .split = s->cfg.record_splits ? split : NULL};
    return s->cfg.on_step ? s->cfg.on_step(s->cfg.ctx, s->m, &step) : LM_OK;
}

/* Apply the change, its patch and footprint (redone after a look at the mesh before it), the
 * split when recorded; commit it to the views. */
static lm_status make_change(isimp *s, co_pm_split *split)
{
    size_t mark = lm_journal_mark(s->j);
    lm_status st = co_collapse_apply(s->m, &s->place, s->cfg.derived_normals, s->j);
    if (st)
        return st;
    co_fp_clear(s->fp, s->cfg.views->count);
    st = lm_patch_from_journal(&s->patch, s->m, s->j, mark);
    for (uint32_t i = 0; !st && i < s->patch.n_added; i++)
        co_fp_add_tri(s->fp, s->cfg.views, &s->patch.added[i]);
    if (!st && s->cfg.record_splits)
        st = co_pm_split_capture(s->m, s->j, mark, before_and_redo, s, split);
    else if (!st)
        st = redo_plain(s, mark);
    if (!st)
        st = co_pricer_commit(s->pricer, &s->patch);
    lm_journal_clear(s->j);
    return st;
}

static lm_status collapse_top(isimp *s, uint32_t t)
{
    co_eq_entry *e = co_eq_at(s->q, t);
    co_place pl[CO_PLACE_KINDS];
    co_place_all(s->m, e->a, e->b, pl);
    s->place = pl[e->place];
    uint32_t ring[CO_ISIMP_MAX_RING];
    uint32_t n_ring = lm_mesh_vertex_neighbors(s->m, s->place.drop, ring, CO_ISIMP_MAX_RING);
    if (n_ring > CO_ISIMP_MAX_RING)
        return lm_fail(LM_E_RANGE, "vertex %u has %u neighbours", s->place.drop, n_ring);
    co_pm_split split = {0};
    lm_status st = make_change(s, &split);
    if (st == LM_E_ILLEGAL) { /* cannot happen to an exact entry; priced again, it goes down */
        lm_clear_error();
        e->state = CO_EQ_DIRTY;
        return LM_OK;
    }
    s->commits++;
    s->stats->collapses++;
    int64_t cost = e->cost;
    if (!st) {
        mark_footprints(s);
        st = update_edges(s, t, ring, n_ring);
    }
    co_eq_entry done = {.cost = cost};
    if (!st)
        st = step_hook(s, &done, &split);
    co_pm_split_free(&split);
    return st;
}

/* ---- verify mode --------------------------------------------------------------------------- */

/* Every entry taken as exact priced again from scratch: the same cost and placement, or a bug. */
static lm_status verify_clean(isimp *s)
{
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < co_eq_size(s->q) && !st; i++) {
        co_eq_entry *e = co_eq_at(s->q, i);
        if (e->state == CO_EQ_DEAD || is_stale(s, e))
            continue;
        int64_t cost = e->cost, fresh;
        uint8_t place = e->place, fresh_place;
        st = co_cands_build(&s->cands, s->m, s->q, s->cfg.views, s->cfg.derived_normals, &i, 1);
        if (!st && s->fpx) /* the footprint just built (the same, for an exact entry) */
            st = co_fpx_put(s->fpx, i, co_eq_rects(s->q, i));
        if (!st)
            st = co_pricer_price(s->pricer, &s->cands, s->q);
        if (st)
            break;
        best_of(&s->cands, 0, &fresh, &fresh_place);
        if (fresh != cost || (cost != INT64_MAX && fresh_place != place))
            st = lm_fail(LM_E_INTERNAL,
                         "edge (%u, %u) kept as exact at %lld (%s) costs %lld (%s) after %u "
                         "collapses",
                         e->a, e->b, (long long)cost, co_place_name(place), (long long)fresh,
                         co_place_name(fresh_place), s->commits);
    }
    return st;
}

/* ---- the loop ------------------------------------------------------------------------------ */

static lm_status run_loop(isimp *s)
{
    lm_status st = first_prices(s);
    while (!st && s->m->live_verts > s->cfg.target_verts) {
        uint32_t n;
        if ((st = reprice_top(s, &n)) || n)
            continue;
        uint32_t t = co_eq_top(s->q);
        if (t == UINT32_MAX || co_eq_at(s->q, t)->cost == INT64_MAX) {
            if ((st = reprice_all(s, &n)) || n)
                continue;
            s->stats->stuck = 1;
            break;
        }
        st = collapse_top(s, t);
        if (!st && s->cfg.verify)
            st = verify_clean(s);
    }
    return st;
}

lm_status co_isimp_run(lm_mesh *m, lm_views *views, const co_isimp_config *cfg,
                       co_isimp_stats *stats)
{
    co_isimp_stats local;
    stats = stats ? stats : &local;
    memset(stats, 0, sizeof *stats);
    if (!cfg->views || cfg->views->count == 0)
        return lm_fail(LM_E_INVALID, "image simplification needs the views' view set");
    if (m->live_verts <= cfg->target_verts)
        return LM_OK; /* nothing to collapse: nothing to price */
    double t0 = now_s();
    isimp s = {.stats = stats};
    lm_status st = setup(&s, m, views, cfg);
    if (!st)
        st = run_loop(&s);
    if (s.pricer) {
        co_pricer_stats ps;
        co_pricer_stats_get(s.pricer, &ps);
        stats->evaluations = ps.evaluations;
        stats->calls = ps.calls;
        stats->renders = ps.renders;
    }
    teardown(&s);
    stats->seconds = now_s() - t0;
    return st;
}
