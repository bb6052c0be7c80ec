/* coordinator/geometric/project.c — ProjectPoints of Hoppe's inner loop: every point's closest
 * point on the current mesh (triangle, barycentrics, squared distance) through the BVH, and the
 * local re-projection onto the few triangles a move changed; the per-triangle chains of points. */
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "coordinator/geometric/geo_internal.h"

lm_status co_geo_heads_fit(co_geo_state *g)
{
    if (g->m->n_tris <= g->cap_head)
        return LM_OK;
    uint32_t cap = g->m->n_tris + g->m->n_tris / 2 + 16;
    uint32_t *h = realloc(g->head, (size_t)cap * sizeof *h);
    if (!h)
        return lm_fail(LM_E_NOMEM, "out of memory for the projections");
    for (uint32_t t = g->cap_head; t < cap; t++)
        h[t] = LM_NONE;
    g->head = h;
    g->cap_head = cap;
    return LM_OK;
}

static void corners(const lm_mesh *m, uint32_t t, double c[3][3])
{
    for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++)
            c[v][k] = m->pos[lm_tri_vertex(m, t, v)][k];
}

void co_geo_project_onto(const lm_mesh *m, co_geo_point *p, const uint32_t *tris, uint32_t n)
{
    double best = -1, w[3];
    for (uint32_t i = 0; i < n; i++) {
        double c[3][3];
        corners(m, tris[i], c);
        double d = lm_point_triangle_bary(p->x, c[0], c[1], c[2], w);
        if (best < 0 || d < best) {
            best = d;
            p->tri = tris[i];
            memcpy(p->bary, w, sizeof w);
        }
    }
    p->d2 = best;
}

lm_status co_geo_project_all(co_geo_state *g)
{
    lm_status st = co_geo_heads_fit(g);
    lm_bvh *b = NULL;
    if (st == LM_OK)
        st = lm_bvh_create(g->m, &b);
    if (st != LM_OK)
        return st;
    for (uint32_t t = 0; t < g->cap_head; t++)
        g->head[t] = LM_NONE;
    for (uint32_t i = g->n_pts; i-- > 0;) { /* chains in ascending point order */
        co_geo_point *p = &g->pt[i];
        p->d2 = lm_bvh_closest_tri(b, p->x, &p->tri, p->bary);
        p->next = g->head[p->tri];
        g->head[p->tri] = i;
    }
    lm_bvh_destroy(b);
    return LM_OK;
}
