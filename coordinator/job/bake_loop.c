/* coordinator/job/bake_loop.c — the optimizer's bakes and the views wrapper that shows them (see
 * bake_loop.h). */
#include "coordinator/job/bake_loop.h"

#include <stdlib.h>
#include <string.h>

#include "common/uv_atlas.h"
#include "coordinator/job/bake.h"

struct co_bake_loop {
    const lm_mesh *original;
    unsigned kinds;
    int size;
    uint32_t cells; /* the last bake's grid side; 0 = none yet */
    lm_mesh *atlas; /* the last bake's atlas: its materials wear the maps */
};

typedef struct loop_views {
    lm_views base;
    co_bake_loop *b;
    lm_views *inner;
    lm_tri_data *tris; /* scratch: rewritten triangles */
    size_t cap_tris;
    lm_patch *patches; /* scratch: the patches over them */
    uint32_t cap_patches;
} loop_views;

lm_status co_bake_loop_create(const lm_mesh *original, unsigned kinds, int size, co_bake_loop **out)
{
    *out = calloc(1, sizeof **out);
    if (!*out)
        return lm_fail(LM_E_NOMEM, "out of memory for the loop's bakes");
    (*out)->original = original;
    (*out)->kinds = kinds;
    (*out)->size = size;
    return LM_OK;
}

void co_bake_loop_destroy(co_bake_loop *b)
{
    if (!b)
        return;
    lm_mesh_destroy(b->atlas);
    free(b);
}

const lm_material *co_bake_loop_materials(const co_bake_loop *b, uint32_t *n)
{
    *n = b->atlas ? b->atlas->n_materials : 0;
    return b->atlas ? b->atlas->materials : NULL;
}

uint32_t co_bake_loop_cells(const co_bake_loop *b)
{
    return b->cells;
}

lm_status co_bake_loop_bake(co_bake_loop *b, const lm_mesh *m, lm_bake_stats *stats)
{
    /* room for the ids the moves make before the next bake */
    uint32_t cells = lm_atlas_cells(m->n_tris + m->n_tris / 4 + 16);
    lm_mesh *a;
    lm_status st = lm_atlas_by_id(m, b->size, cells, &a);
    if (st != LM_OK)
        return st;
    a->attrs |= LM_ATTR_NORMAL; /* the wedges hold the optimizer's normals (derived or not) */
    st = co_bake_attach(b->original, a, m, b->kinds, b->size, stats, NULL);
    if (st != LM_OK) {
        lm_mesh_destroy(a);
        return st;
    }
    lm_mesh_destroy(b->atlas);
    b->atlas = a;
    b->cells = cells;
    return LM_OK;
}

/* Triangle d as the views see it: its id's chart; white with a colour map. */
static void rewrite(const co_bake_loop *b, lm_tri_data *d)
{
    uint32_t cell = d->id % (b->cells * b->cells);
    for (int k = 0; k < 3; k++) {
        lm_atlas_cell_uv(cell, b->cells, b->size, k, d->c[k].uv);
        if (b->kinds & CO_BAKE_COLOR)
            for (int ch = 0; ch < 4; ch++)
                d->c[k].color[ch] = 1.0f;
    }
}

static lm_status grow_tris(loop_views *lv, size_t n)
{
    if (n <= lv->cap_tris)
        return LM_OK;
    size_t cap = n + n / 2 + 16;
    lm_tri_data *t = realloc(lv->tris, cap * sizeof *t);
    if (!t)
        return lm_fail(LM_E_NOMEM, "out of memory rewriting triangles for the loop's maps");
    lv->tris = t;
    lv->cap_tris = cap;
    return LM_OK;
}

/* Copies of patches[0..n) over rewritten triangles (*out = patches itself before a bake). */
static lm_status rewrite_patches(loop_views *lv, const lm_patch *patches, uint32_t n,
                                 const lm_patch **out)
{
    *out = patches;
    if (!lv->b->cells)
        return LM_OK;
    size_t total = 0;
    for (uint32_t i = 0; i < n; i++)
        total += patches[i].n_added;
    lm_status st = grow_tris(lv, total);
    if (st != LM_OK)
        return st;
    if (n > lv->cap_patches) {
        lm_patch *p = realloc(lv->patches, (size_t)n * sizeof *p);
        if (!p)
            return lm_fail(LM_E_NOMEM, "out of memory rewriting patches for the loop's maps");
        lv->patches = p;
        lv->cap_patches = n;
    }
    size_t at = 0;
    for (uint32_t i = 0; i < n; i++) {
        lv->patches[i] = patches[i];
        lv->patches[i].added = lv->tris + at;
        lv->patches[i].cap_added = patches[i].n_added;
        for (uint32_t k = 0; k < patches[i].n_added; k++) {
            lv->tris[at] = patches[i].added[k];
            rewrite(lv->b, &lv->tris[at++]);
        }
    }
    *out = lv->patches;
    return LM_OK;
}

static loop_views *as_lv(lm_views *v)
{
    return (loop_views *)v;
}

static lm_status lv_set_mesh(lm_views *v, const lm_tri_data *tris, size_t n)
{
    loop_views *lv = as_lv(v);
    if (!lv->b->cells)
        return lv->inner->ops->set_mesh(lv->inner, tris, n);
    lm_status st = grow_tris(lv, n);
    if (st != LM_OK)
        return st;
    for (size_t i = 0; i < n; i++) {
        lv->tris[i] = tris[i];
        rewrite(lv->b, &lv->tris[i]);
    }
    return lv->inner->ops->set_mesh(lv->inner, lv->tris, n);
}

static lm_status lv_set_materials(lm_views *v, const lm_material *mats, uint32_t n)
{
    return as_lv(v)->inner->ops->set_materials(as_lv(v)->inner, mats, n);
}

static lm_status lv_evaluate(lm_views *v, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    const lm_patch *p;
    lm_status st = rewrite_patches(as_lv(v), patches, n, &p);
    return st == LM_OK ? as_lv(v)->inner->ops->evaluate(as_lv(v)->inner, p, n, delta) : st;
}

static lm_status lv_evaluate_overlapped(lm_views *v, const lm_patch *patches, uint32_t n,
                                        int64_t *delta, void (*overlap)(void *ctx), void *ctx)
{
    const lm_patch *p;
    lm_status st = rewrite_patches(as_lv(v), patches, n, &p);
    return st == LM_OK ? lm_views_evaluate_overlapped(as_lv(v)->inner, p, n, delta, overlap, ctx)
                       : st;
}

static lm_status lv_commit(lm_views *v, const lm_patch *patch)
{
    const lm_patch *p;
    lm_status st = rewrite_patches(as_lv(v), patch, 1, &p);
    return st == LM_OK ? as_lv(v)->inner->ops->commit(as_lv(v)->inner, p) : st;
}

static lm_status lv_energy(lm_views *v, int64_t *total, int64_t *per_view)
{
    return as_lv(v)->inner->ops->energy(as_lv(v)->inner, total, per_view);
}

static lm_status lv_potentials(lm_views *v, const float (*points)[3], size_t n, int64_t *out)
{
    return as_lv(v)->inner->ops->potentials(as_lv(v)->inner, points, n, out);
}

static lm_status lv_read_image(lm_views *v, lm_image_kind kind, uint32_t view, uint8_t *out)
{
    return as_lv(v)->inner->ops->read_image(as_lv(v)->inner, kind, view, out);
}

static void lv_info(lm_views *v, lm_views_info *out)
{
    as_lv(v)->inner->ops->info(as_lv(v)->inner, out);
}

static void lv_destroy(lm_views *v)
{
    loop_views *lv = as_lv(v);
    lm_views_destroy(lv->inner);
    free(lv->tris);
    free(lv->patches);
    free(lv);
}

static lm_status lv_retarget(lm_views *v)
{
    return lm_views_retarget(as_lv(v)->inner);
}

static lm_status lv_surface_term(lm_views *v, const lm_mesh *surface, double k)
{
    return lm_views_surface_term(as_lv(v)->inner, surface, k);
}

static lm_status lv_evaluate_surface(lm_views *v, const lm_patch *patches, uint32_t n,
                                     int64_t *delta)
{
    const lm_patch *p;
    lm_status st = rewrite_patches(as_lv(v), patches, n, &p);
    return st == LM_OK ? as_lv(v)->inner->ops->evaluate_surface(as_lv(v)->inner, p, n, delta) : st;
}

static const lm_views_ops loop_ops = {
    .set_mesh = lv_set_mesh,
    .set_materials = lv_set_materials,
    .evaluate = lv_evaluate,
    .evaluate_overlapped = lv_evaluate_overlapped,
    .commit = lv_commit,
    .energy = lv_energy,
    .potentials = lv_potentials,
    .read_image = lv_read_image,
    .info = lv_info,
    .destroy = lv_destroy,
    .retarget = lv_retarget,
    .surface_term = lv_surface_term,
    .evaluate_surface = lv_evaluate_surface,
};

lm_status co_bake_loop_wrap(co_bake_loop *b, lm_views *inner, lm_views **out)
{
    *out = NULL;
    loop_views *lv = calloc(1, sizeof *lv);
    if (!lv) {
        lm_views_destroy(inner);
        return lm_fail(LM_E_NOMEM, "out of memory for the loop's views");
    }
    lv->base.ops = &loop_ops;
    lv->b = b;
    lv->inner = inner;
    *out = &lv->base;
    return LM_OK;
}
