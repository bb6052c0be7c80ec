/* coordinator/simplify/work.c — the working mesh, the views of each method, the QEM rule. */
#include "coordinator/simplify/work.h"

#include <stdlib.h>

#include "common/mesh_topology.h"
#include "coordinator/pool/pool.h"
#include "coordinator/views/views.h"

uint32_t co_simplify_start_verts(uint32_t live, uint32_t target, uint32_t presimplify)
{
    uint64_t start = presimplify ? presimplify : (uint64_t)CO_SIMPLIFY_PRESIMPLIFY_FACTOR * target;
    return live > start ? (uint32_t)start : live;
}

lm_status co_simplify_prepare(lm_mesh *m, int *derived_normals)
{
    *derived_normals = !(m->attrs & LM_ATTR_NORMAL);
    if (*derived_normals) {
        lm_mesh_merge_wedges(m, LM_ATTR_UV | LM_ATTR_COLOR);
        lm_mesh_compute_normals(m);
    }
    lm_status st = lm_mesh_compact(m);
    if (st == LM_OK)
        st = lm_mesh_build_adjacency(m);
    return st == LM_OK ? lm_mesh_validate(m) : st;
}

/* A mesh with work's materials and nothing to draw: the shard views' "original". */
static lm_status empty_with_materials(const lm_mesh *work, lm_mesh **out)
{
    lm_status st = lm_mesh_create(out);
    return st == LM_OK ? lm_mesh_copy_materials(work, *out) : st;
}

lm_status co_simplify_make_views(co_price_method method, const lm_mesh *original,
                                 const lm_mesh *work, const lm_view_set *vs, const char *device,
                                 co_pool *pool, lm_views **out)
{
    *out = NULL;
    co_views_desc d = {.original = original,
                       .views = vs,
                       .materials = work->materials,
                       .n_materials = work->n_materials,
                       .mesh = work,
                       .device = device};
    if (method == CO_PRICE_IMAGE) {
        if (pool) {
            d.kind = CO_VIEWS_REMOTE;
            d.pool = pool;
        }
        return co_views_create(&d, out);
    }
    lm_mesh *none = NULL;
    lm_status st = empty_with_materials(work, &none);
    d.original = none;
    d.materials = NULL;
    d.n_materials = 0;
    d.mesh = NULL;
    if (st == LM_OK)
        st = co_views_create(&d, out);
    lm_mesh_destroy(none);
    return st;
}

lm_status co_simplify_pool_start(const co_simplify_workers *w, const char *device, co_pool **out)
{
    *out = NULL;
    if (!w->local && !w->listen)
        return LM_OK;
    co_pool_options po = {.listen = w->listen,
                          .local_workers = w->local,
                          .device = device,
                          .renderer_id = w->renderer,
                          .keys = w->keys,
                          .quiet = !w->listen};
    lm_status st = co_pool_create(&po, out);
    if (st == LM_OK && w->local)
        st = co_pool_wait(*out, w->local, CO_SIMPLIFY_WORKER_START_S);
    if (st != LM_OK) {
        co_pool_destroy(*out);
        *out = NULL;
    }
    return st;
}

lm_status co_simplify_output_copy(const lm_mesh *m, lm_mesh **out)
{
    lm_status st = lm_mesh_clone(m, out);
    if (st == LM_OK && (st = lm_mesh_compact(*out)) != LM_OK) {
        lm_mesh_destroy(*out);
        *out = NULL;
    }
    return st;
}
