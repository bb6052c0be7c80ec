/* coordinator/geometric/outer.c — the outer minimisation of Hoppe's method at one spring constant
 * and c_rep: edges drawn at random from a candidate set, each tried as a collapse, then (unless
 * collapse-only) a swap and a split; an accepted move puts the edges around it back among the
 * candidates, until none is left. Özdal & Güdükbay's improvements switch in here: 3.1 collapses
 * only, 3.2 a later pass's first candidates only the edges whose stored collapse ΔE (ΔE_dist and
 * ΔE_spring / κ, re-weighed with the new κ and c_rep) is negative or unknown, 3.3 the edges near
 * an accepted collapse kept for the next pass rather than this one. */
#include <math.h>
#include <stdlib.h>

#include "coordinator/geometric/edge_set.h"
#include "coordinator/geometric/geo_internal.h"

struct co_geo_edge_memo {
    co_geo_map at;   /* edge -> index */
    double (*de)[2]; /* [n] ΔE_dist, ΔE_spring / κ of its last collapse tried */
    uint32_t n, cap;
};

lm_status co_geo_memo_create(co_geo_edge_memo **out)
{
    *out = calloc(1, sizeof **out);
    return *out ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory");
}

void co_geo_memo_destroy(co_geo_edge_memo *memo)
{
    if (!memo)
        return;
    co_geo_map_free(&memo->at);
    free(memo->de);
    free(memo);
}

static void memo_store(co_geo_edge_memo *memo, uint64_t key, double dd, double ds)
{
    uint32_t i = co_geo_map_get(&memo->at, key);
    if (i == UINT32_MAX) {
        if (memo->n == memo->cap) {
            uint32_t cap = memo->cap * 2 + 1024;
            double(*de)[2] = realloc(memo->de, (size_t)cap * sizeof *de);
            if (!de)
                return; /* a memo is advice: without it the edge is simply tried again */
            memo->de = de;
            memo->cap = cap;
        }
        if (co_geo_map_put(&memo->at, key, memo->n) != LM_OK)
            return;
        i = memo->n++;
    }
    memo->de[i][0] = dd;
    memo->de[i][1] = ds;
}

/* Whether the stored collapse of the edge would lower E now (unknown: yes). */
static int promising(const co_geo_state *g, const co_geo_edge_memo *memo, uint64_t key)
{
    uint32_t i = co_geo_map_get(&memo->at, key);
    if (i == UINT32_MAX)
        return 1;
    return memo->de[i][0] + g->kappa * memo->de[i][1] - g->c_rep < 0;
}

/* The edges of the triangles around v into s. */
static lm_status add_around(const lm_mesh *m, uint32_t v, co_geo_edge_set *s)
{
    uint32_t t[512];
    if (v >= m->n_verts || !m->vert_alive[v])
        return LM_OK;
    uint32_t n = lm_mesh_vertex_tris(m, v, t, 512);
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n && i < 512 && st == LM_OK; i++)
        for (int k = 0; k < 3 && st == LM_OK; k++)
            st = co_geo_set_add(
                s, co_geo_edge_key(lm_tri_vertex(m, t[i], k), lm_tri_vertex(m, t[i], (k + 1) % 3)));
    return st;
}

static lm_status first_candidates(co_geo_state *g, const co_geo_edge_memo *memo, int first,
                                  co_geo_edge_set *cand)
{
    uint32_t(*e)[2] = NULL;
    size_t n = 0;
    lm_status st = lm_mesh_list_edges(g->m, &e, &n);
    for (size_t i = 0; i < n && st == LM_OK; i++) {
        uint64_t key = co_geo_edge_key(e[i][0], e[i][1]);
        if (first || !(g->o.improvements & CO_GEO_STORED) || promising(g, memo, key))
            st = co_geo_set_add(cand, key);
    }
    free(e);
    return st;
}

/* One edge: collapse, else swap, else split. 1 when a move was kept. */
static int try_edge(co_geo_state *g, co_geo_edge_memo *memo, uint32_t a, uint32_t b)
{
    double dd, ds;
    g->sum->tried++;
    if (co_geo_try_move(g, CO_GEO_MOVE_COLLAPSE, a, b, &dd, &ds)) {
        g->sum->collapses++;
        return 1;
    }
    if (!isnan(dd))
        memo_store(memo, co_geo_edge_key(a, b), dd, ds);
    if (g->o.improvements & CO_GEO_COLLAPSE_ONLY)
        return 0;
    g->sum->tried++;
    if (co_geo_try_move(g, CO_GEO_MOVE_SWAP, a, b, NULL, NULL)) {
        g->sum->swaps++;
        return 1;
    }
    g->sum->tried++;
    if (co_geo_try_move(g, CO_GEO_MOVE_SPLIT, a, b, NULL, NULL)) {
        g->sum->splits++;
        return 1;
    }
    return 0;
}

static int nothing_left(const co_geo_state *g)
{
    return g->o.target_verts && g->m->live_verts <= g->o.target_verts &&
           (g->o.improvements & CO_GEO_COLLAPSE_ONLY);
}

lm_status co_geo_outer(co_geo_state *g, co_geo_edge_memo *memo, int first_pass)
{
    co_geo_edge_set cand = {0}, marked = {0};
    lm_status st = first_candidates(g, memo, first_pass, &cand);
    uint64_t done = 0;
    while (st == LM_OK && cand.n && !nothing_left(g)) {
        while (cand.n && st == LM_OK && !nothing_left(g)) {
            uint64_t key = co_geo_set_take(&cand, &g->rng);
            uint32_t a = (uint32_t)(key >> 32), b = (uint32_t)key;
            if (g->o.on_progress && (++done & 255) == 0)
                g->o.on_progress(g->o.ctx, NULL, done, done + cand.n);
            if (!lm_mesh_edge_exists(g->m, a, b) || !try_edge(g, memo, a, b))
                continue;
            g->sum->accepted++;
            if (g->o.on_accept)
                g->o.on_accept(g->o.ctx, g);
            co_geo_edge_set *to = (g->o.improvements & CO_GEO_DEFERRED) ? &marked : &cand;
            st = add_around(g->m, a, to);
            if (st == LM_OK)
                st = add_around(g->m, b, to);
        }
        co_geo_edge_set t = cand; /* the next pass: the marked edges */
        cand = marked;
        marked = t;
        co_geo_set_clear(&marked);
    }
    co_geo_set_free(&cand);
    co_geo_set_free(&marked);
    return st;
}
