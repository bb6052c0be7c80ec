/* worker/render/gl/gl_views.c — the views backend on an EGL context: creation, target and
 * full current renders (chunked streams, one readback per view), the current mesh replica and
 * its triangle buckets, energies, the oracle's potentials and the ops table. Incremental
 * evaluation and commit are in views_eval.c. */
#include <EGL/egl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "worker/render/gl/gl_views_internal.h"

lm_status wk_vl_make_current(wk_views_local *v)
{
    if (v->egl_context && eglGetCurrentContext() == (EGLContext)v->egl_context)
        return LM_OK;
    lm_status st = wk_gl_context_make_current(v->ctx);
    if (st == LM_OK)
        v->egl_context = (void *)eglGetCurrentContext();
    return st;
}

lm_status wk_vl_stream_reserve(wk_views_local *v, size_t n_tris)
{
    if (n_tris <= v->stream_cap)
        return LM_OK;
    size_t cap = v->stream_cap ? v->stream_cap : 4096;
    while (cap < n_tris)
        cap *= 2;
    lm_corner *s = realloc(v->stream, cap * 3 * sizeof *s);
    if (s)
        v->stream = s;
    uint32_t *m = realloc(v->stream_mat, cap * sizeof *m);
    if (m)
        v->stream_mat = m;
    if (!s || !m)
        return lm_fail(LM_E_NOMEM, "out of memory for a stream of %zu triangles", cap);
    v->stream_cap = cap;
    return LM_OK;
}

/* ---- full renders ------------------------------------------------------------------------ */

/* A source of triangle records in ascending id order, pushed into the stream chunk by chunk. */
typedef struct tri_source {
    const lm_mesh *mesh; /* either a mesh (alive triangles) ... */
    uint32_t next_id;
    const lm_tri_data *tris; /* ... or records, in the order `order` (NULL: as given) */
    const uint32_t *order;
    size_t n, pos;
} tri_source;

static size_t source_fill(wk_views_local *v, tri_source *s, size_t cap)
{
    size_t k = 0;
    if (s->mesh) {
        lm_tri_data t;
        for (; k < cap && s->next_id < s->mesh->n_tris; s->next_id++)
            if (s->mesh->tri_alive[s->next_id]) {
                lm_tri_data_from_mesh(s->mesh, s->next_id, &t);
                wk_vl_stream_push(v, &t);
                k++;
            }
        return k;
    }
    for (; k < cap && s->pos < s->n; k++, s->pos++)
        wk_vl_stream_push(v, &s->tris[s->order ? s->order[s->pos] : s->pos]);
    return k;
}

/* Read every view of the full atlas into the target (to_target) or current images. */
static lm_status read_full(wk_views_local *v, int to_target)
{
    size_t plane = (size_t)v->width * v->height;
    uint8_t *rgba = malloc(plane * 4), *y = malloc(plane);
    lm_status st = (rgba && y) ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory reading images");
    wk_rect all = {0, 0, v->width, v->height};
    int depth = !to_target && v->occlusion;
    for (uint32_t h = 0; st == LM_OK && h < v->views.count; h++) {
        st = wk_renderer_read(v->r, WK_FULL_ATLAS, h, &all, rgba);
        wk_luma_from_rgba(rgba, plane, y);
        if (to_target)
            wk_image_store_set_target(v->img, h, y);
        else
            wk_image_store_set_current(v->img, h, y);
        if (st == LM_OK && depth) { /* plane floats fit in the rgba buffer */
            st = wk_renderer_read_depth(v->r, WK_FULL_ATLAS, h, &all, (float *)(void *)rgba);
            wk_image_store_set_depth(v->img, h, (const float *)(void *)rgba);
        }
    }
    free(rgba);
    free(y);
    if (st == LM_OK)
        st = wk_renderer_check(v->r, "reading back full images");
    return st;
}

static lm_status render_full(wk_views_local *v, int table, tri_source *src, int to_target)
{
    lm_status st = wk_vl_stream_reserve(v, WK_FULL_CHUNK);
    if (st == LM_OK)
        st = wk_renderer_clear_all(v->r, WK_FULL_ATLAS);
    while (st == LM_OK) {
        v->stream_n = 0;
        size_t n = source_fill(v, src, WK_FULL_CHUNK);
        if (n == 0)
            break;
        st = wk_renderer_upload(v->r, v->stream, n);
        for (uint32_t h = 0; st == LM_OK && h < v->views.count; h++) {
            wk_draw d = {WK_FULL_ATLAS, h, 0, n, {0, 0, v->width, v->height}};
            st = wk_renderer_draw(v->r, table, &d, v->stream_mat);
        }
    }
    if (st == LM_OK)
        st = wk_renderer_check(v->r, "rendering full images");
    return st == LM_OK ? read_full(v, to_target) : st;
}

/* ---- set_mesh ---------------------------------------------------------------------------- */

static int cmp_by_id(const void *a, const void *b, const lm_tri_data *tris)
{
    uint32_t x = tris[*(const uint32_t *)a].id, y = tris[*(const uint32_t *)b].id;
    return (x > y) - (x < y);
}

/* Indices of tris in ascending id order (NULL result: already ascending); refuses duplicates. */
static lm_status order_by_id(const lm_tri_data *tris, size_t n, uint32_t **order)
{
    *order = NULL;
    size_t i = 1;
    while (i < n && tris[i - 1].id < tris[i].id)
        i++;
    if (i >= n)
        return LM_OK;
    uint32_t *o = malloc(n * sizeof *o);
    if (!o)
        return lm_fail(LM_E_NOMEM, "out of memory sorting %zu triangles", n);
    for (i = 0; i < n; i++)
        o[i] = (uint32_t)i;
    /* merge sort through a temporary keeps this deterministic and O(n log n) */
    uint32_t *tmp = malloc(n * sizeof *tmp);
    if (!tmp) {
        free(o);
        return lm_fail(LM_E_NOMEM, "out of memory sorting %zu triangles", n);
    }
    for (size_t w = 1; w < n; w *= 2) {
        for (size_t lo = 0; lo < n; lo += 2 * w) {
            size_t mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n;
            size_t a = lo, b = mid, k = lo;
            while (a < mid || b < hi)
                tmp[k++] =
                    (b >= hi || (a < mid && cmp_by_id(&o[a], &o[b], tris) <= 0)) ? o[a++] : o[b++];
        }
        memcpy(o, tmp, n * sizeof *o);
    }
    free(tmp);
    for (i = 1; i < n; i++)
        if (tris[o[i - 1]].id == tris[o[i]].id) {
            uint32_t id = tris[o[i]].id;
            free(o);
            return lm_fail(LM_E_INVALID, "triangle id %u appears twice in the mesh", id);
        }
    *order = o;
    return LM_OK;
}

static lm_status build_replica(wk_views_local *v, const lm_tri_data *tris, size_t n)
{
    uint32_t n_mat = wk_renderer_material_count(v->r, v->table);
    wk_replica_clear(&v->rep);
    for (size_t i = 0; i < n; i++) {
        if (tris[i].material >= n_mat)
            return lm_fail(LM_E_RANGE, "triangle %u uses material %u of %u", tris[i].id,
                           tris[i].material, n_mat);
        lm_status st = wk_replica_put(&v->rep, &tris[i]);
        if (st != LM_OK)
            return st;
    }
    v->buckets_ready = 0; /* built on the first evaluate/commit: energy alone needs none */
    return LM_OK;
}

lm_status wk_vl_build_buckets(wk_views_local *v)
{
    for (uint32_t h = 0; h < v->views.count; h++) {
        lm_status st = wk_buckets_fill(v->buckets[h], &v->views.views[h], &v->rep);
        if (st != LM_OK)
            return st;
    }
    v->buckets_ready = 1;
    return LM_OK;
}

/* set_mesh without advancing the sequence number (also the re-render after a material change). */
static lm_status set_mesh_quiet(wk_views_local *v, const lm_tri_data *tris, size_t n)
{
    lm_status st = wk_vl_make_current(v);
    if (st != LM_OK)
        return st;
    if (n > LM_MESH_MAX_TRIS)
        return lm_fail(LM_E_RANGE, "mesh of %zu triangles exceeds the limit", n);
    for (size_t i = 0; i < n; i++)
        if (tris[i].id >= LM_MESH_MAX_TRIS)
            return lm_fail(LM_E_RANGE, "triangle id %u exceeds the limit", tris[i].id);
    uint32_t *order;
    if ((st = order_by_id(tris, n, &order)) != LM_OK)
        return st;
    wk_vl_forget_cache(v);
    v->mesh_set = 0;
    st = build_replica(v, tris, n);
    if (st == LM_OK) {
        tri_source src = {.tris = tris, .order = order, .n = n};
        st = render_full(v, v->table, &src, 0);
    }
    free(order);
    v->mesh_set = st == LM_OK;
    return st;
}

static lm_status vl_set_mesh(lm_views *base, const lm_tri_data *tris, size_t n)
{
    wk_views_local *v = (wk_views_local *)base;
    lm_status st = set_mesh_quiet(v, tris, n);
    v->seq += st == LM_OK;
    return st;
}

/* Re-render the replica from scratch (after a material change). */
static lm_status rerender_replica(wk_views_local *v)
{
    lm_tri_data *tris = malloc((v->rep.n_alive + 1) * sizeof *tris);
    if (!tris)
        return lm_fail(LM_E_NOMEM, "out of memory re-rendering the mesh");
    size_t n = 0;
    for (size_t id = 0; id < v->rep.cap; id++)
        if (v->rep.alive[id])
            tris[n++] = v->rep.tris[id];
    lm_status st = set_mesh_quiet(v, tris, n);
    free(tris);
    return st;
}

/* ---- energy, oracle, info ---------------------------------------------------------------- */

static lm_status vl_energy(lm_views *base, int64_t *total, int64_t *per_view)
{
    wk_views_local *v = (wk_views_local *)base;
    return wk_views_answer_energy(v->mesh_set, v->img, total, per_view);
}

static lm_status vl_potentials(lm_views *base, const float (*points)[3], size_t n, int64_t *out)
{
    wk_views_local *v = (wk_views_local *)base;
    return wk_views_answer_potentials(v->mesh_set, v->img, &v->views, points, n, out);
}

static void vl_info(lm_views *base, lm_views_info *out)
{
    wk_views_local *v = (wk_views_local *)base;
    wk_views_answer_info(out, &v->views, v->width, v->height, v->seq, &v->stats,
                         wk_gl_context_description(v->ctx));
}

static void vl_destroy(lm_views *base)
{
    wk_views_local *v = (wk_views_local *)base;
    if (v->ctx && wk_vl_make_current(v) == LM_OK)
        wk_renderer_destroy(v->r);
    wk_gl_context_destroy(v->ctx);
    for (uint32_t h = 0; h < LM_MAX_VIEWS; h++)
        wk_buckets_destroy(v->buckets[h]);
    wk_image_store_destroy(v->img);
    wk_replica_free(&v->rep);
    wk_vl_free_eval(v);
    free(v->stream);
    free(v->stream_mat);
    free(v);
}

/* The current images become the targets (E = 0); cached evaluations priced the old targets. */
static lm_status vl_retarget(lm_views *base)
{
    wk_views_local *v = (wk_views_local *)base;
    if (!v->mesh_set)
        return lm_fail(LM_E_INVALID, "retarget asked before a mesh was set");
    for (uint32_t h = 0; h < v->views.count; h++)
        wk_image_store_set_target(v->img, h, wk_image_store_current(v->img, h));
    wk_vl_forget_cache(v);
    v->seq++;
    return LM_OK;
}

static lm_status vl_set_materials(lm_views *base, const lm_material *mats, uint32_t n);
static lm_status vl_read_image(lm_views *base, lm_image_kind kind, uint32_t view, uint8_t *out);

static const lm_views_ops vl_ops = {
    .set_mesh = vl_set_mesh,
    .set_materials = vl_set_materials,
    .evaluate = wk_vl_evaluate,
    .commit = wk_vl_commit,
    .energy = vl_energy,
    .potentials = vl_potentials,
    .read_image = vl_read_image,
    .info = vl_info,
    .destroy = vl_destroy,
    .retarget = vl_retarget,
};

/* ---- creation ---------------------------------------------------------------------------- */

static lm_status create_parts(wk_views_local *v, const lm_mesh *original, lm_view_deal deal,
                              uint32_t total)
{
    lm_status st = wk_vl_make_current(v);
    if (st == LM_OK)
        st = wk_renderer_create(&v->views, deal, total, &v->r);
    if (st == LM_OK)
        st = wk_renderer_set_materials(v->r, 0, original->materials, original->n_materials);
    if (st == LM_OK)
        st = wk_image_store_create(v->views.count, v->width, v->height, &v->img);
    for (uint32_t h = 0; st == LM_OK && h < v->views.count; h++)
        st = wk_buckets_create(v->width, v->height, 0, &v->buckets[h]);
    if (st == LM_OK && wk_renderer_has_depth_images(v->r)) {
        st = wk_image_store_enable_depth(v->img);
        v->occlusion = st == LM_OK;
    }
    return st;
}

lm_status wk_gl_views_create(const lm_mesh *original, const lm_view_set *views, lm_view_deal deal,
                             uint32_t total, wk_gl_context *ctx, lm_views **out)
{
    wk_views_local *v = calloc(1, sizeof *v);
    if (!v) {
        wk_gl_context_destroy(ctx);
        return lm_fail(LM_E_NOMEM, "out of memory creating the views");
    }
    v->base.ops = &vl_ops;
    v->ctx = ctx;
    v->views = *views;
    v->width = views->views[0].width;
    v->height = views->views[0].height;
    wk_replica_init(&v->rep);
    lm_status st = create_parts(v, original, deal, total);
    if (st == LM_OK) {
        tri_source src = {.mesh = original};
        st = render_full(v, 0, &src, 1);
    }
    if (st != LM_OK) {
        vl_destroy(&v->base);
        return st;
    }
    *out = &v->base;
    return LM_OK;
}

/* ---- extras ------------------------------------------------------------------------------ */

static lm_status vl_set_materials(lm_views *base, const lm_material *mats, uint32_t n)
{
    wk_views_local *v = (wk_views_local *)base;
    lm_status st = wk_vl_make_current(v);
    if (st == LM_OK)
        st = wk_renderer_set_materials(v->r, 1, mats, n);
    if (st == LM_OK) {
        v->table = 1;
        st = v->mesh_set ? rerender_replica(v) : LM_OK;
    }
    v->seq += st == LM_OK;
    return st;
}

int wk_gl_views_is(const lm_views *views)
{
    return views && views->ops == &vl_ops;
}

lm_status wk_gl_views_set_occlusion(lm_views *base, int on)
{
    wk_views_local *v = (wk_views_local *)base;
    if (on && !wk_image_store_has_depth(v->img))
        return lm_fail(LM_E_UNSUPPORTED, "this device cannot render depth images");
    int was = v->occlusion;
    v->occlusion = on != 0;
    wk_vl_forget_cache(v);
    if (v->occlusion && !was && v->mesh_set) {
        lm_status st = wk_vl_make_current(v);
        return st == LM_OK ? rerender_replica(v) : st;
    }
    return LM_OK;
}

void wk_gl_views_get_stats(lm_views *base, wk_views_local_stats *out)
{
    *out = ((wk_views_local *)base)->stats;
}

static lm_status read_luma(wk_views_local *v, int which, uint32_t view, uint8_t *out)
{
    if (view >= v->views.count)
        return lm_fail(LM_E_RANGE, "view %u of %u", view, v->views.count);
    const uint8_t *src =
        which ? wk_image_store_target(v->img, view) : wk_image_store_current(v->img, view);
    memcpy(out, src, (size_t)v->width * v->height);
    return LM_OK;
}

static lm_status read_rgba(wk_views_local *v, uint32_t view, uint8_t *out)
{
    if (view >= v->views.count)
        return lm_fail(LM_E_RANGE, "view %u of %u", view, v->views.count);
    lm_status st = wk_vl_make_current(v);
    wk_rect all = {0, 0, v->width, v->height};
    if (st == LM_OK)
        st = wk_renderer_read(v->r, WK_FULL_ATLAS, view, &all, out);
    return st == LM_OK ? wk_renderer_check(v->r, "reading a colour image") : st;
}

static lm_status read_coverage(wk_views_local *v, uint32_t view, uint8_t *out)
{
    if (view >= v->views.count)
        return lm_fail(LM_E_RANGE, "view %u of %u", view, v->views.count);
    lm_status st = wk_vl_make_current(v);
    if (st == LM_OK && !wk_renderer_has_depth_images(v->r))
        return lm_fail(LM_E_UNSUPPORTED, "this device has no readable depth images");
    size_t plane = (size_t)v->width * v->height;
    float *z = malloc(plane * sizeof *z);
    if (st == LM_OK && !z)
        st = lm_fail(LM_E_NOMEM, "out of memory reading a depth image");
    wk_rect all = {0, 0, v->width, v->height};
    if (st == LM_OK)
        st = wk_renderer_read_depth(v->r, WK_FULL_ATLAS, view, &all, z);
    for (size_t i = 0; st == LM_OK && i < plane; i++)
        out[i] = z[i] < 1.0f;
    free(z);
    return st == LM_OK ? wk_renderer_check(v->r, "reading a depth image") : st;
}

static lm_status vl_read_image(lm_views *base, lm_image_kind kind, uint32_t view, uint8_t *out)
{
    wk_views_local *v = (wk_views_local *)base;
    switch (kind) {
    case LM_IMAGE_TARGET_LUMA:
        return read_luma(v, 1, view, out);
    case LM_IMAGE_CURRENT_LUMA:
        return read_luma(v, 0, view, out);
    case LM_IMAGE_RGBA:
        return read_rgba(v, view, out);
    case LM_IMAGE_COVERAGE:
        return read_coverage(v, view, out);
    }
    return lm_fail(LM_E_INVALID, "unknown image kind %d", (int)kind);
}
