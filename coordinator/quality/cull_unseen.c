/* coordinator/quality/cull_unseen.c — removing the triangles no view sees (see cull_unseen.h): one
 * view at a time through the CPU renderer's triangle ids, then the unseen triangles and what only
 * they used marked dead and the mesh compacted. */
#include "coordinator/quality/cull_unseen.h"

#include <stdlib.h>
#include <string.h>

#include "common/views_api.h"
#include "coordinator/quality/view_setup.h"

int co_cull_size(int size)
{
    return size > LM_MAX_VIEW_SIZE / CO_CULL_SCALE ? LM_MAX_VIEW_SIZE : size * CO_CULL_SCALE;
}

/* Mark in seen[] the triangles of m that view `view` of vs shows. */
static lm_status mark_view(const lm_mesh *m, const lm_view_set *vs, uint32_t view, lm_view_set *one,
                           uint32_t *ids, uint8_t *seen)
{
    one->count = 1;
    one->views[0] = vs->views[view];
    lm_views *v = NULL;
    lm_status st = co_views_with_model(m, m, one, "cpu", &v);
    if (st == LM_OK)
        st = v->ops->read_image(v, LM_IMAGE_TRIANGLE, 0, (uint8_t *)ids);
    size_t plane = (size_t)one->views[0].width * (size_t)one->views[0].height;
    for (size_t i = 0; st == LM_OK && i < plane; i++)
        if (ids[i] < m->n_tris)
            seen[ids[i]] = 1;
    if (v)
        v->ops->destroy(v);
    return st;
}

/* Kill the unseen triangles, then the wedges and vertices no live triangle uses. */
static uint32_t kill_unseen(lm_mesh *m, const uint8_t *seen, uint8_t *used_w, uint8_t *used_v)
{
    uint32_t removed = 0;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        if (!seen[t]) {
            m->tri_alive[t] = 0;
            m->live_tris--;
            removed++;
            continue;
        }
        for (int k = 0; k < 3; k++) {
            used_w[m->tris[t].w[k]] = 1;
            used_v[m->wedges[m->tris[t].w[k]].vertex] = 1;
        }
    }
    for (uint32_t w = 0; w < m->n_wedges; w++)
        if (m->wedge_alive[w] && !used_w[w])
            m->wedge_alive[w] = 0;
    for (uint32_t x = 0; x < m->n_verts; x++)
        if (m->vert_alive[x] && !used_v[x]) {
            m->vert_alive[x] = 0;
            m->live_verts--;
        }
    return removed;
}

lm_status co_cull_unseen(lm_mesh *m, const lm_mesh *framing, const lm_view_spec *spec, int size,
                         uint32_t *removed)
{
    int side = co_cull_size(size);
    lm_view_set *vs = NULL, *one = malloc(sizeof *one);
    uint32_t *ids = malloc((size_t)side * (size_t)side * sizeof *ids);
    uint8_t *seen = calloc((size_t)m->n_tris + 1, 1), *used_w = calloc((size_t)m->n_wedges + 1, 1),
            *used_v = calloc((size_t)m->n_verts + 1, 1);
    lm_status st = one && ids && seen && used_w && used_v
                       ? co_view_set_of(framing, spec, side, LM_VIEWS_TRAINING, &vs)
                       : lm_fail(LM_E_NOMEM, "out of memory culling unseen triangles");
    for (uint32_t h = 0; st == LM_OK && h < vs->count; h++)
        st = mark_view(m, vs, h, one, ids, seen);
    uint32_t n_seen = 0;
    for (uint32_t t = 0; st == LM_OK && t < m->n_tris; t++)
        n_seen += m->tri_alive[t] && seen[t];
    if (st == LM_OK && n_seen == 0)
        st = lm_fail(LM_E_INVALID, "--cull-unseen: no view sees any triangle of the model");
    uint32_t gone = st == LM_OK ? kill_unseen(m, seen, used_w, used_v) : 0;
    if (st == LM_OK)
        st = lm_mesh_compact(m);
    if (st == LM_OK && removed)
        *removed = gone;
    free(vs);
    free(one);
    free(ids);
    free(seen);
    free(used_w);
    free(used_v);
    return st;
}
