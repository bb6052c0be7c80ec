/* worker/render/shared/views_core.c — the state both in-process views backends hold alike (see
 * views_core.h): creation, end, buckets, and a committed patch. */
#include "worker/render/shared/views_core.h"

#include <string.h>

void wk_views_core_init(wk_views_core *c, const lm_view *views, uint32_t count)
{
    c->views.count = count;
    memcpy(c->views.views, views, (size_t)count * sizeof *c->views.views);
    c->width = views[0].width;
    c->height = views[0].height;
    lm_replica_init(&c->rep);
}

lm_status wk_views_core_create_parts(wk_views_core *c)
{
    lm_status st = wk_image_store_create(c->views.count, c->width, c->height, &c->img);
    for (uint32_t h = 0; st == LM_OK && h < c->views.count; h++)
        st = wk_buckets_create(c->width, c->height, 0, &c->buckets[h]);
    return st;
}

void wk_views_core_free(wk_views_core *c)
{
    for (uint32_t h = 0; h < LM_MAX_VIEWS; h++)
        wk_buckets_destroy(c->buckets[h]);
    wk_image_store_destroy(c->img);
    lm_replica_free(&c->rep);
}

lm_status wk_views_core_build_buckets(wk_views_core *c)
{
    for (uint32_t h = 0; h < c->views.count; h++) {
        lm_status st = wk_buckets_fill(c->buckets[h], &c->views.views[h], &c->rep);
        if (st != LM_OK)
            return st;
    }
    c->buckets_ready = 1;
    return LM_OK;
}

lm_status wk_views_core_ready(wk_views_core *c)
{
    if (!c->mesh_set)
        return lm_fail(LM_E_INVALID, "no mesh set: call set_mesh before evaluate/commit");
    return c->buckets_ready ? LM_OK : wk_views_core_build_buckets(c);
}

lm_status wk_views_core_apply(wk_views_core *c, const lm_patch *p,
                              void (*forget)(wk_views_core *c, uint32_t id))
{
    for (uint32_t i = 0; i < p->n_removed; i++) {
        forget(c, p->removed[i]);
        for (uint32_t h = 0; h < c->views.count; h++)
            wk_buckets_remove(c->buckets[h], p->removed[i]);
        lm_replica_kill(&c->rep, p->removed[i]);
    }
    for (uint32_t i = 0; i < p->n_added; i++) {
        forget(c, p->added[i].id);
        lm_status st = lm_replica_put(&c->rep, &p->added[i]);
        for (uint32_t h = 0; st == LM_OK && h < c->views.count; h++) {
            wk_footprint f;
            wk_tri_footprint(&c->views.views[h], &p->added[i], &f);
            st = wk_buckets_insert(c->buckets[h], p->added[i].id, &f);
        }
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}
