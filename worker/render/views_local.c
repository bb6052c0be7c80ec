/* worker/render/views_local.c — the in-process views: which backend a --device spec makes (the GL
 * one on an EGL context, worker/render/gl/gl_views.h, or the exact CPU rasteriser,
 * worker/render/cpu/cpu_views.h), after the checks both share; and the extras, answered through
 * the seam both backends share (worker/render/shared/views_seam.h). */
#include "worker/render/views_local.h"

#include <stdlib.h>
#include <string.h>

#include "worker/render/cpu/cpu_views.h"
#include "worker/render/device_choice.h"
#include "worker/render/gl/gl_views.h"
#include "worker/render/shared/views_seam.h"

static lm_status check_views(const lm_view_set *views, lm_view_deal deal)
{
    if (views->count < 1 || views->count > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "view count %u is outside 1..%d", views->count, LM_MAX_VIEWS);
    if (!lm_view_deal_fits(deal, views->count))
        return lm_fail(LM_E_RANGE, "%u views from view %u, %u apart, are not among the %u views",
                       deal.count, deal.first, deal.stride ? deal.stride : 1, views->count);
    for (uint32_t h = 0; h < views->count; h++)
        if (views->views[h].width != views->views[0].width ||
            views->views[h].height != views->views[0].height)
            return lm_fail(LM_E_INVALID, "view %u differs in size from view 0", h);
    return LM_OK;
}

static lm_status check_materials(const lm_mesh *original)
{
    for (uint32_t t = 0; t < original->n_tris; t++)
        if (original->tri_alive[t] && original->tris[t].material >= original->n_materials)
            return lm_fail(LM_E_RANGE, "original triangle %u uses material %u of %u", t,
                           original->tris[t].material, original->n_materials);
    return LM_OK;
}

/* The views of `deal`, in their order (malloc'ed). */
static lm_view_set *deal_views(const lm_view_set *views, lm_view_deal deal)
{
    lm_view_set *out = malloc(sizeof *out);
    if (!out)
        return NULL;
    out->count = deal.count;
    for (uint32_t i = 0; i < deal.count; i++)
        out->views[i] = views->views[lm_view_deal_view(deal, i)];
    return out;
}

/* The CPU backend of the views of `deal` (it has no atlas: a view's pixels never depend on which
 * others a backend holds); targets: NULL or those of the deal's views, in its order. */
static lm_status create_cpu(const lm_mesh *original, const lm_view_set *views, lm_view_deal deal,
                            const uint8_t *targets, lm_views **out)
{
    if (deal.stride <= 1)
        return wk_cpu_views_create(original, views, deal.first, deal.count, targets, out);
    lm_view_set *mine = deal_views(views, deal);
    if (!mine)
        return lm_fail(LM_E_NOMEM, "out of memory creating the views");
    lm_status st = wk_cpu_views_create(original, mine, 0, deal.count, targets, out);
    free(mine);
    return st;
}

/* The GL backend of the views of `deal` on ctx (its atlas places them among all of the job's). */
static lm_status create_gl(const lm_mesh *original, const lm_view_set *views, lm_view_deal deal,
                           wk_gl_context *ctx, const uint8_t *targets, lm_views **out)
{
    lm_view_set *mine = deal_views(views, deal);
    if (!mine) {
        wk_gl_context_destroy(ctx);
        return lm_fail(LM_E_NOMEM, "out of memory creating the views");
    }
    lm_status st = wk_gl_views_create(original, mine, deal, views->count, ctx, targets, out);
    free(mine);
    return st;
}

/* Either backend on device_spec; targets as create_cpu's. */
static lm_status create_on(const lm_mesh *original, const lm_view_set *views, lm_view_deal deal,
                           const char *device_spec, const uint8_t *targets, lm_views **out)
{
    wk_gl_context *ctx = NULL;
    lm_status st = wk_device_open(device_spec, &ctx);
    if (st != LM_OK)
        return st;
    if (!ctx) /* "cpu", or "auto" without a GPU */
        return create_cpu(original, views, deal, targets, out);
    return create_gl(original, views, deal, ctx, targets, out);
}

lm_status wk_views_local_create(const lm_mesh *original, const lm_view_set *views, uint32_t first,
                                uint32_t count, const char *device_spec, lm_views **out)
{
    if (!count && first < views->count)
        count = views->count - first;
    return wk_views_local_create_dealt(original, views, (lm_view_deal){first, count, 1},
                                       device_spec, out);
}

lm_status wk_views_local_create_dealt(const lm_mesh *original, const lm_view_set *views,
                                      lm_view_deal deal, const char *device_spec, lm_views **out)
{
    lm_status st = check_views(views, deal);
    if (st == LM_OK)
        st = check_materials(original);
    return st == LM_OK ? create_on(original, views, deal, device_spec, NULL, out) : st;
}

lm_status wk_views_local_create_given(const lm_mesh *original, const lm_view_set *views,
                                      lm_view_deal deal, const char *device_spec,
                                      const uint8_t *targets, lm_views **out)
{
    lm_status st = check_views(views, deal);
    if (st == LM_OK)
        st = check_materials(original);
    if (st != LM_OK)
        return st;
    size_t plane = (size_t)views->views[0].width * (size_t)views->views[0].height;
    uint32_t stride = deal.stride ? deal.stride : 1;
    if (stride == 1) /* the deal's targets lie together already */
        return create_on(original, views, deal, device_spec, targets + deal.first * plane, out);
    uint8_t *mine = malloc(deal.count * plane + 1);
    if (!mine)
        return lm_fail(LM_E_NOMEM, "out of memory for %u target images", deal.count);
    for (uint32_t i = 0; i < deal.count; i++)
        memcpy(mine + i * plane, targets + (size_t)lm_view_deal_view(deal, i) * plane, plane);
    st = create_on(original, views, deal, device_spec, mine, out);
    free(mine);
    return st;
}

int wk_views_is_local(const lm_views *views)
{
    return wk_views_seam_is(views);
}

lm_status wk_views_local_set_occlusion(lm_views *views, int on)
{
    if (!wk_views_seam_is(views))
        return lm_fail(LM_E_UNSUPPORTED, "occlusion is a setting of the in-process views only");
    wk_views_core *c = (wk_views_core *)views;
    return c->backend->set_occlusion(c, on);
}

lm_status wk_views_local_get_stats(lm_views *views, wk_views_local_stats *out)
{
    memset(out, 0, sizeof *out);
    if (!wk_views_seam_is(views))
        return lm_fail(LM_E_UNSUPPORTED, "statistics are kept by the in-process views only");
    *out = ((wk_views_core *)views)->stats;
    return LM_OK;
}
