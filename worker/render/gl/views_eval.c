/* worker/render/gl/views_eval.c — incremental ΔE (paper §4.2–4.3) for the in-process views: for
 * each patch and view, the region R_h around the removed and added triangles, the bucket query for
 * every triangle touching it, a scissored clear and redraw of (T_R \ T) ∪ T' in ascending id order
 * into a scratch atlas, and after all draws of a batch one readback sync and the exact int64 sums.
 * Evaluations neither write nor read the scratch depth images. Commit reuses the pixels of an
 * evaluated patch without occlusion; with it, commit re-renders the patch writing the depth images
 * and reads them. Then it updates images, replica and buckets. */
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "worker/render/gl/gl_views_internal.h"

/* Change this far behind the visible surface is certainly hidden (window depth units; a 24-bit
 * depth step is 6e-8). */
#define WK_HIDDEN_EPS 1e-5f

/* ---- patch checks and the per-patch id marks ---------------------------------------------- */

/* The whole-footprint hidden memo for ids below need (forgotten when it grows). */
static lm_status hidden_reserve(wk_views_local *v, size_t need)
{
    if (need <= v->cap_hidden)
        return LM_OK;
    size_t cap = lm_grow_cap(v->cap_hidden, need, 1024, SIZE_MAX);
    wk_hidden_memo *m = calloc((size_t)v->core.views.count * cap, sizeof *m);
    if (!m)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu hidden-test memos", cap);
    free(v->hidden);
    v->hidden = m;
    v->cap_hidden = cap;
    return LM_OK;
}

/* The whole-footprint hidden test of alive triangle id (footprint f) in view h, remembered until
 * the view's depth image or the triangle changes. */
static const wk_hidden_memo *hidden_whole(wk_views_local *v, uint32_t h, uint32_t id,
                                          const wk_footprint *f)
{
    wk_hidden_memo *m = &v->hidden[(size_t)h * v->cap_hidden + id];
    uint32_t version = wk_image_store_depth_version(v->core.img, h);
    if (!m->known || m->version != version) {
        int w[2];
        m->hidden = (uint8_t)wk_image_store_hidden_tri_witness(v->core.img, h, f, &f->rect,
                                                               WK_HIDDEN_EPS, w);
        m->witness[0] = (int16_t)w[0];
        m->witness[1] = (int16_t)w[1];
        m->version = version;
        m->known = 1;
    }
    return m;
}

static void hidden_forget(wk_views_local *v, uint32_t id)
{
    if (id < v->cap_hidden)
        for (uint32_t h = 0; h < v->core.views.count; h++)
            v->hidden[(size_t)h * v->cap_hidden + id].known = 0;
}

static void sort_added(lm_tri_data *a, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        lm_tri_data x = a[i];
        size_t j = i;
        while (j > 0 && a[j - 1].id > x.id) {
            a[j] = a[j - 1];
            j--;
        }
        a[j] = x;
    }
}

/* v->cover_patch for patch p (whose removed ids are alive). */
static lm_status check_boundary(wk_views_local *v, const lm_patch *p)
{
    if (p->n_removed > v->cap_removed_tris) {
        const lm_tri_data **a = realloc(v->removed_tris, p->n_removed * sizeof *a);
        if (!a)
            return lm_fail(LM_E_NOMEM, "out of memory for a patch of %u triangles", p->n_removed);
        v->removed_tris = a;
        v->cap_removed_tris = p->n_removed;
    }
    for (uint32_t i = 0; i < p->n_removed; i++)
        v->removed_tris[i] = &v->core.rep.tris[p->removed[i]];
    return wk_cover_patch_prepare(&v->cover_patch, v->removed_tris, p->n_removed, p->added,
                                  p->n_added);
}

/* Validates p against the replica (patch_prepare.h), marks its removed and added ids and leaves
 * its added records sorted by id in v->sorted_added. */
static lm_status prepare_patch(wk_views_local *v, const lm_patch *p)
{
    uint32_t n_mat = wk_renderer_material_count(v->r, v->core.table);
    lm_status st = wk_patch_prepare(&v->marks, &v->core.rep, n_mat, p);
    if (st == LM_OK && v->core.occlusion)
        st = hidden_reserve(v, v->marks.cap);
    if (st != LM_OK)
        return st;
    if (p->n_added > v->cap_sorted) {
        lm_tri_data *s = realloc(v->sorted_added, p->n_added * sizeof *s);
        if (!s)
            return lm_fail(LM_E_NOMEM, "out of memory for a patch of %u triangles", p->n_added);
        v->sorted_added = s;
        v->cap_sorted = p->n_added;
    }
    memcpy(v->sorted_added, p->added, p->n_added * sizeof *p->added);
    sort_added(v->sorted_added, p->n_added);
    return v->core.occlusion ? check_boundary(v, p) : LM_OK;
}

/* ---- jobs ------------------------------------------------------------------------------- */

static lm_status push_job(wk_views_local *v, const wk_job *j)
{
    if (v->n_jobs == v->cap_jobs) {
        size_t cap = v->cap_jobs ? v->cap_jobs * 2 : 64;
        wk_job *a = realloc(v->jobs, cap * sizeof *a);
        if (!a)
            return lm_fail(LM_E_NOMEM, "out of memory for %zu render jobs", cap);
        v->jobs = a;
        v->cap_jobs = cap;
    }
    v->jobs[v->n_jobs++] = *j;
    return LM_OK;
}

static void sort_ids(uint32_t *a, size_t n)
{
    for (size_t i = 1; i < n; i++) {
        uint32_t x = a[i];
        size_t j = i;
        while (j > 0 && a[j - 1] > x) {
            a[j] = a[j - 1];
            j--;
        }
        a[j] = x;
    }
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Whether rectangle a lies in b (an empty a always does). */
static int rect_within(const wk_rect *a, const wk_rect *b)
{
    return wk_rect_empty(a) ||
           (a->x0 >= b->x0 && a->y0 >= b->y0 && a->x1 <= b->x1 && a->y1 <= b->y1);
}

/* The region of patch p in view h: the rectangles of the removed and added triangles that may show.
 * With occlusion on, a removed triangle certainly hidden behind the visible surface is left out
 * (its removal changes no pixel), and so is an added one that is certainly hidden where no visible
 * removed triangle could have made that surface. An empty region: the view does not change. */
static lm_status patch_region(wk_views_local *v, const lm_patch *p, uint32_t h, wk_rect *r,
                              uint32_t *n_visible)
{
    *r = (wk_rect){0, 0, 0, 0};
    if (v->core.occlusion && p->n_removed > v->cap_visible) {
        wk_rect *a = realloc(v->visible, p->n_removed * sizeof *a);
        if (!a)
            return lm_fail(LM_E_NOMEM, "out of memory for %u rectangles", p->n_removed);
        v->visible = a;
        v->cap_visible = p->n_removed;
    }
    uint32_t n_vis = 0;
    lm_status st = v->core.occlusion ? wk_cover_begin(&v->cover, &v->cover_patch,
                                                      (size_t)p->n_removed + p->n_added,
                                                      v->core.width, v->core.height)
                                     : LM_OK;
    if (st != LM_OK)
        return st;
    for (uint32_t i = 0; i < p->n_removed; i++) {
        const wk_footprint *f = wk_buckets_footprint(v->core.buckets[h], p->removed[i]);
        if (v->core.occlusion) {
            if (!v->cover_patch.twin[i])
                wk_cover_feed(&v->cover, f, 0);
            if (hidden_whole(v, h, p->removed[i], f)->hidden)
                continue;
            v->visible[n_vis++] = f->rect;
        }
        wk_rect_union(r, &f->rect);
    }
    for (uint32_t i = 0; i < p->n_added; i++) {
        wk_footprint f;
        wk_tri_footprint(&v->core.views.views[h], &p->added[i], &f);
        if (v->core.occlusion && !v->cover_patch.twin[p->n_removed + i])
            wk_cover_feed(&v->cover, &f, 1);
        if (rect_within(&f.rect, r))
            continue; /* the region holds it whether it shows or not */
        if (v->core.occlusion && wk_image_store_hidden_tri(v->core.img, h, &f, WK_HIDDEN_EPS)) {
            uint32_t k = 0;
            while (k < n_vis && !wk_rects_meet(&v->visible[k], &f.rect))
                k++;
            if (k == n_vis)
                continue;
        }
        wk_rect_union(r, &f.rect);
    }
    *n_visible = n_vis;
    return LM_OK;
}

/* Whether kept triangle id can be left out of the redraw of region r in view h: it is certainly
 * hidden in r behind the current surface, and where that surface changes the new one stays in
 * front of it: either no visible removed triangle (the first n_vis of v->visible) meets it, or
 * the added triangles cover the removed ones' pixels nearer than it (v->cover). Where the surface
 * is kept it is redrawn unchanged. Its fragments are then deeper than the redrawn ones at every
 * pixel of r, so it changes no pixel. */
static int occluded_in_region(wk_views_local *v, uint32_t h, uint32_t id, const wk_rect *r,
                              uint32_t n_vis)
{
    const wk_footprint *f = wk_buckets_footprint(v->core.buckets[h], id);
    const wk_hidden_memo *m = hidden_whole(v, h, id, f);
    const int16_t *w = m->witness;
    if (!m->hidden && w[0] >= r->x0 && w[0] < r->x1 && w[1] >= r->y0 && w[1] < r->y1)
        return 0; /* a pixel of it in r shows it now */
    uint32_t k = 0;
    while (k < n_vis && !wk_rects_meet(&v->visible[k], &f->rect))
        k++;
    if (k < n_vis) {
        wk_rect in = wk_rect_intersect(&f->rect, r);
        if (!wk_cover_front_of(&v->cover, &in, f->zmin - WK_HIDDEN_EPS))
            return 0;
    }
    return m->hidden || wk_image_store_hidden_tri_in(v->core.img, h, f, r, WK_HIDDEN_EPS);
}

/* Stream (T_R \ T) ∪ T' for view h in ascending id order; T' = v->sorted_added (n_added); with
 * occlusion on, kept triangles certainly hidden in the region are left out. */
static lm_status stream_region(wk_views_local *v, uint32_t h, const wk_rect *r, uint32_t n_added,
                               uint32_t n_vis, size_t *count)
{
    v->cand.n = 0;
    lm_status st = wk_buckets_query(v->core.buckets[h], r, &v->cand);
    if (st != LM_OK)
        return st;
    size_t k = 0;
    for (size_t i = 0; i < v->cand.n; i++)
        if (!wk_patch_removes(&v->marks, v->cand.ids[i]) &&
            !(v->core.occlusion && occluded_in_region(v, h, v->cand.ids[i], r, n_vis)))
            v->cand.ids[k++] = v->cand.ids[i];
    if (k <= 64)
        sort_ids(v->cand.ids, k);
    else
        qsort(v->cand.ids, k, sizeof *v->cand.ids, cmp_u32);
    if ((st = wk_vl_stream_reserve(v, v->stream_n + k + n_added)) != LM_OK)
        return st;
    size_t a = 0, b = 0;
    while (a < k || b < n_added) {
        if (b >= n_added || (a < k && v->cand.ids[a] < v->sorted_added[b].id))
            wk_vl_stream_push(v, &v->core.rep.tris[v->cand.ids[a++]]);
        else
            wk_vl_stream_push(v, &v->sorted_added[b++]);
    }
    *count = k + n_added;
    return LM_OK;
}

/* Jobs of one patch (index pi of the batch) for every view its region touches. */
static lm_status plan_patch(wk_views_local *v, const lm_patch *p, uint32_t pi)
{
    lm_status st = prepare_patch(v, p);
    for (uint32_t h = 0; st == LM_OK && h < v->core.views.count; h++) {
        wk_job j = {.patch = pi, .view = h, .first = v->stream_n, .luma = v->n_luma};
        uint32_t n_vis = 0;
        st = patch_region(v, p, h, &j.rect, &n_vis);
        if (st == LM_OK && wk_rect_empty(&j.rect)) {
            v->core.stats.views_skipped++;
            continue;
        }
        if (st != LM_OK)
            break;
        st = stream_region(v, h, &j.rect, p->n_added, n_vis, &j.count);
        if (st == LM_OK)
            st = push_job(v, &j);
        v->n_luma += (size_t)(j.rect.x1 - j.rect.x0) * (j.rect.y1 - j.rect.y0);
    }
    return st;
}

static lm_status reserve_bytes(uint8_t **buf, size_t *cap, size_t need)
{
    if (need <= *cap)
        return LM_OK;
    size_t c = lm_grow_cap(*cap, need, 65536, SIZE_MAX);
    uint8_t *b = realloc(*buf, c);
    if (!b)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu bytes of pixels", c);
    *buf = b;
    *cap = c;
    return LM_OK;
}

/* Clear and draw the regions of jobs [a, b) of one patch in its scratch atlas (patch i of the
 * batch uses atlas 1 + i - p0): one quad draw for the clears, then the regions. Patches go one
 * after the other because binding another framebuffer makes Mesa rasterise what was drawn so
 * far (llvmpipe flushes its scene): one atlas switch per patch instead of two. */
static lm_status draw_patch_jobs(wk_views_local *v, size_t a, size_t b, uint32_t p0)
{
    uint32_t atlas = 1 + v->jobs[a].patch - p0;
    lm_status st = wk_renderer_write_depth_images(v->r, atlas, v->scratch_depth);
    v->n_regions = 0;
    for (size_t j = a; j < b; j++) {
        v->region_views[v->n_regions] = v->jobs[j].view;
        v->region_rects[v->n_regions++] = v->jobs[j].rect;
    }
    if (st == LM_OK)
        st = wk_renderer_clear_regions(v->r, atlas, v->region_views, v->region_rects, v->n_regions);
    for (size_t j = a; st == LM_OK && j < b; j++) {
        const wk_job *job = &v->jobs[j];
        wk_draw d = {atlas, job->view, job->first, job->count, job->rect};
        st = wk_renderer_draw(v->r, v->core.table, &d, v->stream_mat);
    }
    return st;
}

/* Draw jobs [j0, j1): per patch, clear its regions and draw them; then read them all back (one
 * sync). */
static lm_status run_jobs(wk_views_local *v, size_t j0, size_t j1, uint32_t p0)
{
    lm_status st = wk_renderer_upload(v->r, v->stream, v->stream_n);
    for (size_t a = j0; st == LM_OK && a < j1;) {
        size_t b = a;
        while (b < j1 && v->jobs[b].patch == v->jobs[a].patch)
            b++;
        st = draw_patch_jobs(v, a, b, p0);
        a = b;
    }
    if (st == LM_OK)
        st = reserve_bytes(&v->luma, &v->cap_luma, v->n_luma);
    for (size_t j = j0; st == LM_OK && j < j1; j++) {
        const wk_job *job = &v->jobs[j];
        size_t area = (size_t)(job->rect.x1 - job->rect.x0) * (job->rect.y1 - job->rect.y0);
        st = reserve_bytes(&v->rgba, &v->cap_rgba, area * 4);
        if (st == LM_OK)
            st = wk_renderer_read(v->r, 1 + job->patch - p0, job->view, &job->rect, v->rgba);
        if (st == LM_OK)
            wk_luma_from_rgba(v->rgba, area, v->luma + job->luma);
    }
    v->core.stats.batches++;
    v->core.stats.tris_drawn += v->stream_n;
    v->core.stats.regions += j1 - j0;
    v->core.stats.region_pixels += v->n_luma - v->jobs[j0].luma;
    return st == LM_OK ? wk_renderer_check(v->r, "rendering patch regions") : st;
}

/* ---- the patch cache -------------------------------------------------------------------- */

void wk_vl_forget_cache(wk_views_local *v)
{
    v->n_cached = 0;
    v->n_jobs = 0;
    v->n_luma = 0;
}

void wk_vl_free_eval(wk_views_local *v)
{
    for (uint32_t i = 0; i < v->cap_cached; i++)
        lm_patch_free(&v->cached[i]);
    free(v->cached);
    free(v->jobs);
    free(v->luma);
    free(v->zreg);
    free(v->rgba);
    free(v->cand.ids);
    wk_patch_marks_free(&v->marks);
    free(v->sorted_added);
    free(v->visible);
    free(v->removed_tris);
    free(v->hidden);
    wk_cover_patch_free(&v->cover_patch);
    wk_cover_free(&v->cover);
}

static lm_status cache_patch(wk_views_local *v, const lm_patch *p)
{
    if (v->n_cached == v->cap_cached) {
        uint32_t cap = v->cap_cached ? v->cap_cached * 2 : 8;
        lm_patch *c = realloc(v->cached, cap * sizeof *c);
        if (!c)
            return lm_fail(LM_E_NOMEM, "out of memory caching patches");
        for (uint32_t i = v->cap_cached; i < cap; i++)
            lm_patch_init(&c[i]);
        v->cached = c;
        v->cap_cached = cap;
    }
    lm_patch *c = &v->cached[v->n_cached];
    lm_patch_reset(c);
    lm_status st = LM_OK;
    for (uint32_t i = 0; st == LM_OK && i < p->n_removed; i++)
        st = lm_patch_remove(c, p->removed[i]);
    for (uint32_t i = 0; st == LM_OK && i < p->n_added; i++)
        st = lm_patch_add(c, &p->added[i]);
    if (st == LM_OK)
        v->n_cached++;
    return st;
}

static int patch_equal(const lm_patch *a, const lm_patch *b)
{
    return a->n_removed == b->n_removed && a->n_added == b->n_added &&
           (a->n_removed == 0 ||
            !memcmp(a->removed, b->removed, a->n_removed * sizeof(uint32_t))) &&
           (a->n_added == 0 || !memcmp(a->added, b->added, a->n_added * sizeof(lm_tri_data)));
}

/* ---- evaluate and commit ---------------------------------------------------------------- */

static lm_status evaluate_batch(wk_views_local *v, const lm_patch *patches, uint32_t n,
                                int64_t *delta)
{
    wk_vl_forget_cache(v);
    lm_status st = LM_OK;
    for (uint32_t p0 = 0; st == LM_OK && p0 < n; p0 += WK_SCRATCH_ATLASES) {
        uint32_t p1 = p0 + WK_SCRATCH_ATLASES < n ? p0 + WK_SCRATCH_ATLASES : n;
        size_t j0 = v->n_jobs;
        v->stream_n = 0;
        for (uint32_t i = p0; st == LM_OK && i < p1; i++)
            st = plan_patch(v, &patches[i], i);
        if (st == LM_OK)
            st = run_jobs(v, j0, v->n_jobs, p0);
        for (size_t j = j0; st == LM_OK && j < v->n_jobs; j++) {
            const wk_job *job = &v->jobs[j];
            delta[job->patch] += wk_image_store_region_delta(v->core.img, job->view, &job->rect,
                                                             v->luma + job->luma);
        }
    }
    for (uint32_t i = 0; st == LM_OK && i < n; i++)
        st = cache_patch(v, &patches[i]);
    if (st != LM_OK)
        wk_vl_forget_cache(v);
    v->core.stats.evaluations += n;
    return st;
}

lm_status wk_vl_evaluate(wk_views_core *c, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    wk_views_local *v = (wk_views_local *)c;
    lm_status st = wk_vl_make_current(v);
    return st == LM_OK ? evaluate_batch(v, patches, n, delta) : st;
}

/* What the views keep of triangle id: its hidden-test memos. */
static void forget_tri(wk_views_core *c, uint32_t id)
{
    hidden_forget((wk_views_local *)c, id);
}

/* The first patch of the batch's last group: only the regions of patches from there on are still
 * in the scratch atlases (the last group drew over the earlier ones). */
static uint32_t last_p0(const wk_views_local *v)
{
    return v->n_cached ? (v->n_cached - 1) / WK_SCRATCH_ATLASES * WK_SCRATCH_ATLASES : 0;
}

/* Depth images of patch k's regions, read from its scratch atlas at commit time only: evaluations
 * far outnumber commits, so evaluate neither writes nor reads them (a fragment writing one render
 * target less saves ≈ 4% of an evaluation) and commit re-renders the patch with them. */
static lm_status read_depths(wk_views_local *v, uint32_t k)
{
    uint32_t p0 = last_p0(v);
    lm_status st = reserve_bytes((uint8_t **)&v->zreg, &v->cap_zreg, v->n_luma * sizeof(float));
    for (size_t j = 0; st == LM_OK && j < v->n_jobs; j++)
        if (v->jobs[j].patch == k)
            st = wk_renderer_read_depth(v->r, 1 + k - p0, v->jobs[j].view, &v->jobs[j].rect,
                                        v->zreg + v->jobs[j].luma);
    return st == LM_OK ? wk_renderer_check(v->r, "reading patch depth images") : st;
}

lm_status wk_vl_commit(wk_views_core *c, const lm_patch *patch)
{
    wk_views_local *v = (wk_views_local *)c;
    lm_status st = wk_vl_make_current(v);
    if (st != LM_OK)
        return st;
    uint32_t k = 0;
    while (k < v->n_cached && !patch_equal(&v->cached[k], patch))
        k++;
    if (k < v->n_cached && !v->core.occlusion) {
        v->core.stats.commits_cached++;
    } else {
        int64_t unused = 0;
        v->scratch_depth = v->core.occlusion;
        st = evaluate_batch(v, patch, 1, &unused);
        v->scratch_depth = 0;
        if (st != LM_OK)
            return st;
        v->core.stats.evaluations--; /* a commit's render is not an evaluation */
        k = 0;
    }
    if (v->core.occlusion && (st = read_depths(v, k)) != LM_OK)
        return st;
    for (size_t j = 0; j < v->n_jobs; j++) {
        const wk_job *job = &v->jobs[j];
        if (job->patch != k)
            continue;
        wk_image_store_commit_region(v->core.img, job->view, &job->rect, v->luma + job->luma);
        if (v->core.occlusion)
            wk_image_store_commit_depth(v->core.img, job->view, &job->rect, v->zreg + job->luma);
    }
    wk_vl_forget_cache(v);
    st = wk_views_core_apply(c, patch, forget_tri); /* replica and buckets follow the patch */
    if (st != LM_OK) {
        v->core.mesh_set = 0; /* half-applied: refuse further work until set_mesh */
        v->core.buckets_ready = 0;
    }
    return st;
}
