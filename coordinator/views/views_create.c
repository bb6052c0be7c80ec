/* coordinator/views/views_create.c — co_views_create: defaults, checks, the range of the view set,
 * then the backend of the described kind with its materials and mesh. */
#include <stdlib.h>
#include <string.h>

#include "coordinator/views/views.h"
#include "coordinator/views/views_remote.h"
#include "worker/render/views_local.h"

co_views_desc co_views_desc_defaults(const co_views_desc *d)
{
    co_views_desc r = *d;
    if (r.views && !r.count && r.first < r.views->count)
        r.count = r.views->count - r.first;
    if (!r.device)
        r.device = "auto";
    if (!r.split)
        r.split = 2;
    if (r.split > r.count && r.count)
        r.split = r.count;
    return r;
}

static lm_status check_desc(const co_views_desc *d)
{
    if (!d->original || !d->views)
        return lm_fail(LM_E_INVALID, "views: an original and a view set are required");
    if (d->first >= d->views->count || d->count > d->views->count - d->first)
        return lm_fail(LM_E_RANGE, "views: range %u+%u is outside the %u views", d->first, d->count,
                       d->views->count);
    if (d->kind == CO_VIEWS_REMOTE && !d->pool)
        return lm_fail(LM_E_INVALID, "views: remote views need a worker pool");
    if ((unsigned)d->kind > CO_VIEWS_REMOTE)
        return lm_fail(LM_E_INVALID, "views: unknown kind %d", (int)d->kind);
    return LM_OK;
}

static lm_status make_local(const co_views_desc *d, uint32_t first, uint32_t count, lm_views **out)
{
    return wk_views_local_create(d->original, d->views, first, count, d->device, out);
}

/* `split` children of nearly equal ranges (the first ones one view longer). */
static lm_status make_split(const co_views_desc *d, lm_views **out)
{
    lm_views **kids = calloc(d->split, sizeof *kids);
    if (!kids)
        return lm_fail(LM_E_NOMEM, "out of memory for %u views children", d->split);
    lm_status st = LM_OK;
    uint32_t first = d->first;
    for (uint32_t i = 0; i < d->split && st == LM_OK; i++) {
        uint32_t n = d->count / d->split + (i < d->count % d->split);
        st = make_local(d, first, n, &kids[i]);
        first += n;
    }
    if (st != LM_OK) {
        for (uint32_t i = 0; i < d->split; i++)
            lm_views_destroy(kids[i]);
        free(kids);
        return st;
    }
    st = co_views_split_create(kids, d->split, out);
    free(kids);
    return st;
}

static lm_status make_kind(const co_views_desc *d, lm_views **out)
{
    switch (d->kind) {
    case CO_VIEWS_LOCAL:
        return make_local(d, d->first, d->count, out);
    case CO_VIEWS_SPLIT:
        return make_split(d, out);
    case CO_VIEWS_REMOTE:
        return co_views_remote_create(d, out);
    }
    return lm_fail(LM_E_INVALID, "views: unknown kind %d", (int)d->kind);
}

lm_status co_views_create(const co_views_desc *desc, lm_views **out)
{
    *out = NULL;
    co_views_desc d = co_views_desc_defaults(desc);
    lm_status st = check_desc(&d);
    lm_views *v = NULL;
    if (st == LM_OK)
        st = make_kind(&d, &v);
    if (st == LM_OK && d.materials)
        st = v->ops->set_materials(v, d.materials, d.n_materials);
    if (st == LM_OK && d.mesh)
        st = lm_views_set_mesh_from(v, d.mesh);
    if (st != LM_OK) {
        lm_views_destroy(v);
        return st;
    }
    *out = v;
    return LM_OK;
}
