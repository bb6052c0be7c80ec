/* coordinator/geometric/energy.c — the terms of Hoppe's energy E = E_dist + E_rep + E_spring:
 * E_dist = w_dist Σ d² over the points (their projections), E_spring = κ w_len Σ |v_j - v_k|² over
 * the edges, E_rep = c_rep m; and the inner loop (project, solve) that lowers E_dist + E_spring
 * for a fixed connectivity. */
#include <stdlib.h>
#include <string.h>

#include "coordinator/geometric/geo_internal.h"

static double len_sq(const float *a, const float *b)
{
    double d[3] = {(double)a[0] - b[0], (double)a[1] - b[1], (double)a[2] - b[2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

double co_geo_spring_sum(const lm_mesh *m)
{
    uint32_t(*e)[2] = NULL;
    size_t n = 0;
    if (lm_mesh_list_edges(m, &e, &n) != LM_OK)
        return 0;
    double s = 0;
    for (size_t i = 0; i < n; i++)
        s += len_sq(m->pos[e[i][0]], m->pos[e[i][1]]);
    free(e);
    return s;
}

double co_geo_vertex_spring(const lm_mesh *m, uint32_t v, const float p[3], uint32_t skip)
{
    uint32_t buf[256], *nb = buf;
    uint32_t n = lm_mesh_vertex_neighbors(m, v, buf, 256);
    if (n > 256) {
        nb = malloc((size_t)n * sizeof *nb);
        if (!nb)
            return 0;
        lm_mesh_vertex_neighbors(m, v, nb, n);
    }
    double s = 0;
    for (uint32_t i = 0; i < n; i++)
        if (nb[i] != skip)
            s += len_sq(p, m->pos[nb[i]]);
    if (nb != buf)
        free(nb);
    return s;
}

double co_geo_dist_sum(const co_geo_state *g)
{
    double s = 0;
    for (uint32_t i = 0; i < g->n_pts; i++)
        s += g->pt[i].d2;
    return s;
}

void co_geo_retotal(co_geo_state *g)
{
    g->e_dist = g->w_dist * co_geo_dist_sum(g);
    g->e_spring = g->kappa * g->w_len * co_geo_spring_sum(g->m);
}

double co_geo_total(const co_geo_state *g)
{
    return g->e_dist + g->e_spring + g->c_rep * g->m->live_verts;
}

double co_geo_energy_tracked(const co_geo_state *g)
{
    return co_geo_total(g);
}

/* Σ d² of every point to its recorded triangle as the mesh is now. */
double co_geo_energy_now(const co_geo_state *g)
{
    double s = 0;
    for (uint32_t i = 0; i < g->n_pts; i++) {
        co_geo_point p = g->pt[i];
        co_geo_project_onto(g->m, &p, &g->pt[i].tri, 1);
        s += p.d2;
    }
    return g->w_dist * s + g->kappa * g->w_len * co_geo_spring_sum(g->m) +
           g->c_rep * g->m->live_verts;
}

const lm_mesh *co_geo_mesh(const co_geo_state *g)
{
    return g->m;
}

lm_status co_geo_inner(co_geo_state *g, int rounds)
{
    size_t bytes = (size_t)g->m->n_verts * sizeof *g->m->pos;
    float(*keep)[3] = malloc(bytes);
    if (!keep)
        return lm_fail(LM_E_NOMEM, "out of memory for the inner loop");
    lm_status st = LM_OK;
    for (int r = 0; r < rounds && st == LM_OK; r++) {
        double e0 = co_geo_total(g);
        memcpy(keep, g->m->pos, bytes);
        st = co_geo_solve_positions(g);
        if (st == LM_OK)
            st = co_geo_project_all(g);
        if (st != LM_OK)
            break;
        co_geo_retotal(g);
        double e1 = co_geo_total(g);
        if (!(e1 < e0)) { /* no better (rounding to floats, a singular system): as before */
            memcpy(g->m->pos, keep, bytes);
            st = co_geo_project_all(g);
            co_geo_retotal(g);
            break;
        }
        if (e0 - e1 < 1e-4 * e0)
            break;
    }
    free(keep);
    return st;
}
