/* coordinator/geometric/moves.c — GenerateLegalMove and its judgement: one edge collapse, swap or
 * split done on the mesh (lm_mesh_topology, journaled), the points of the triangles it changed
 * re-projected onto the new ones, the new vertex placed by the local least-squares step (from
 * three starts for a collapse: either end and the midpoint), and the move kept when it lowers
 * E = E_dist + E_spring + E_rep, else rolled back. Moves that would turn a triangle over (its
 * normal against every one it replaces) or reach past the target vertex count are refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "coordinator/geometric/geo_internal.h"

#define STAR_MAX 512

typedef struct move {
    uint32_t old_tris[2 * STAR_MAX], n_old;
    double old_n[2 * STAR_MAX][3];
    uint32_t new_tris[STAR_MAX], n_new;
    uint32_t n_pts;
    double d_old, s_old; /* Σ d² of the points, Σ |e|² of the springs that change, before */
} move;

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Adds the triangles of v to mv->old_tris (no repeats). 0 when there are too many. */
static int add_old(const lm_mesh *m, move *mv, uint32_t v)
{
    uint32_t t[STAR_MAX];
    uint32_t n = lm_mesh_vertex_tris(m, v, t, STAR_MAX);
    if (n > STAR_MAX)
        return 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t k = 0;
        while (k < mv->n_old && mv->old_tris[k] != t[i])
            k++;
        if (k == mv->n_old)
            mv->old_tris[mv->n_old++] = t[i];
    }
    return 1;
}

/* The points on the old triangles into g->pidx, their Σ d², the old triangles' normals. */
static int gather(co_geo_state *g, move *mv)
{
    mv->n_pts = 0;
    mv->d_old = 0;
    for (uint32_t k = 0; k < mv->n_old; k++) {
        uint32_t t = mv->old_tris[k];
        lm_mesh_face_normal(g->m, t, mv->old_n[k]);
        for (uint32_t p = g->head[t]; p != LM_NONE; p = g->pt[p].next) {
            if (mv->n_pts == g->pcap) {
                uint32_t cap = g->pcap * 2 + 64;
                uint32_t *pi = realloc(g->pidx, (size_t)cap * sizeof *pi);
                if (pi)
                    g->pidx = pi;
                co_geo_point *pt = realloc(g->ptmp, (size_t)cap * sizeof *pt);
                if (pt)
                    g->ptmp = pt;
                if (!pi || !pt)
                    return 0;
                g->pcap = cap;
            }
            g->pidx[mv->n_pts++] = p;
            mv->d_old += g->pt[p].d2;
        }
    }
    return 1;
}

/* Re-project the gathered points onto the new triangles; their Σ d². */
static double reproject(co_geo_state *g, const move *mv)
{
    double d = 0;
    for (uint32_t i = 0; i < mv->n_pts; i++) {
        g->ptmp[i] = g->pt[g->pidx[i]];
        co_geo_project_onto(g->m, &g->ptmp[i], mv->new_tris, mv->n_new);
        d += g->ptmp[i].d2;
    }
    return d;
}

/* The least-squares position of vertex v alone for the projections in g->ptmp (all on triangles
 * around v) and its springs. */
static void best_position(const co_geo_state *g, const move *mv, uint32_t v, float out[3])
{
    double num[3] = {0, 0, 0}, den = 0, k = g->kappa * g->w_len;
    for (uint32_t i = 0; i < mv->n_pts; i++) {
        const co_geo_point *p = &g->ptmp[i];
        double beta = 0, c[3] = {0, 0, 0};
        for (int s = 0; s < 3; s++) {
            uint32_t u = lm_tri_vertex(g->m, p->tri, s);
            if (u == v)
                beta = p->bary[s];
            else
                for (int a = 0; a < 3; a++)
                    c[a] += p->bary[s] * g->m->pos[u][a];
        }
        for (int a = 0; a < 3; a++)
            num[a] += g->w_dist * beta * (p->x[a] - c[a]);
        den += g->w_dist * beta * beta;
    }
    uint32_t nb[STAR_MAX];
    uint32_t n = lm_mesh_vertex_neighbors(g->m, v, nb, STAR_MAX);
    for (uint32_t i = 0; i < n && i < STAR_MAX; i++) {
        for (int a = 0; a < 3; a++)
            num[a] += k * g->m->pos[nb[i]][a];
        den += k;
    }
    for (int a = 0; a < 3; a++)
        out[a] = den > 0 ? (float)(num[a] / den) : g->m->pos[v][a];
}

/* Σ d² and w_dist Σ d² + κ w_len (springs of v) with v at p, after `iters` local steps from p;
 * p gets the final position. */
static double place(co_geo_state *g, const move *mv, uint32_t v, float p[3], int iters,
                    double *d_out, double *s_out)
{
    memcpy(g->m->pos[v], p, sizeof(float[3]));
    double d = reproject(g, mv);
    for (int it = 0; it < iters; it++) {
        best_position(g, mv, v, g->m->pos[v]);
        d = reproject(g, mv);
    }
    memcpy(p, g->m->pos[v], sizeof(float[3]));
    *d_out = d;
    *s_out = co_geo_vertex_spring(g->m, v, p, LM_NONE);
    return g->w_dist * d + g->kappa * g->w_len * *s_out;
}

/* No new triangle degenerate or turned against every old one. */
static int upright(const co_geo_state *g, const move *mv)
{
    for (uint32_t i = 0; i < mv->n_new; i++) {
        double n[3];
        lm_mesh_face_normal(g->m, mv->new_tris[i], n);
        if (!(dot3(n, n) > 0))
            return 0;
        int ok = 0;
        for (uint32_t k = 0; k < mv->n_old && !ok; k++)
            ok = dot3(n, mv->old_n[k]) > 0;
        if (!ok)
            return 0;
    }
    return 1;
}

/* The move is kept: the points take their new projections. */
static void commit(co_geo_state *g, const move *mv, double dd, double ds)
{
    for (uint32_t k = 0; k < mv->n_old; k++)
        g->head[mv->old_tris[k]] = LM_NONE;
    for (uint32_t k = 0; k < mv->n_new; k++)
        g->head[mv->new_tris[k]] = LM_NONE;
    for (uint32_t i = mv->n_pts; i-- > 0;) {
        co_geo_point *p = &g->pt[g->pidx[i]];
        *p = g->ptmp[i];
        p->next = g->head[p->tri];
        g->head[p->tri] = g->pidx[i];
    }
    g->e_dist += dd;
    g->e_spring += g->kappa * ds;
    lm_journal_clear(g->j);
}

static void new_star(co_geo_state *g, move *mv, uint32_t v)
{
    mv->n_new = lm_mesh_vertex_tris(g->m, v, mv->new_tris, STAR_MAX);
    if (mv->n_new > STAR_MAX)
        mv->n_new = 0;
}

static const float *pos(const lm_mesh *m, uint32_t v)
{
    return m->pos[v];
}

/* Collapse (a, b) into a at the best of three placements. Returns ΔE (NAN: illegal). */
static double collapse(co_geo_state *g, move *mv, uint32_t a, uint32_t b, double *dd, double *ds)
{
    if (!add_old(g->m, mv, a) || !add_old(g->m, mv, b) || !gather(g, mv))
        return NAN;
    mv->s_old = co_geo_vertex_spring(g->m, a, pos(g->m, a), LM_NONE) +
                co_geo_vertex_spring(g->m, b, pos(g->m, b), a);
    float start[3][3];
    for (int k = 0; k < 3; k++) {
        start[0][k] = g->m->pos[a][k];
        start[1][k] = g->m->pos[b][k];
        start[2][k] = (float)(0.5 * ((double)g->m->pos[a][k] + g->m->pos[b][k]));
    }
    if (lm_mesh_collapse_edge(g->m, a, b, start[2], g->j) != LM_OK)
        return NAN;
    new_star(g, mv, a);
    if (!mv->n_new)
        return NAN;
    double best = INFINITY, bd = 0, bs = 0;
    int bi = 0;
    for (int i = 0; i < 3; i++) {
        double d, s, e = place(g, mv, a, start[i], 2, &d, &s);
        if (e < best)
            best = e, bd = d, bs = s, bi = i;
    }
    memcpy(g->m->pos[a], start[bi], sizeof start[bi]);
    reproject(g, mv);
    if (!upright(g, mv))
        return NAN;
    *dd = g->w_dist * (bd - mv->d_old);
    *ds = g->w_len * (bs - mv->s_old);
    return *dd + g->kappa * *ds - g->c_rep;
}

/* The two triangles of edge (a, b) and their far corners c, d; 0 when not two. */
static int edge_pair(const lm_mesh *m, uint32_t a, uint32_t b, move *mv, uint32_t far[2])
{
    mv->n_old = lm_mesh_edge_tris(m, a, b, mv->old_tris, 2);
    if (mv->n_old > 2)
        return 0;
    for (uint32_t k = 0; k < mv->n_old; k++)
        for (int s = 0; s < 3; s++) {
            uint32_t u = lm_tri_vertex(m, mv->old_tris[k], s);
            if (u != a && u != b)
                far[k] = u;
        }
    return mv->n_old > 0;
}

static double edge_len_sq(const lm_mesh *m, uint32_t a, uint32_t b)
{
    float p[3];
    memcpy(p, m->pos[a], sizeof p);
    double d[3] = {(double)p[0] - m->pos[b][0], (double)p[1] - m->pos[b][1],
                   (double)p[2] - m->pos[b][2]};
    return dot3(d, d);
}

static double swap(co_geo_state *g, move *mv, uint32_t a, uint32_t b, double *dd, double *ds)
{
    uint32_t far[2];
    if (!edge_pair(g->m, a, b, mv, far) || mv->n_old != 2 || !gather(g, mv))
        return NAN;
    mv->s_old = edge_len_sq(g->m, a, b);
    if (lm_mesh_swap_edge(g->m, a, b, g->j) != LM_OK)
        return NAN;
    memcpy(mv->new_tris, mv->old_tris, sizeof(uint32_t[2]));
    mv->n_new = 2;
    double d = reproject(g, mv);
    if (!upright(g, mv))
        return NAN;
    *dd = g->w_dist * (d - mv->d_old);
    *ds = g->w_len * (edge_len_sq(g->m, far[0], far[1]) - mv->s_old);
    return *dd + g->kappa * *ds;
}

static double split(co_geo_state *g, move *mv, uint32_t a, uint32_t b, double *dd, double *ds)
{
    uint32_t far[2], v;
    if (!edge_pair(g->m, a, b, mv, far) || !gather(g, mv))
        return NAN;
    mv->s_old = edge_len_sq(g->m, a, b);
    if (lm_mesh_split_edge(g->m, a, b, &v, g->j) != LM_OK || co_geo_heads_fit(g) != LM_OK)
        return NAN;
    new_star(g, mv, v);
    if (!mv->n_new)
        return NAN;
    float p[3];
    memcpy(p, g->m->pos[v], sizeof p);
    double d, s;
    place(g, mv, v, p, 2, &d, &s);
    if (!upright(g, mv))
        return NAN;
    *dd = g->w_dist * (d - mv->d_old);
    *ds = g->w_len * (s - mv->s_old);
    return *dd + g->kappa * *ds + g->c_rep;
}

int co_geo_try_move(co_geo_state *g, int kind, uint32_t a, uint32_t b, double *dd_out,
                    double *ds_out)
{
    static __thread move mv; /* large: off the stack */
    mv.n_old = mv.n_new = 0;
    size_t mark = lm_journal_mark(g->j);
    double dd = NAN, ds = NAN, de;
    if (kind == CO_GEO_MOVE_COLLAPSE)
        de = collapse(g, &mv, a, b, &dd, &ds);
    else if (kind == CO_GEO_MOVE_SWAP)
        de = swap(g, &mv, a, b, &dd, &ds);
    else
        de = split(g, &mv, a, b, &dd, &ds);
    if (dd_out)
        *dd_out = isnan(de) ? NAN : dd;
    if (ds_out)
        *ds_out = isnan(de) ? NAN : ds;
    uint32_t t = g->o.target_verts;
    int room = !t || (kind == CO_GEO_MOVE_COLLAPSE ? g->m->live_verts >= t
                      : kind == CO_GEO_MOVE_SPLIT  ? g->m->live_verts <= t
                                                   : 1);
    if (de < 0 && room) {
        commit(g, &mv, dd, ds);
        return 1;
    }
    lm_journal_rollback(g->m, g->j, mark);
    lm_journal_clear(g->j);
    return 0;
}
