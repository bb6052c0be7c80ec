/* coordinator/simplify/collapse_op.c — a placed edge collapse: topology, merged attributes,
 * derived normals; journaled. */
#include "coordinator/simplify/collapse_op.h"

#include <string.h>

#include "common/optimizer/moves.h"

#define CO_OP_MAX_RING 1024

/* The wedges of keep and drop on the one or two triangles of the edge (before the collapse). */
typedef struct edge_wedges {
    uint32_t n;
    uint32_t keep[2], drop[2];
    lm_wedge keep_val[2], drop_val[2];
} edge_wedges;

static uint32_t wedge_at(const lm_mesh *m, uint32_t t, uint32_t v)
{
    for (int k = 0; k < 3; k++)
        if (lm_tri_vertex(m, t, k) == v)
            return m->tris[t].w[k];
    return LM_NONE;
}

static void gather_edge_wedges(const lm_mesh *m, const co_place *pl, edge_wedges *e)
{
    uint32_t t[2];
    uint32_t n = lm_mesh_edge_tris(m, pl->keep, pl->drop, t, 2);
    e->n = n < 2 ? n : 2;
    for (uint32_t i = 0; i < e->n; i++) {
        e->keep[i] = wedge_at(m, t[i], pl->keep);
        e->drop[i] = wedge_at(m, t[i], pl->drop);
        e->keep_val[i] = m->wedges[e->keep[i]];
        e->drop_val[i] = m->wedges[e->drop[i]];
    }
}

static float blend(float x, float y, float t)
{
    return t == 0.0f ? x : x + (y - x) * t;
}

/* Each merged wedge takes (1 - t) of its own old attributes and t of the other side's. */
static void set_merged(lm_mesh *m, const edge_wedges *e, float t, int derived_normals,
                       lm_journal *j)
{
    for (uint32_t i = 0; i < e->n; i++) {
        uint32_t w = e->keep[i];
        if ((i == 1 && w == e->keep[0]) || w >= m->n_wedges || !m->wedge_alive[w])
            continue;
        const lm_wedge *x = &e->keep_val[i], *y = &e->drop_val[i];
        lm_wedge r = m->wedges[w];
        for (int k = 0; k < 2; k++)
            r.uv[k] = blend(x->uv[k], y->uv[k], t);
        for (int k = 0; k < 4; k++)
            r.color[k] = blend(x->color[k], y->color[k], t);
        for (int k = 0; k < 3 && !derived_normals; k++)
            r.normal[k] = blend(x->normal[k], y->normal[k], t);
        if (memcmp(&r, &m->wedges[w], sizeof r))
            lm_mesh_set_wedge(m, w, &r, j);
    }
}

static lm_status derive_normals(lm_mesh *m, uint32_t v, lm_journal *j)
{
    uint32_t ring[CO_OP_MAX_RING];
    uint32_t n = lm_mesh_vertex_neighbors(m, v, ring, CO_OP_MAX_RING);
    if (n > CO_OP_MAX_RING)
        return LM_E_RANGE;
    lm_moves_derive_normal(m, v, j);
    for (uint32_t i = 0; i < n; i++)
        lm_moves_derive_normal(m, ring[i], j);
    return LM_OK;
}

lm_status co_collapse_apply(lm_mesh *m, const co_place *pl, int derived_normals, lm_journal *j)
{
    if (!pl->valid)
        return LM_E_ILLEGAL;
    size_t mark = lm_journal_mark(j);
    edge_wedges e = {0};
    gather_edge_wedges(m, pl, &e);
    lm_status st = lm_mesh_collapse_edge(m, pl->keep, pl->drop, pl->pos, j);
    if (st == LM_OK) {
        set_merged(m, &e, pl->t, derived_normals, j);
        if (derived_normals && derive_normals(m, pl->keep, j) != LM_OK) {
            lm_journal_rollback(m, j, mark);
            st = LM_E_RANGE;
        }
    }
    if (st == LM_E_ILLEGAL || st == LM_E_RANGE) {
        lm_clear_error();
        return LM_E_ILLEGAL;
    }
    return st;
}
