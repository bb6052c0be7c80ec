/* coordinator/simplify/candidates.c — placed collapses turned into patches, footprints and
 * vertex lists, one edge after the other, the mesh rolled back after each. */
#include "coordinator/simplify/candidates.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "coordinator/simplify/collapse_op.h"

lm_status co_cands_init(co_cands *c)
{
    memset(c, 0, sizeof *c);
    co_fp_corners_init(&c->corners);
    return lm_journal_create(&c->j);
}

void co_cands_free(co_cands *c)
{
    for (uint32_t i = 0; i < c->cap_patches; i++)
        lm_patch_free(&c->patches[i]);
    free(c->patches);
    free(c->delta);
    free(c->edges);
    free(c->shard);
    free(c->tri_stamp);
    free(c->vert_stamp);
    free(c->verts);
    lm_journal_destroy(c->j);
    co_fp_corners_free(&c->corners);
    memset(c, 0, sizeof *c);
}

static lm_status grow(void **p, uint32_t *cap, uint32_t need, size_t elem, int zero)
{
    if (need <= *cap)
        return LM_OK;
    uint32_t old = *cap;
    if (!lm_grow32(p, cap, need, elem, 64))
        return lm_fail(LM_E_NOMEM, "out of memory for collapse candidates");
    if (zero)
        memset((char *)*p + (size_t)old * elem, 0, (size_t)(*cap - old) * elem);
    return LM_OK;
}

static lm_status reserve(co_cands *c, const lm_mesh *m, uint32_t n_edges)
{
    uint32_t old = c->cap_patches, need = c->n_patches + CO_PLACE_KINDS;
    lm_status st = grow((void **)&c->edges, &c->cap_edges, n_edges, sizeof *c->edges, 0);
    if (!st && need > old) {
        st = grow((void **)&c->patches, &c->cap_patches, need, sizeof *c->patches, 0);
        for (uint32_t i = old; !st && i < c->cap_patches; i++)
            lm_patch_init(&c->patches[i]);
        uint32_t cap = old;
        if (!st)
            st = grow((void **)&c->delta, &cap, c->cap_patches, sizeof *c->delta, 0);
    }
    if (!st)
        st = grow((void **)&c->tri_stamp, &c->cap_tri_stamp, m->n_tris + 1, sizeof(uint32_t), 1);
    if (!st)
        st = grow((void **)&c->vert_stamp, &c->cap_vert_stamp, m->n_verts + 1, sizeof(uint32_t), 1);
    return st;
}

/* The removed triangles of patch p as they are now: into the shard (once each), their corners
 * into the footprint's, their vertices into the vertex list. */
static lm_status take_removed(co_cands *c, const lm_mesh *m, const lm_patch *p, uint32_t *n_verts)
{
    for (uint32_t i = 0; i < p->n_removed; i++) {
        uint32_t t = p->removed[i];
        if (c->tri_stamp[t] == c->stamp)
            continue;
        c->tri_stamp[t] = c->stamp;
        lm_status st = grow((void **)&c->shard, &c->cap_shard, c->n_shard + 1, sizeof *c->shard, 0);
        if (!st)
            st = grow((void **)&c->verts, &c->cap_verts, *n_verts + 3, sizeof *c->verts, 0);
        if (st)
            return st;
        lm_tri_data *d = &c->shard[c->n_shard++];
        lm_tri_data_from_mesh(m, t, d);
        st = co_fp_corners_add_tri(&c->corners, d);
        if (st)
            return st;
        for (int k = 0; k < 3; k++) {
            uint32_t v = lm_tri_vertex(m, t, k);
            if (c->vert_stamp[v] != c->stamp) {
                c->vert_stamp[v] = c->stamp;
                c->verts[(*n_verts)++] = v;
            }
        }
    }
    return LM_OK;
}

/* Every legal placement of one edge. */
static lm_status build_edge(co_cands *c, lm_mesh *m, co_eq *q, const lm_view_set *vs, int derived,
                            uint32_t entry)
{
    const co_eq_entry *e = co_eq_at(q, entry);
    co_cand_edge *ce = &c->edges[c->n_edges++];
    *ce = (co_cand_edge){.entry = entry, .patch0 = c->n_patches, .shard0 = c->n_shard};
    co_rect *fp = co_eq_rects(q, entry);
    co_fp_clear(fp, vs->count);
    co_fp_corners_reset(&c->corners);
    c->stamp++;
    uint32_t n_verts = 0;
    co_place pl[CO_PLACE_KINDS];
    co_place_all(m, e->a, e->b, pl);
    /* legality depends on the triangles around both endpoints: a change there stamps them */
    lm_status st = grow((void **)&c->verts, &c->cap_verts, 2, sizeof *c->verts, 0);
    if (st)
        return st;
    c->verts[n_verts++] = e->a;
    c->verts[n_verts++] = e->b;
    c->vert_stamp[e->a] = c->vert_stamp[e->b] = c->stamp;
    for (int k = 0; k < CO_PLACE_KINDS && st == LM_OK; k++) {
        size_t mark = lm_journal_mark(c->j);
        st = co_collapse_apply(m, &pl[k], derived, c->j);
        if (st == LM_E_ILLEGAL) {
            st = LM_OK;
            continue;
        }
        lm_patch *p = &c->patches[c->n_patches];
        if (st == LM_OK)
            st = lm_patch_from_journal(p, m, c->j, mark);
        for (uint32_t i = 0; st == LM_OK && i < p->n_added; i++)
            st = co_fp_corners_add_tri(&c->corners, &p->added[i]);
        lm_journal_rollback(m, c->j, mark);
        if (st == LM_OK)
            st = take_removed(c, m, p, &n_verts);
        ce->kind[ce->n++] = (uint8_t)k;
        c->n_patches++;
    }
    ce->n_shard = c->n_shard - ce->shard0;
    if (st == LM_OK)
        co_fp_corners_apply(&c->corners, fp, vs);
    return st ? st : co_eq_set_verts(q, entry, c->verts, n_verts);
}

lm_status co_cands_build(co_cands *c, lm_mesh *m, co_eq *q, const lm_view_set *vs,
                         int derived_normals, const uint32_t *entries, uint32_t n)
{
    c->n_edges = c->n_patches = c->n_shard = 0;
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n && st == LM_OK; i++) {
        st = reserve(c, m, n);
        if (st == LM_OK)
            st = build_edge(c, m, q, vs, derived_normals, entries[i]);
    }
    lm_journal_clear(c->j);
    return st;
}
