/* worker/render/shared/views_seam.c — the views_api.h ops of both in-process backends, answered
 * from their wk_views_core and their wk_views_backend table (see views_seam.h). */
#include "worker/render/shared/views_seam.h"

#include <stdlib.h>
#include <string.h>

#include "worker/render/shared/views_answers.h"

static lm_status seam_set_mesh(lm_views *base, const lm_tri_data *tris, size_t n)
{
    wk_views_core *c = (wk_views_core *)base;
    lm_status st = c->backend->set_mesh(c, tris, n);
    c->seq += st == LM_OK;
    return st;
}

static lm_status seam_set_materials(lm_views *base, const lm_material *mats, uint32_t n)
{
    wk_views_core *c = (wk_views_core *)base;
    lm_status st = c->backend->set_materials(c, mats, n);
    c->seq += st == LM_OK;
    return st;
}

static lm_status seam_commit(lm_views *base, const lm_patch *patch)
{
    wk_views_core *c = (wk_views_core *)base;
    lm_status st = wk_views_core_ready(c);
    if (st == LM_OK)
        st = c->backend->commit(c, patch);
    c->seq += st == LM_OK;
    return st;
}

static lm_status seam_evaluate(lm_views *base, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    wk_views_core *c = (wk_views_core *)base;
    lm_status st = wk_views_core_ready(c);
    if (st != LM_OK)
        return st;
    memset(delta, 0, n * sizeof *delta);
    return c->backend->evaluate(c, patches, n, delta);
}

static lm_status seam_energy(lm_views *base, int64_t *total, int64_t *per_view)
{
    wk_views_core *c = (wk_views_core *)base;
    return wk_views_answer_energy(c->mesh_set, c->img, total, per_view);
}

static lm_status seam_potentials(lm_views *base, const float (*points)[3], size_t n, int64_t *out)
{
    wk_views_core *c = (wk_views_core *)base;
    return wk_views_answer_potentials(c->mesh_set, c->img, &c->views, points, n, out);
}

static void seam_info(lm_views *base, lm_views_info *out)
{
    wk_views_core *c = (wk_views_core *)base;
    wk_views_answer_info(out, &c->views, c->width, c->height, c->seq, &c->stats,
                         c->backend->renderer(c));
}

static int known_kind(lm_image_kind kind)
{
    switch (kind) {
    case LM_IMAGE_TARGET_LUMA:
    case LM_IMAGE_CURRENT_LUMA:
    case LM_IMAGE_RGBA:
    case LM_IMAGE_COVERAGE:
    case LM_IMAGE_TRIANGLE:
        return 1;
    }
    return 0;
}

static lm_status seam_read_image(lm_views *base, lm_image_kind kind, uint32_t view, uint8_t *out)
{
    wk_views_core *c = (wk_views_core *)base;
    if (!known_kind(kind))
        return lm_fail(LM_E_INVALID, "unknown image kind %d", (int)kind);
    if (view >= c->views.count)
        return lm_fail(LM_E_RANGE, "view %u of %u", view, c->views.count);
    if (kind == LM_IMAGE_RGBA)
        return c->backend->read_rgba(c, view, out);
    if (kind == LM_IMAGE_COVERAGE)
        return c->backend->read_coverage(c, view, out);
    if (kind == LM_IMAGE_TRIANGLE)
        return c->backend->read_triangles
                   ? c->backend->read_triangles(c, view, (uint32_t *)(void *)out)
                   : lm_fail(LM_E_UNSUPPORTED, "this renderer gives no triangle ids");
    const uint8_t *src = kind == LM_IMAGE_TARGET_LUMA ? wk_image_store_target(c->img, view)
                                                      : wk_image_store_current(c->img, view);
    memcpy(out, src, (size_t)c->width * c->height);
    return LM_OK;
}

/* The current images become the targets (E = 0). */
static lm_status seam_retarget(lm_views *base)
{
    wk_views_core *c = (wk_views_core *)base;
    if (!c->mesh_set)
        return lm_fail(LM_E_INVALID, "retarget asked before a mesh was set");
    for (uint32_t h = 0; h < c->views.count; h++)
        wk_image_store_set_target(c->img, h, wk_image_store_current(c->img, h));
    c->backend->retargeted(c);
    c->seq++;
    return LM_OK;
}

static void seam_destroy(lm_views *base)
{
    wk_views_core *c = (wk_views_core *)base;
    c->backend->destroy(c);
    wk_views_core_free(c);
    free(c);
}

#define SEAM_OPS                                                                                   \
    .set_mesh = seam_set_mesh, .set_materials = seam_set_materials, .evaluate = seam_evaluate,     \
    .commit = seam_commit, .energy = seam_energy, .potentials = seam_potentials,                   \
    .read_image = seam_read_image, .info = seam_info, .destroy = seam_destroy

static const lm_views_ops ops = {SEAM_OPS};
static const lm_views_ops ops_retarget = {SEAM_OPS, .retarget = seam_retarget};

void wk_views_seam_attach(wk_views_core *c, const wk_views_backend *b)
{
    c->backend = b;
    c->base.ops = b->retargeted ? &ops_retarget : &ops;
}

lm_status wk_views_seam_created(wk_views_core *c, lm_status st, lm_views **out)
{
    if (st != LM_OK) {
        seam_destroy(&c->base);
        return st;
    }
    *out = &c->base;
    return LM_OK;
}

int wk_views_seam_is(const lm_views *v)
{
    return v && (v->ops == &ops || v->ops == &ops_retarget);
}
