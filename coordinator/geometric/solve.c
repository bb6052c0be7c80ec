/* coordinator/geometric/solve.c — ImproveVertexPositions of Hoppe's inner loop: for fixed
 * projections, the positions that minimise w_dist Σ |Σ_k b_ik v_k - x_i|² + κ w_len Σ |v_j - v_k|²
 * (a sparse linear least-squares problem; its normal equations A v = r, one right-hand side per
 * coordinate) by CHOLMOD's Cholesky factorisation (simplicial, AMD ordering: no threads, no BLAS
 * blocking, so the same bits every run). A tiny pull towards the current positions keeps
 * vertices no point sees (and, with κ = 0, whole pieces) where they are. */
#include <cholmod.h>
#include <stdlib.h>

#include "coordinator/geometric/geo_internal.h"

typedef struct ls_system {
    cholmod_common c;
    cholmod_triplet *t;
    cholmod_dense *r;
    uint32_t *idx; /* vertex id -> unknown (LM_NONE: dead) */
    uint32_t n;
} ls_system;

static void put(ls_system *s, uint32_t i, uint32_t j, double v)
{
    cholmod_triplet *t = s->t;
    int *ri = t->i, *ci = t->j;
    double *x = t->x;
    ri[t->nnz] = (int)(i < j ? i : j);
    ci[t->nnz] = (int)(i < j ? j : i);
    x[t->nnz++] = v;
}

/* Each point's row of the least-squares matrix is w (b_0, b_1, b_2) on its triangle's corners:
 * (AᵀA)_ab += w b_a b_b (one entry per unordered pair: the matrix is stored as its upper half),
 * (Aᵀx)_a += w b_a x. */
static void add_points(ls_system *s, const co_geo_state *g)
{
    double *r = s->r->x;
    for (uint32_t p = 0; p < g->n_pts; p++) {
        const co_geo_point *q = &g->pt[p];
        uint32_t u[3];
        for (int k = 0; k < 3; k++)
            u[k] = s->idx[lm_tri_vertex(g->m, q->tri, k)];
        for (int a = 0; a < 3; a++) {
            for (int b = a; b < 3; b++)
                put(s, u[a], u[b], g->w_dist * q->bary[a] * q->bary[b]);
            for (int c = 0; c < 3; c++)
                r[u[a] + (size_t)c * s->n] += g->w_dist * q->bary[a] * q->x[c];
        }
    }
}

static lm_status add_springs(ls_system *s, const co_geo_state *g)
{
    uint32_t(*e)[2] = NULL;
    size_t n = 0;
    lm_status st = lm_mesh_list_edges(g->m, &e, &n);
    if (st != LM_OK)
        return st;
    double k = g->kappa * g->w_len;
    for (size_t i = 0; i < n; i++) {
        uint32_t a = s->idx[e[i][0]], b = s->idx[e[i][1]];
        put(s, a, a, k);
        put(s, b, b, k);
        put(s, a, b, -k);
    }
    free(e);
    return LM_OK;
}

static void add_pull(ls_system *s, const co_geo_state *g)
{
    double eps = 1e-9 * (g->w_dist + g->kappa * g->w_len), *r = s->r->x;
    for (uint32_t v = 0; v < g->m->n_verts; v++) {
        uint32_t u = s->idx[v];
        if (u == LM_NONE)
            continue;
        put(s, u, u, eps);
        for (int c = 0; c < 3; c++)
            r[u + (size_t)c * s->n] += eps * g->m->pos[v][c];
    }
}

static lm_status factor_solve(ls_system *s, co_geo_state *g)
{
    cholmod_sparse *a = cholmod_triplet_to_sparse(s->t, s->t->nnz, &s->c);
    cholmod_factor *l = a ? cholmod_analyze(a, &s->c) : NULL;
    int ok = l && cholmod_factorize(a, l, &s->c) && s->c.status == CHOLMOD_OK;
    cholmod_dense *x = ok ? cholmod_solve(CHOLMOD_A, l, s->r, &s->c) : NULL;
    if (x) {
        const double *v = x->x;
        for (uint32_t id = 0; id < g->m->n_verts; id++)
            if (s->idx[id] != LM_NONE)
                for (int c = 0; c < 3; c++)
                    g->m->pos[id][c] = (float)v[s->idx[id] + (size_t)c * s->n];
    }
    cholmod_free_dense(&x, &s->c);
    cholmod_free_factor(&l, &s->c);
    cholmod_free_sparse(&a, &s->c);
    return LM_OK; /* a ls_system that would not factor leaves the positions as they were */
}

lm_status co_geo_solve_positions(co_geo_state *g)
{
    ls_system s = {.n = 0};
    s.idx = malloc((size_t)g->m->n_verts * sizeof *s.idx);
    if (!s.idx)
        return lm_fail(LM_E_NOMEM, "out of memory for the least-squares step");
    for (uint32_t v = 0; v < g->m->n_verts; v++)
        s.idx[v] = g->m->vert_alive[v] ? s.n++ : LM_NONE;
    cholmod_start(&s.c);
    s.c.supernodal = CHOLMOD_SIMPLICIAL;
    s.c.nmethods = 1;
    s.c.method[0].ordering = CHOLMOD_AMD;
    s.c.postorder = 0;
    size_t nnz = (size_t)g->n_pts * 6 + 9 * (size_t)g->m->live_tris + s.n;
    s.t = cholmod_allocate_triplet(s.n, s.n, nnz, 1, CHOLMOD_REAL, &s.c);
    s.r = cholmod_zeros(s.n, 3, CHOLMOD_REAL, &s.c);
    lm_status st = s.t && s.r ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for CHOLMOD");
    if (st == LM_OK) {
        add_points(&s, g);
        st = add_springs(&s, g);
    }
    if (st == LM_OK) {
        add_pull(&s, g);
        st = factor_solve(&s, g);
    }
    cholmod_free_triplet(&s.t, &s.c);
    cholmod_free_dense(&s.r, &s.c);
    cholmod_finish(&s.c);
    free(s.idx);
    return st;
}
