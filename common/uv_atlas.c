/* common/uv_atlas.c — the per-triangle grid atlas (see uv_atlas.h). */
#include "common/uv_atlas.h"

#include <math.h>
#include <stdlib.h>

/* Copies src's live vertices into dst; vmap[old] = new. */
static lm_status copy_vertices(const lm_mesh *src, lm_mesh *dst, uint32_t *vmap)
{
    for (uint32_t v = 0; v < src->n_verts; v++) {
        vmap[v] = LM_NONE;
        if (!src->vert_alive[v])
            continue;
        lm_status st = lm_mesh_add_vertex(dst, src->pos[v], &vmap[v]);
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}

void lm_atlas_cell_uv(uint32_t i, uint32_t cells, int size, int k, float uv[2])
{
    double cell = (double)size / cells, leg = cell - 2.0 * LM_ATLAS_MARGIN;
    double x0 = (i % cells) * cell + LM_ATLAS_MARGIN, y0 = (i / cells) * cell + LM_ATLAS_MARGIN;
    /* texel x, y from the top: (x0, y0 + leg) bottom-left, then right, then up (counter-clockwise
     * in u, v) */
    const double cx[3] = {x0, x0 + leg, x0}, cy[3] = {y0 + leg, y0 + leg, y0};
    uv[0] = (float)(cx[k] / size);
    uv[1] = (float)(1.0 - cy[k] / size);
}

/* Triangle t with new wedges at cell i of a grid of `cells` a side. */
static lm_status add_chart(const lm_mesh *src, uint32_t t, uint32_t i, uint32_t cells, int size,
                           const uint32_t *vmap, lm_mesh *dst)
{
    uint32_t w[3];
    for (int k = 0; k < 3; k++) {
        lm_wedge we = src->wedges[src->tris[t].w[k]];
        we.vertex = vmap[we.vertex];
        lm_atlas_cell_uv(i, cells, size, k, we.uv);
        lm_status st = lm_mesh_add_wedge(dst, &we, &w[k]);
        if (st != LM_OK)
            return st;
    }
    uint32_t id;
    lm_status st = lm_mesh_add_tri(dst, w, src->tris[t].material, &id);
    if (st == LM_OK)
        dst->tris[id].part = src->tris[t].part;
    return st;
}

/* by_id: triangle t's chart in cell t mod cells² (else the i-th live one's in cell i). */
static lm_status fill(const lm_mesh *src, int size, uint32_t cells, int by_id, lm_mesh *dst)
{
    uint32_t *vmap = malloc(((size_t)src->n_verts + 1) * sizeof *vmap);
    if (!vmap)
        return lm_fail(LM_E_NOMEM, "out of memory for an atlas");
    lm_status st = copy_vertices(src, dst, vmap);
    uint32_t i = 0;
    for (uint32_t t = 0; st == LM_OK && t < src->n_tris; t++)
        if (src->tri_alive[t])
            st = add_chart(src, t, by_id ? t % (cells * cells) : i++, cells, size, vmap, dst);
    free(vmap);
    if (st == LM_OK)
        st = lm_mesh_copy_materials(src, dst);
    if (st == LM_OK)
        st = lm_mesh_copy_parts(src, dst);
    dst->attrs = src->attrs | LM_ATTR_UV;
    return st;
}

uint32_t lm_atlas_cells(uint32_t charts)
{
    uint32_t cells = (uint32_t)ceil(sqrt((double)charts));
    return cells ? cells : 1;
}

lm_status lm_atlas_fits(uint32_t charts, uint32_t cells, int size)
{
    if ((double)size / cells - 2.0 * LM_ATLAS_MARGIN >= LM_ATLAS_MIN_LEG)
        return LM_OK;
    return lm_fail(LM_E_INVALID,
                   "%u triangles do not fit a per-triangle atlas of %d x %d texels (cells of "
                   "%.1f texels; at least %d needed): use a bake size of at least %u",
                   charts, size, size, (double)size / cells, 2 * LM_ATLAS_MARGIN + LM_ATLAS_MIN_LEG,
                   cells * (2u * LM_ATLAS_MARGIN + LM_ATLAS_MIN_LEG));
}

static lm_status make_atlas(const lm_mesh *src, int size, uint32_t cells, int by_id, lm_mesh **out)
{
    lm_mesh *m;
    lm_status st = lm_mesh_create(&m);
    if (st == LM_OK)
        st = fill(src, size, cells, by_id, m);
    if (st != LM_OK) {
        lm_mesh_destroy(m);
        return st;
    }
    *out = m;
    return LM_OK;
}

lm_status lm_atlas_per_triangle(const lm_mesh *src, int size, lm_mesh **out)
{
    *out = NULL;
    uint32_t cells = lm_atlas_cells(src->live_tris);
    lm_status st = lm_atlas_fits(src->live_tris, cells, size);
    return st == LM_OK ? make_atlas(src, size, cells, 0, out) : st;
}

lm_status lm_atlas_by_id(const lm_mesh *src, int size, uint32_t cells, lm_mesh **out)
{
    *out = NULL;
    lm_status st = lm_atlas_fits(src->n_tris, cells, size);
    return st == LM_OK ? make_atlas(src, size, cells, 1, out) : st;
}
