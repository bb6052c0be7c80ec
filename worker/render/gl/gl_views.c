/* worker/render/gl/gl_views.c — the views backend on an EGL context: creation, target and
 * full current renders (chunked streams, one readback per view), the current mesh replica, the
 * colour and coverage images, occlusion, and the backend table through which views_seam.c
 * answers views_api.h. Incremental evaluation and commit are in views_eval.c. */
#include <EGL/egl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "worker/render/gl/gl_views_internal.h"
#include "worker/render/shared/views_seam.h"

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
    size_t cap = lm_grow_cap(v->stream_cap, n_tris, 4096, SIZE_MAX);
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
    size_t plane = (size_t)v->core.width * v->core.height;
    uint8_t *rgba = malloc(plane * 4), *y = malloc(plane);
    lm_status st = (rgba && y) ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory reading images");
    wk_rect all = {0, 0, v->core.width, v->core.height};
    int depth = !to_target && v->core.occlusion;
    for (uint32_t h = 0; st == LM_OK && h < v->core.views.count; h++) {
        st = wk_renderer_read(v->r, WK_FULL_ATLAS, h, &all, rgba);
        wk_luma_from_rgba(rgba, plane, y);
        if (to_target)
            wk_image_store_set_target(v->core.img, h, y);
        else
            wk_image_store_set_current(v->core.img, h, y);
        if (st == LM_OK && depth) { /* plane floats fit in the rgba buffer */
            st = wk_renderer_read_depth(v->r, WK_FULL_ATLAS, h, &all, (float *)(void *)rgba);
            wk_image_store_set_depth(v->core.img, h, (const float *)(void *)rgba);
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
        for (uint32_t h = 0; st == LM_OK && h < v->core.views.count; h++) {
            wk_draw d = {WK_FULL_ATLAS, h, 0, n, {0, 0, v->core.width, v->core.height}};
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
    uint32_t n_mat = wk_renderer_material_count(v->r, v->core.table);
    lm_replica_clear(&v->core.rep);
    for (size_t i = 0; i < n; i++) {
        if (tris[i].material >= n_mat)
            return lm_fail(LM_E_RANGE, "triangle %u uses material %u of %u", tris[i].id,
                           tris[i].material, n_mat);
        lm_status st = lm_replica_put(&v->core.rep, &tris[i]);
        if (st != LM_OK)
            return st;
    }
    v->core.buckets_ready = 0; /* built on the first evaluate/commit: energy alone needs none */
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
    v->core.mesh_set = 0;
    st = build_replica(v, tris, n);
    if (st == LM_OK) {
        tri_source src = {.tris = tris, .order = order, .n = n};
        st = render_full(v, v->core.table, &src, 0);
    }
    free(order);
    v->core.mesh_set = st == LM_OK;
    return st;
}

static lm_status vl_set_mesh(wk_views_core *c, const lm_tri_data *tris, size_t n)
{
    return set_mesh_quiet((wk_views_local *)c, tris, n);
}

/* Re-render the replica from scratch (after a material change). */
static lm_status rerender_replica(wk_views_local *v)
{
    lm_tri_data *tris = malloc((v->core.rep.n_alive + 1) * sizeof *tris);
    if (!tris)
        return lm_fail(LM_E_NOMEM, "out of memory re-rendering the mesh");
    size_t n = 0;
    for (size_t id = 0; id < v->core.rep.cap; id++)
        if (v->core.rep.alive[id])
            tris[n++] = v->core.rep.tris[id];
    lm_status st = set_mesh_quiet(v, tris, n);
    free(tris);
    return st;
}

/* ---- the backend table ------------------------------------------------------------------ */

static const char *vl_renderer(const wk_views_core *c)
{
    return wk_gl_context_description(((const wk_views_local *)c)->ctx);
}

/* The backend's own parts (views_seam.c frees the core's). */
static void vl_destroy(wk_views_core *c)
{
    wk_views_local *v = (wk_views_local *)c;
    if (v->ctx && wk_vl_make_current(v) == LM_OK)
        wk_renderer_destroy(v->r);
    wk_gl_context_destroy(v->ctx);
    wk_vl_free_eval(v);
    free(v->stream);
    free(v->stream_mat);
}

/* After a retarget: cached evaluations priced the old targets. */
static void vl_retargeted(wk_views_core *c)
{
    wk_vl_forget_cache((wk_views_local *)c);
}

static lm_status vl_set_materials(wk_views_core *c, const lm_material *mats, uint32_t n);
static lm_status vl_set_occlusion(wk_views_core *c, int on);
static lm_status vl_read_rgba(wk_views_core *c, uint32_t view, uint8_t *out);
static lm_status vl_read_coverage(wk_views_core *c, uint32_t view, uint8_t *out);

static const wk_views_backend vl_backend = {
    .set_mesh = vl_set_mesh,
    .set_materials = vl_set_materials,
    .commit = wk_vl_commit,
    .evaluate = wk_vl_evaluate,
    .read_rgba = vl_read_rgba,
    .read_coverage = vl_read_coverage,
    .renderer = vl_renderer,
    .set_occlusion = vl_set_occlusion,
    .retargeted = vl_retargeted,
    .destroy = vl_destroy,
};

/* ---- creation ---------------------------------------------------------------------------- */

static lm_status create_parts(wk_views_local *v, const lm_mesh *original, lm_view_deal deal,
                              uint32_t total)
{
    lm_status st = wk_vl_make_current(v);
    if (st == LM_OK)
        st = wk_renderer_create(&v->core.views, deal, total, &v->r);
    if (st == LM_OK)
        st = wk_renderer_set_materials(v->r, 0, original->materials, original->n_materials);
    if (st == LM_OK)
        st = wk_views_core_create_parts(&v->core);
    if (st == LM_OK && wk_renderer_has_depth_images(v->r)) {
        st = wk_image_store_enable_depth(v->core.img);
        v->core.occlusion = st == LM_OK;
    }
    return st;
}

/* Targets given (wk_gl_views_create): into the image store as the render would put them. */
static void take_targets(wk_views_local *v, const uint8_t *targets)
{
    size_t plane = (size_t)v->core.width * v->core.height;
    for (uint32_t h = 0; h < v->core.views.count; h++)
        wk_image_store_set_target(v->core.img, h, targets + h * plane);
}

lm_status wk_gl_views_create(const lm_mesh *original, const lm_view_set *views, lm_view_deal deal,
                             uint32_t total, wk_gl_context *ctx, const uint8_t *targets,
                             lm_views **out)
{
    wk_views_local *v = calloc(1, sizeof *v);
    if (!v) {
        wk_gl_context_destroy(ctx);
        return lm_fail(LM_E_NOMEM, "out of memory creating the views");
    }
    wk_views_core_init(&v->core, views->views, views->count);
    wk_views_seam_attach(&v->core, &vl_backend);
    v->ctx = ctx;
    lm_status st = create_parts(v, original, deal, total);
    if (st == LM_OK && targets) {
        take_targets(v, targets);
    } else if (st == LM_OK) {
        tri_source src = {.mesh = original};
        st = render_full(v, 0, &src, 1);
    }
    return wk_views_seam_created(&v->core, st, out);
}

/* ---- extras ------------------------------------------------------------------------------ */

static lm_status vl_set_materials(wk_views_core *c, const lm_material *mats, uint32_t n)
{
    wk_views_local *v = (wk_views_local *)c;
    lm_status st = wk_vl_make_current(v);
    if (st == LM_OK)
        st = wk_renderer_set_materials(v->r, 1, mats, n);
    if (st == LM_OK) {
        v->core.table = 1;
        st = v->core.mesh_set ? rerender_replica(v) : LM_OK;
    }
    return st;
}

static lm_status vl_set_occlusion(wk_views_core *c, int on)
{
    wk_views_local *v = (wk_views_local *)c;
    if (on && !wk_image_store_has_depth(v->core.img))
        return lm_fail(LM_E_UNSUPPORTED, "this device cannot render depth images");
    int was = v->core.occlusion;
    v->core.occlusion = on != 0;
    wk_vl_forget_cache(v);
    if (v->core.occlusion && !was && v->core.mesh_set) {
        lm_status st = wk_vl_make_current(v);
        return st == LM_OK ? rerender_replica(v) : st;
    }
    return LM_OK;
}

static lm_status vl_read_rgba(wk_views_core *c, uint32_t view, uint8_t *out)
{
    wk_views_local *v = (wk_views_local *)c;
    lm_status st = wk_vl_make_current(v);
    wk_rect all = {0, 0, v->core.width, v->core.height};
    if (st == LM_OK)
        st = wk_renderer_read(v->r, WK_FULL_ATLAS, view, &all, out);
    return st == LM_OK ? wk_renderer_check(v->r, "reading a colour image") : st;
}

static lm_status vl_read_coverage(wk_views_core *c, uint32_t view, uint8_t *out)
{
    wk_views_local *v = (wk_views_local *)c;
    lm_status st = wk_vl_make_current(v);
    if (st == LM_OK && !wk_renderer_has_depth_images(v->r))
        return lm_fail(LM_E_UNSUPPORTED, "this device has no readable depth images");
    size_t plane = (size_t)v->core.width * v->core.height;
    float *z = malloc(plane * sizeof *z);
    if (st == LM_OK && !z)
        st = lm_fail(LM_E_NOMEM, "out of memory reading a depth image");
    wk_rect all = {0, 0, v->core.width, v->core.height};
    if (st == LM_OK)
        st = wk_renderer_read_depth(v->r, WK_FULL_ATLAS, view, &all, z);
    for (size_t i = 0; st == LM_OK && i < plane; i++)
        out[i] = z[i] < 1.0f;
    free(z);
    return st == LM_OK ? wk_renderer_check(v->r, "reading a depth image") : st;
}
