/* worker/render/cpu/cpu_views.c — the CPU views backend's life cycle: creation (target images of
 * the original), set_mesh and set_materials (full renders of the current mesh), its colour and
 * coverage images, occlusion, and the backend table through which views_seam.c answers
 * views_api.h. Full renders are in cpu_render.c, evaluate and commit in cpu_eval.c. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "worker/render/cpu/cpu_views_internal.h"
#include "worker/render/shared/views_seam.h"

/* Full renders of every view from src: keys, counts (current mesh only), luminance. */
static lm_status render_all(wk_cpu_views *v, const wk_cpu_source *src, int table, int to_target)
{
    size_t n_ids = to_target ? 0 : src->rep->cap;
    uint8_t *y = malloc(v->plane);
    uint32_t *cnt = to_target ? NULL : malloc((n_ids ? n_ids : 1) * sizeof *cnt);
    if (!y || (!to_target && !cnt)) {
        free(y);
        free(cnt);
        return lm_fail(LM_E_NOMEM, "out of memory rendering %zu pixels", v->plane);
    }
    lm_status st = to_target ? LM_OK : wk_cpu_count_reserve(v, n_ids);
    for (uint32_t h = 0; st == LM_OK && h < v->core.views.count; h++) {
        st = wk_cpu_render_view(v, h, src, table, y, cnt);
        for (size_t id = 0; st == LM_OK && id < n_ids; id++) /* into the counts' layout */
            *wk_cpu_count(v, h, (uint32_t)id) = cnt[id];
        if (st == LM_OK && to_target)
            wk_image_store_set_target(v->core.img, h, y);
        else if (st == LM_OK)
            wk_image_store_set_current(v->core.img, h, y);
    }
    free(cnt);
    free(y);
    return st;
}

static lm_status build_replica(wk_cpu_views *v, const lm_tri_data *tris, size_t n)
{
    lm_replica_clear(&v->core.rep);
    for (size_t i = 0; i < n; i++) {
        if (tris[i].id >= LM_MESH_MAX_TRIS)
            return lm_fail(LM_E_RANGE, "triangle id %u exceeds the limit", tris[i].id);
        if (tris[i].material >= v->mats[v->core.table].n)
            return lm_fail(LM_E_RANGE, "triangle %u uses material %u of %u", tris[i].id,
                           tris[i].material, v->mats[v->core.table].n);
        if (lm_replica_alive(&v->core.rep, tris[i].id))
            return lm_fail(LM_E_INVALID, "triangle id %u appears twice in the mesh", tris[i].id);
        lm_status st = lm_replica_put(&v->core.rep, &tris[i]);
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}

static lm_status cv_set_mesh(wk_views_core *c, const lm_tri_data *tris, size_t n)
{
    wk_cpu_views *v = (wk_cpu_views *)c;
    if (n > LM_MESH_MAX_TRIS)
        return lm_fail(LM_E_RANGE, "mesh of %zu triangles exceeds the limit", n);
    v->core.mesh_set = 0;
    v->core.buckets_ready = 0; /* built on the first evaluate/commit: energy alone needs none */
    wk_cpu_subcache_clear(&v->subcache);
    lm_status st = build_replica(v, tris, n);
    if (st == LM_OK)
        st = wk_cpu_subcache_reserve(&v->subcache, v->core.rep.cap);
    if (st == LM_OK) {
        wk_cpu_source src = {.rep = &v->core.rep};
        st = render_all(v, &src, v->core.table, 0);
    }
    v->core.mesh_set = st == LM_OK;
    return st;
}

/* Re-render the replica from scratch (after a material change). */
static lm_status rerender_replica(wk_cpu_views *v)
{
    wk_cpu_source src = {.rep = &v->core.rep};
    lm_status st = render_all(v, &src, v->core.table, 0);
    v->core.mesh_set = st == LM_OK;
    return st;
}

static const char *cv_renderer(const wk_views_core *c)
{
    (void)c;
    return WK_CPU_RENDERER;
}

/* The backend's own parts (views_seam.c frees the core's). */
static void cv_destroy(wk_views_core *c)
{
    wk_cpu_views *v = (wk_cpu_views *)c;
    free(v->count);
    wk_cpu_materials_free(&v->mats[0]);
    wk_cpu_materials_free(&v->mats[1]);
    wk_cpu_eval_free(&v->eval, v->core.views.count);
    wk_cpu_subcache_free(&v->subcache);
    free(v->vc);
    free(v->keys);
    free(v->tmax);
    free(v->second);
    free(v->texf);
    free(v->rgba);
}

static lm_status cv_set_materials(wk_views_core *c, const lm_material *mats, uint32_t n);
static lm_status cv_set_occlusion(wk_views_core *c, int on);
static lm_status cv_read_rgba(wk_views_core *c, uint32_t view, uint8_t *out);
static lm_status cv_read_coverage(wk_views_core *c, uint32_t view, uint8_t *out);
static lm_status cv_read_triangles(wk_views_core *c, uint32_t view, uint32_t *out);

static const wk_views_backend cv_backend = {
    .set_mesh = cv_set_mesh,
    .set_materials = cv_set_materials,
    .commit = wk_cpu_commit,
    .evaluate = wk_cpu_evaluate,
    .read_rgba = cv_read_rgba,
    .read_coverage = cv_read_coverage,
    .read_triangles = cv_read_triangles,
    .renderer = cv_renderer,
    .set_occlusion = cv_set_occlusion,
    .destroy = cv_destroy,
};

/* A large per-view table: asked for on huge pages where the system has them (evaluations touch
 * all views' tables in turn; with 4 KiB pages their address translations thrash). Free with
 * free(). */
static void *big_alloc(size_t bytes)
{
    void *p = NULL;
    const size_t huge = (size_t)2 << 20;
    if (bytes < huge || posix_memalign(&p, huge, (bytes + huge - 1) / huge * huge) != 0)
        return malloc(bytes);
#ifdef MADV_HUGEPAGE
    madvise(p, (bytes + huge - 1) / huge * huge, MADV_HUGEPAGE); /* a hint: failure is harmless */
#endif
    return p;
}

/* The per-pixel texture factors (for twins that keep their texture), made once a textured
 * material is in use. */
static lm_status need_texture_factors(wk_cpu_views *v, const wk_cpu_materials *m)
{
    int textured = 0;
    for (uint32_t i = 0; i < m->n; i++)
        textured |= m->tex[i] != NULL;
    if (!textured || v->texf)
        return LM_OK;
    v->texf = big_alloc(v->core.views.count * v->plane * 3 * sizeof *v->texf);
    return v->texf ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for texture factors");
}

/* ---- creation ---------------------------------------------------------------------------- */

static lm_status check_input(const lm_mesh *original, const lm_view_set *views, uint32_t first,
                             uint32_t count)
{
    if (views->count < 1 || views->count > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "view count %u is outside 1..%d", views->count, LM_MAX_VIEWS);
    if (first >= views->count || count < 1 || count > views->count - first)
        return lm_fail(LM_E_RANGE, "views %u..%u are not among the %u views", first,
                       first + count - 1, views->count);
    for (uint32_t h = 0; h < views->count; h++)
        if (views->views[h].width != views->views[0].width ||
            views->views[h].height != views->views[0].height)
            return lm_fail(LM_E_INVALID, "view %u differs in size from view 0", h);
    int w = views->views[0].width, hgt = views->views[0].height;
    if (w < 1 || hgt < 1 || w > LM_MAX_VIEW_SIZE || hgt > LM_MAX_VIEW_SIZE)
        return lm_fail(LM_E_RANGE, "view size %dx%d is out of range", w, hgt);
    for (uint32_t t = 0; t < original->n_tris; t++)
        if (original->tri_alive[t] && original->tris[t].material >= original->n_materials)
            return lm_fail(LM_E_RANGE, "original triangle %u uses material %u of %u", t,
                           original->tris[t].material, original->n_materials);
    return LM_OK;
}

static lm_status create_parts(wk_cpu_views *v, const lm_mesh *original)
{
    size_t n = v->core.views.count;
    v->keys = big_alloc(n * v->plane * sizeof *v->keys);
    v->tmax = malloc(n * v->tiles * sizeof *v->tmax);
    v->second = big_alloc(n * v->plane * sizeof *v->second);
    v->rgba = malloc(n * v->plane * 4);
    if (!v->keys || !v->tmax || !v->second || !v->rgba)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu views of %dx%d", n, v->core.width,
                       v->core.height);
    lm_status st = wk_views_core_create_parts(&v->core);
    if (st == LM_OK)
        st = wk_cpu_materials_set(&v->mats[0], original->materials, original->n_materials);
    if (st == LM_OK)
        st = need_texture_factors(v, &v->mats[0]);
    if (st == LM_OK)
        st = wk_cpu_eval_init(v);
    return st;
}

lm_status wk_cpu_views_create(const lm_mesh *original, const lm_view_set *views, uint32_t first,
                              uint32_t count, const uint8_t *targets, lm_views **out)
{
    if (!count && first < views->count)
        count = views->count - first;
    lm_status st = check_input(original, views, first, count);
    if (st != LM_OK)
        return st;
    wk_cpu_views *v = calloc(1, sizeof *v);
    if (!v)
        return lm_fail(LM_E_NOMEM, "out of memory creating the views");
    wk_views_core_init(&v->core, views->views + first, count);
    wk_views_seam_attach(&v->core, &cv_backend);
    for (uint32_t h = 0; h < count; h++)
        wk_cpu_view_init(&v->core.views.views[h], &v->cviews[h]);
    v->tiles_w = (v->core.width + WK_CPU_TILE - 1) / WK_CPU_TILE;
    v->tiles_h = (v->core.height + WK_CPU_TILE - 1) / WK_CPU_TILE;
    v->plane = (size_t)v->core.width * v->core.height;
    v->tiles = (size_t)v->tiles_w * v->tiles_h;
    v->core.occlusion = 1;
    wk_cpu_subcache_init(&v->subcache, count);
    st = create_parts(v, original);
    for (uint32_t h = 0; st == LM_OK && targets && h < count; h++)
        wk_image_store_set_target(v->core.img, h, targets + h * v->plane);
    if (st == LM_OK && !targets) {
        wk_cpu_source src = {.mesh = original};
        st = render_all(v, &src, 0, 1);
    }
    return wk_views_seam_created(&v->core, st, out);
}

/* ---- extras ------------------------------------------------------------------------------ */

static lm_status cv_set_materials(wk_views_core *c, const lm_material *mats, uint32_t n)
{
    wk_cpu_views *v = (wk_cpu_views *)c;
    lm_status st = wk_cpu_materials_set(&v->mats[1], mats, n);
    if (st == LM_OK)
        st = need_texture_factors(v, &v->mats[1]);
    if (st != LM_OK)
        return st;
    v->core.table = 1;
    if (!v->core.mesh_set)
        return LM_OK;
    for (size_t id = 0; id < v->core.rep.cap; id++)
        if (v->core.rep.alive[id] && v->core.rep.tris[id].material >= n) {
            v->core.mesh_set = 0;
            return lm_fail(LM_E_RANGE, "triangle %zu uses material %u of %u", id,
                           v->core.rep.tris[id].material, n);
        }
    return rerender_replica(v);
}

static lm_status cv_set_occlusion(wk_views_core *c, int on)
{
    c->occlusion = on != 0;
    return LM_OK;
}

static lm_status cv_read_rgba(wk_views_core *c, uint32_t view, uint8_t *out)
{
    wk_cpu_views *v = (wk_cpu_views *)c;
    memcpy(out, v->rgba + view * v->plane * 4, v->plane * 4);
    return LM_OK;
}

static lm_status cv_read_coverage(wk_views_core *c, uint32_t view, uint8_t *out)
{
    wk_cpu_views *v = (wk_cpu_views *)c;
    const uint64_t *key = v->keys + view * v->plane;
    for (size_t i = 0; i < v->plane; i++)
        out[i] = key[i] != WK_CPU_KEY_BG;
    return LM_OK;
}

static lm_status cv_read_triangles(wk_views_core *c, uint32_t view, uint32_t *out)
{
    wk_cpu_views *v = (wk_cpu_views *)c;
    const uint64_t *key = v->keys + view * v->plane;
    for (size_t i = 0; i < v->plane; i++)
        out[i] = key[i] == WK_CPU_KEY_BG ? LM_NONE : WK_CPU_KEY_ID(key[i]);
    return LM_OK;
}
