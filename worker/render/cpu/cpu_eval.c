/* worker/render/cpu/cpu_eval.c — incremental ΔE on the CPU rasteriser: a patch is applied to each
 * view's keys in place, the changed pixels logged, shaded and summed into ΔE, then rolled back
 * (evaluate) or kept (commit). Per view:
 *
 *   A. holes: the pixels where a removed triangle is the visible surface (found by rasterising it
 *      and comparing keys; none when its visible-pixel count is 0) become background; the old key
 *      there is a lower bound of every kept triangle's key (it beat them all). A removed triangle
 *      re-added with the same id and bit-identical corners (a "twin": only its attributes change)
 *      keeps its keys; its pixels are only marked for shading. An evaluation that removes the same
 *      triangles (and twins) from the same keys as the view's last one replays that step's log
 *      instead (cpu_holes.h: a simplex evaluates one neighbourhood many times in a row).
 *   B. the added triangles (twins aside) are drawn by min-update, skipping 8x8 tiles whose
 *      depth maximum lies in front of them.
 *   C. a hole whose new key is not below its bound may show a kept triangle: those triangles come
 *      from the buckets (a query over the unresolved pixels' box, drawn only in tiles holding such
 *      pixels). Elsewhere no kept triangle can win: each loses to the old surface already.
 *   D. every logged pixel is shaded with its new visible triangle; ΔE is the exact int64 sum of
 *      (Ŷ - Y')² - (Ŷ - Y)² over them.
 *
 * Every step is a min over keys, so the result equals a full render pixel for pixel. */
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "worker/render/cpu/cpu_views_internal.h"

enum { F_HOLE = 1, F_RESHADE = 2, F_NEW = 3 };

/* ---- scratch ------------------------------------------------------------------------------ */

lm_status wk_cpu_eval_init(wk_cpu_views *v)
{
    wk_cpu_eval *e = &v->eval;
    e->log.stamp = calloc(v->plane, sizeof *e->log.stamp);
    e->log.idx = malloc(v->plane * sizeof *e->log.idx);
    e->log.xy = malloc(v->plane * sizeof *e->log.xy);
    e->log.old = malloc(v->plane * sizeof *e->log.old);
    e->log.flag = malloc(v->plane);
    e->owned = malloc(v->plane * sizeof *e->owned);
    e->luma = malloc(v->plane);
    e->rgb = malloc(v->plane * 3);
    e->texl = malloc(v->plane * 3 * sizeof *e->texl);
    e->tile_old = malloc(v->tiles * sizeof *e->tile_old);
    e->tile_idx = malloc(v->tiles * sizeof *e->tile_idx);
    e->tile_stamp = calloc(v->tiles, sizeof *e->tile_stamp);
    e->tile_mask = calloc(v->tiles, 1);
    e->mask_idx = malloc(v->tiles * sizeof *e->mask_idx);
    e->cmax = malloc(v->tiles * sizeof *e->cmax);
    e->holes = calloc(v->core.views.count, sizeof *e->holes);
    if (!e->log.stamp || !e->log.idx || !e->log.xy || !e->log.old || !e->log.flag || !e->owned ||
        !e->luma || !e->rgb || !e->texl || !e->tile_old || !e->tile_idx || !e->tile_stamp ||
        !e->tile_mask || !e->mask_idx || !e->cmax || !e->holes)
        return lm_fail(LM_E_NOMEM, "out of memory for the evaluation scratch of %zu pixels",
                       v->plane);
    return LM_OK;
}

void wk_cpu_eval_free(wk_cpu_eval *e, uint32_t n_views)
{
    for (uint32_t h = 0; e->holes && h < n_views; h++)
        wk_cpu_holes_free(&e->holes[h]);
    free(e->holes);
    free(e->removed_twin);
    wk_patch_marks_free(&e->marks);
    void *p[] = {e->log.stamp,  e->log.idx,       e->log.xy,   e->log.old,   e->log.flag,
                 e->owned,      e->luma,          e->rgb,      e->tile_old,  e->tile_idx,
                 e->tile_stamp, e->tile_mask,     e->mask_idx, e->cmax,      e->twin_stamp,
                 e->twin_of,    e->textwin_stamp, e->texl,     e->loc_stamp, e->loc_first,
                 e->loc_n,      e->cand.ids};
    for (size_t i = 0; i < sizeof p / sizeof *p; i++)
        free(p[i]);
    wk_cpu_setups_free(&e->set);
    memset(e, 0, sizeof *e);
}

static lm_status grow_ids(void **a, size_t elem, size_t old, size_t cap)
{
    uint8_t *b = realloc(*a, cap * elem);
    if (!b)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu per-triangle entries", cap);
    memset(b + old * elem, 0, (cap - old) * elem);
    *a = b;
    return LM_OK;
}

static lm_status ids_reserve(wk_cpu_eval *e, size_t need)
{
    if (need <= e->cap_ids)
        return LM_OK;
    size_t cap = lm_grow_cap(e->cap_ids, need, 1024, SIZE_MAX), old = e->cap_ids;
    void **u32[] = {(void **)&e->twin_stamp, (void **)&e->textwin_stamp, (void **)&e->twin_of,
                    (void **)&e->loc_stamp, (void **)&e->loc_first};
    for (size_t i = 0; i < sizeof u32 / sizeof *u32; i++)
        if (grow_ids(u32[i], sizeof(uint32_t), old, cap) != LM_OK)
            return LM_E_NOMEM;
    if (grow_ids((void **)&e->loc_n, 1, old, cap) != LM_OK)
        return LM_E_NOMEM;
    e->cap_ids = cap;
    return LM_OK;
}

/* ---- the patch ---------------------------------------------------------------------------- */

static int same_corners(const lm_tri_data *a, const lm_tri_data *b)
{
    for (int k = 0; k < 3; k++)
        if (memcmp(a->c[k].pos, b->c[k].pos, sizeof a->c[k].pos))
            return 0;
    return 1;
}

/* Whether a twin's texture factors stay: the same material and texture coordinates. */
static int same_texturing(const lm_tri_data *a, const lm_tri_data *b)
{
    if (a->material != b->material)
        return 0;
    for (int k = 0; k < 3; k++)
        if (memcmp(a->c[k].uv, b->c[k].uv, sizeof a->c[k].uv))
            return 0;
    return 1;
}

/* Validates p against the replica (patch_prepare.h), marks its removed and added ids and finds
 * the twins. */
static lm_status prepare_patch(wk_cpu_views *v, const lm_patch *p)
{
    wk_cpu_eval *e = &v->eval;
    lm_status st = wk_patch_prepare(&e->marks, &v->core.rep, v->mats[v->core.table].n, p);
    if (st == LM_OK)
        st = ids_reserve(e, e->marks.cap);
    if (st != LM_OK)
        return st;
    uint32_t now = e->marks.now;
    if (now == 1) { /* the marks' stamps (re)started: so do the twins' */
        memset(e->twin_stamp, 0, e->cap_ids * sizeof *e->twin_stamp);
        memset(e->textwin_stamp, 0, e->cap_ids * sizeof *e->textwin_stamp);
    }
    wk_cpu_box_clear(&e->box);
    for (uint32_t i = 0; i < p->n_added; i++) {
        uint32_t id = p->added[i].id;
        if (v->core.occlusion && wk_patch_removes(&e->marks, id) &&
            same_corners(&p->added[i], &v->core.rep.tris[id])) {
            e->twin_stamp[id] = now;
            e->twin_of[id] = i;
            if (same_texturing(&p->added[i], &v->core.rep.tris[id]))
                e->textwin_stamp[id] = now;
        } else {
            wk_cpu_box_add(&e->box, &p->added[i]);
        }
    }
    if (p->n_removed > e->cap_removed) {
        uint8_t *t = realloc(e->removed_twin, p->n_removed);
        if (!t)
            return lm_fail(LM_E_NOMEM, "out of memory for a patch of %u triangles", p->n_removed);
        e->removed_twin = t;
        e->cap_removed = p->n_removed;
    }
    for (uint32_t i = 0; i < p->n_removed; i++)
        e->removed_twin[i] = e->twin_stamp[p->removed[i]] == now;
    return LM_OK;
}

static int is_twin(const wk_cpu_eval *e, uint32_t id)
{
    return e->twin_stamp[id] == e->marks.now;
}

/* ---- one (patch, view) pass --------------------------------------------------------------- */

static void pass_begin(wk_cpu_views *v)
{
    wk_cpu_eval *e = &v->eval;
    if (++e->log.now == 0) {
        memset(e->log.stamp, 0, v->plane * sizeof *e->log.stamp);
        memset(e->tile_stamp, 0, v->tiles * sizeof *e->tile_stamp);
        memset(e->loc_stamp, 0, e->cap_ids * sizeof *e->loc_stamp);
        e->log.now = 1;
    }
    e->log.n = 0;
    wk_cpu_setups_reset(&e->set);
    e->n_raised = 0;
}

/* The subs of record t (triangle t->id) set up for this pass, registered once per pass; when
 * `current`, t has the corners of the current triangle of its id (kept, or a twin) and the subs
 * come from the table of the current triangles'. */
static lm_status register_tri(wk_cpu_views *v, uint32_t h, const lm_tri_data *t, int current,
                              uint32_t *first, uint32_t *n)
{
    wk_cpu_eval *e = &v->eval;
    if (e->loc_stamp[t->id] != e->log.now) {
        wk_cpu_sub local[WK_CPU_MAX_SUBS], *pool;
        int k = 0;
        const wk_cpu_sub *subs =
            current ? wk_cpu_subcache_get(&v->subcache, &v->cviews[h], h, t, local, &k) : NULL;
        lm_status st = LM_OK;
        if (!subs || subs == local) { /* new corners, or not kept in the table */
            st = wk_cpu_setups_pool(&e->set, WK_CPU_MAX_SUBS, &pool);
            if (st == LM_OK && subs)
                memcpy(pool, local, (size_t)k * sizeof *pool);
            else if (st == LM_OK)
                k = wk_cpu_tri_setup(&v->cviews[h], t, pool);
            subs = pool;
        }
        e->loc_first[t->id] = (uint32_t)e->set.n;
        if (st == LM_OK)
            st = wk_cpu_setups_push(&e->set, subs, k, t);
        if (st != LM_OK)
            return st;
        e->loc_stamp[t->id] = e->log.now;
        e->loc_n[t->id] = (uint8_t)k;
    }
    *first = e->loc_first[t->id];
    *n = e->loc_n[t->id];
    return LM_OK;
}

static uint32_t tile_of(const wk_cpu_views *v, uint32_t xy)
{
    return (uint32_t)(WK_CPU_Y(xy) / WK_CPU_TILE) * (uint32_t)v->tiles_w +
           (uint32_t)(WK_CPU_X(xy) / WK_CPU_TILE);
}

/* Raise tile t's maximum to the background for this pass (it may hold holes now). */
static void raise_tile(wk_cpu_eval *e, wk_cpu_keys *k, uint32_t t)
{
    if (e->tile_stamp[t] == e->log.now)
        return;
    e->tile_stamp[t] = e->log.now;
    e->tile_idx[e->n_raised] = t;
    e->tile_old[e->n_raised++] = k->tmax[t];
    k->tmax[t] = WK_CPU_KEY_BG;
}

/* Raise the maxima of the tiles of sub s's box. */
static void raise_tiles(wk_cpu_views *v, wk_cpu_keys *k, const wk_cpu_sub *s)
{
    if (!k->tmax)
        return;
    for (int ty = s->y0 / WK_CPU_TILE; ty * WK_CPU_TILE < s->y1; ty++)
        for (int tx = s->x0 / WK_CPU_TILE; tx * WK_CPU_TILE < s->x1; tx++)
            raise_tile(&v->eval, k, (uint32_t)ty * (uint32_t)v->tiles_w + (uint32_t)tx);
}

/* Step A for removed triangle id: its visible pixels (found along its subs' rows, the key
 * carrying its tag) become holes or, for a twin, pixels to shade again. */
static lm_status punch(wk_cpu_views *v, const lm_patch *p, uint32_t h, uint32_t id, wk_cpu_keys *k)
{
    wk_cpu_eval *e = &v->eval;
    size_t limit = v->core.occlusion ? *wk_cpu_count(v, h, id) : v->plane, found = 0;
    if (limit == 0)
        return LM_OK; /* it shows nowhere */
    int twin = is_twin(e, id);
    wk_cpu_sub local[WK_CPU_MAX_SUBS];
    const wk_cpu_sub *const *reg = NULL, *subs = NULL;
    uint32_t first = 0, n = 0;
    if (twin) { /* registered: its new record shades it, step C may draw it */
        lm_status st = register_tri(v, h, &p->added[e->twin_of[id]], 1, &first, &n);
        if (st != LM_OK)
            return st;
        reg = e->set.sub + first;
    } else {
        int kn = 0;
        subs =
            wk_cpu_subcache_get(&v->subcache, &v->cviews[h], h, &v->core.rep.tris[id], local, &kn);
        n = (uint32_t)kn;
    }
    for (uint32_t i = 0; i < n && found < limit; i++) {
        const wk_cpu_sub *si = reg ? reg[i] : &subs[i];
        size_t m =
            wk_cpu_log_owned(si, k, &e->log, twin ? F_RESHADE : F_HOLE, !twin, limit - found);
        if (m && !twin)
            raise_tiles(v, k, si);
        found += m;
    }
    return LM_OK;
}

/* Step A for every removed triangle: replayed from the view's last pass where that removed the
 * same triangles, with the same twins, against the same keys (cpu_holes.h); else rasterised, and
 * remembered when `keep`. */
static lm_status punch_all(wk_cpu_views *v, const lm_patch *p, uint32_t h, wk_cpu_keys *k, int keep)
{
    wk_cpu_eval *e = &v->eval;
    wk_cpu_holes *c = &e->holes[h];
    lm_status st = LM_OK;
    if (keep && wk_cpu_holes_match(c, v->core.seq, v->core.occlusion, p->removed, e->removed_twin,
                                   p->n_removed)) {
        for (uint32_t i = 0; st == LM_OK && i < p->n_removed; i++) {
            uint32_t id = p->removed[i], first, n; /* twins are registered as punch does */
            if (e->removed_twin[i] && (!v->core.occlusion || *wk_cpu_count(v, h, id)))
                st = register_tri(v, h, &p->added[e->twin_of[id]], 1, &first, &n);
        }
        if (st != LM_OK)
            return st;
        for (size_t j = 0; j < c->n; j++) {
            wk_cpu_log_pixel(&e->log, c->idx[j], c->xy[j], c->old[j], c->flag[j]);
            if (c->flag[j] == F_HOLE)
                k->key[c->idx[j]] = WK_CPU_KEY_BG;
        }
        for (size_t j = 0; k->tmax && j < c->n_tiles; j++)
            raise_tile(e, k, c->tiles[j]);
        return LM_OK;
    }
    for (uint32_t i = 0; st == LM_OK && i < p->n_removed; i++)
        st = punch(v, p, h, p->removed[i], k);
    if (st == LM_OK && keep)
        wk_cpu_holes_keep(c, v->core.seq, v->core.occlusion, p->removed, e->removed_twin,
                          p->n_removed, &e->log, e->log.n, e->tile_idx, e->n_raised);
    else
        wk_cpu_holes_forget(c);
    return st;
}

/* Step B: the added triangles that are not twins, drawn with logging. */
static lm_status draw_added(wk_cpu_views *v, const lm_patch *p, uint32_t h, wk_cpu_keys *k)
{
    wk_cpu_eval *e = &v->eval;
    const wk_cpu_clip all = {{0, 0, v->core.width, v->core.height}, NULL};
    for (uint32_t i = 0; i < p->n_added; i++) {
        if (is_twin(e, p->added[i].id))
            continue;
        uint32_t first, n;
        lm_status st = register_tri(v, h, &p->added[i], 0, &first, &n);
        if (st != LM_OK)
            return st;
        for (uint32_t j = 0; j < n; j++)
            wk_cpu_draw(e->set.sub[first + j], k, &all, &e->log, F_NEW);
        v->core.stats.tris_drawn += n;
    }
    return LM_OK;
}

static void update_tile(const wk_cpu_views *v, wk_cpu_keys *k, uint32_t t)
{
    int x = (int)(t % (uint32_t)v->tiles_w) * WK_CPU_TILE,
        y = (int)(t / (uint32_t)v->tiles_w) * WK_CPU_TILE;
    const wk_rect one = {x, y, x + 1, y + 1};
    wk_cpu_keys_update_tiles(k, &one);
}

/* The box of the holes not certainly filled and, with occlusion, the mask of their tiles and per
 * tile the greatest key among them (only those pixels can still change: a kept triangle behind
 * that key everywhere in a tile changes nothing there); 0 if there are none. A hole is filled for
 * certain when its new key is not above a lower bound of every kept triangle's key there: the old
 * key (the removed triangle beat them all) or, with occlusion, the second least key's bound. */
static int unresolved(wk_cpu_views *v, uint32_t h, const wk_cpu_keys *k, wk_rect *box)
{
    wk_cpu_eval *e = &v->eval;
    const uint32_t *bound = v->core.occlusion ? v->second + h * v->plane : NULL;
    *box = (wk_rect){v->core.width, v->core.height, 0, 0};
    e->n_mask = 0;
    for (size_t j = 0; j < e->log.n; j++) {
        uint32_t q = e->log.idx[j];
        /* filled for certain: at or in front of the old key, or of the second key's bound
         * (the old key first: it is at hand, the bound is a load from a large table) */
        if (e->log.flag[j] != F_HOLE || k->key[q] <= e->log.old[j] ||
            (bound && k->key[q] <= wk_cpu_second_key(bound[q])))
            continue;
        int x = WK_CPU_X(e->log.xy[j]), y = WK_CPU_Y(e->log.xy[j]);
        box->x0 = x < box->x0 ? x : box->x0;
        box->y0 = y < box->y0 ? y : box->y0;
        box->x1 = x + 1 > box->x1 ? x + 1 : box->x1;
        box->y1 = y + 1 > box->y1 ? y + 1 : box->y1;
        uint32_t t = tile_of(v, e->log.xy[j]);
        if (!v->core.occlusion)
            continue;
        if (!e->tile_mask[t]) {
            e->tile_mask[t] = 1;
            e->mask_idx[e->n_mask++] = t;
            e->cmax[t] = 0;
        }
        e->cmax[t] = k->key[q] > e->cmax[t] ? k->key[q] : e->cmax[t];
    }
    return box->x0 < box->x1;
}

/* The least key a triangle's fragments may have, from its bucket footprint (0 when unknown): its
 * nearest corner's window depth, less a margin far above the float error of that projection. */
static uint64_t footprint_bound(const wk_footprint *f)
{
    double z = (double)f->zmin - 1e-5;
    if (!f->projected || !(z > 0.0))
        return 0;
    return z < 1.0 ? (uint64_t)(z * 4294967296.0) << 32 : 0xFFFFFFFF00000000ull;
}

/* Whether some masked tile meeting rectangle r has a maximum at or above bound. */
static int masked_tiles_behind(const wk_cpu_views *v, const wk_rect *r, uint64_t bound)
{
    const wk_cpu_eval *e = &v->eval;
    for (size_t i = 0; i < e->n_mask; i++) {
        uint32_t t = e->mask_idx[i];
        int x = (int)(t % (uint32_t)v->tiles_w) * WK_CPU_TILE;
        int y = (int)(t / (uint32_t)v->tiles_w) * WK_CPU_TILE;
        wk_rect tile = {x, y, x + WK_CPU_TILE, y + WK_CPU_TILE};
        if (e->cmax[t] >= bound && wk_rects_meet(&tile, r))
            return 1;
    }
    return 0;
}

/* Whether candidate id (a kept triangle) may show in front somewhere in the masked tiles. */
static int candidate_may_show(const wk_cpu_views *v, uint32_t h, uint32_t id)
{
    if (!v->core.occlusion)
        return 1;
    const wk_footprint *f = wk_buckets_footprint(v->core.buckets[h], id);
    return masked_tiles_behind(v, &f->rect, footprint_bound(f));
}

/* A hint that sub s will be drawn soon: the lines the rasteriser reads (not the shading's). */
static void prefetch_sub(const wk_cpu_sub *s)
{
    __builtin_prefetch(s);
    __builtin_prefetch((const char *)s + 64);
    __builtin_prefetch(&s->bias[2]); /* the last of them (wk_cpu_sub) */
}

/* Step C: kept triangles (and twins) whose footprint meets the unresolved holes. */
static lm_status fill_unresolved(wk_cpu_views *v, const lm_patch *p, uint32_t h, wk_cpu_keys *k)
{
    wk_cpu_eval *e = &v->eval;
    wk_cpu_clip clip = {{0, 0, 0, 0}, v->core.occlusion ? e->tile_mask : NULL};
    if (!unresolved(v, h, k, &clip.rect))
        return LM_OK;
    wk_cpu_keys kc = *k; /* depth rejection against the unresolved pixels' maxima */
    if (v->core.occlusion)
        kc.tmax = e->cmax;
    e->cand.n = 0;
    lm_status st = wk_buckets_query(v->core.buckets[h], &clip.rect, &e->cand);
    size_t m = 0; /* the candidates kept, registered first: their subs' loads then overlap */
    for (size_t i = 0; st == LM_OK && i < e->cand.n; i++) {
        uint32_t id = e->cand.ids[i], first, n;
        const lm_tri_data *t = &v->core.rep.tris[id];
        if (wk_patch_removes(&e->marks, id)) {
            if (!is_twin(e, id))
                continue;
            t = &p->added[e->twin_of[id]];
        }
        if (!candidate_may_show(v, h, id))
            continue;
        st = register_tri(v, h, t, 1, &first, &n);
        for (uint32_t j = 0; st == LM_OK && j < n; j++)
            prefetch_sub(e->set.sub[first + j]);
        e->cand.ids[m++] = id;
    }
    for (size_t i = 0; st == LM_OK && i < m; i++) {
        uint32_t id = e->cand.ids[i], first = e->loc_first[id], n = e->loc_n[id];
        for (uint32_t j = 0; j < n; j++)
            wk_cpu_draw(e->set.sub[first + j], &kc, &clip, &e->log, F_NEW);
        v->core.stats.tris_drawn += n;
    }
    for (size_t i = 0; i < e->n_mask; i++)
        e->tile_mask[e->mask_idx[i]] = 0;
    return st;
}

/* The setup index of the sub that key belongs to (drawn during this pass). */
static lm_status sub_of_key(wk_cpu_views *v, uint64_t key, uint32_t *out)
{
    wk_cpu_eval *e = &v->eval;
    uint32_t id = WK_CPU_KEY_ID(key), j = e->loc_first[id], end = j + e->loc_n[id];
    if (e->loc_stamp[id] != e->log.now)
        return lm_fail(LM_E_INTERNAL, "a pixel shows triangle %u, which this pass never drew", id);
    while (j < end && e->set.sub[j]->tag != (uint32_t)key)
        j++;
    LM_ASSERT(j < end);
    *out = j;
    return LM_OK;
}

/* The shading of setup j, made on first use. */
static const wk_cpu_shade *shade_of(wk_cpu_views *v, uint32_t h, uint32_t j)
{
    wk_cpu_setups *set = &v->eval.set;
    if (!set->shade_ready[j]) {
        wk_cpu_shade_setup(set->sub[j], set->tri[j], v->core.views.views[h].dir,
                           &v->mats[v->core.table], &set->shade[j]);
        set->shade_ready[j] = 1;
    }
    return &set->shade[j];
}

/* Step D: new luminance of every logged pixel (runs of pixels of one sub shaded together) and
 * the view's ΔE. */
/* Entries [i, end) of the log with one visible sub (tag) and all changed or all unchanged. */
static size_t run_end(const wk_cpu_eval *e, const wk_cpu_keys *k, size_t i, int *unchanged)
{
    uint64_t key = k->key[e->log.idx[i]];
    size_t end = i + 1;
    *unchanged = key == e->log.old[i];
    while (end < e->log.n && (uint32_t)k->key[e->log.idx[end]] == (uint32_t)key &&
           (k->key[e->log.idx[end]] == e->log.old[end]) == *unchanged)
        end++;
    return end;
}

/* Shade log entries [i, end), all showing setup j; a twin that keeps its texture reuses the
 * view's stored factors where it showed before (unchanged keys). */
static void shade_run(wk_cpu_views *v, uint32_t h, uint32_t j, size_t i, size_t end, int unchanged)
{
    wk_cpu_eval *e = &v->eval;
    float *texl = e->texl + 3 * i;
    int reuse = v->texf && unchanged && e->textwin_stamp[e->set.tri[j]->id] == e->marks.now;
    for (size_t r = i; reuse && r < end; r++)
        memcpy(texl + 3 * (r - i), v->texf + 3 * (h * v->plane + e->log.idx[r]), 3 * sizeof *texl);
    wk_cpu_shade_pixels(e->set.sub[j], shade_of(v, h, j), e->log.xy + i, end - i, e->rgb,
                        e->luma + i, texl, reuse);
}

/* Step D: new luminance of every logged pixel (runs of pixels of one sub shaded together) and
 * the view's ΔE. */
static lm_status shade_log(wk_cpu_views *v, uint32_t h, const wk_cpu_keys *k, int64_t *delta)
{
    wk_cpu_eval *e = &v->eval;
    for (size_t i = 0; i < e->log.n;) {
        int unchanged;
        size_t end = run_end(e, k, i, &unchanged);
        uint64_t key = k->key[e->log.idx[i]];
        if (key == WK_CPU_KEY_BG) {
            memset(e->luma + i, WK_CPU_BACKGROUND, end - i);
        } else {
            uint32_t j = 0;
            lm_status st = sub_of_key(v, key, &j);
            if (st != LM_OK)
                return st;
            shade_run(v, h, j, i, end, unchanged);
        }
        i = end;
    }
    const uint8_t *tgt = wk_image_store_target(v->core.img, h),
                  *cur = wk_image_store_current(v->core.img, h);
    int64_t d = 0;
    for (size_t i = 0; i < e->log.n; i++) {
        uint32_t q = e->log.idx[i];
        int a = (int)tgt[q] - (int)e->luma[i], b = (int)tgt[q] - (int)cur[q];
        d += a * a - b * b;
    }
    *delta += d;
    return LM_OK;
}

/* ---- gathering a view's memory ----------------------------------------------------------- */

/* The per-pixel tables of all views (keys, second-key bounds, luminance: ~0.9 MB a view of 256²)
 * and the kept subs are far larger than the caches. Inside a pass their loads sit behind branches
 * that depend on them, so they miss one after another: measured, an evaluation of a patch whose
 * memory is cold took 1.75 times as long as the same evaluation again. So before view h's pass
 * the rows that the patch's visible removed triangles cover there (their subs' box) are read in
 * a loop of independent loads, which the processor overlaps, and the subs that the next view's
 * box needs (of its visible removed triangles only: punch reads no other's) and the visible-pixel
 * counts of the view after it are asked for (hints, a view ahead of their first read). No value
 * depends on either. */
#define GATHER_MAX_PIXELS 4096 /* a larger box is mostly work, not waiting: left alone */

static void prefetch_subs(const wk_cpu_views *v, const lm_patch *p, uint32_t h)
{
    int ahead = h + 1 < v->core.views.count;
    for (uint32_t i = 0; i < p->n_removed; i++) {
        uint32_t id = p->removed[i];
        if (ahead) /* read when view h's subs are asked for, one view later */
            __builtin_prefetch(wk_cpu_count(v, h + 1, id));
        if (*wk_cpu_count(v, h, id)) /* only a visible triangle's subs are read (punch) */
            wk_cpu_subcache_prefetch(&v->subcache, h, id);
    }
}

/* The box of the subs of the patch's removed triangles that show in view h (kept subs only). */
static wk_rect removed_box(const wk_cpu_views *v, const lm_patch *p, uint32_t h)
{
    wk_rect box = {0, 0, 0, 0};
    for (uint32_t i = 0; i < p->n_removed; i++) {
        const wk_cpu_sub *s;
        if (*wk_cpu_count(v, h, p->removed[i]) &&
            (s = wk_cpu_subcache_peek(&v->subcache, h, p->removed[i])))
            wk_rect_union(&box, &(wk_rect){s->x0, s->y0, s->x1, s->y1});
    }
    return box;
}

/* One load per cache line of the box's rows in each table; the sum only keeps the loads. */
static uint64_t touch_rows(const wk_cpu_views *v, uint32_t h, const wk_rect *box)
{
    const uint64_t *keys = v->keys + h * v->plane;
    const uint32_t *second = v->second + h * v->plane;
    const uint8_t *tgt = wk_image_store_target(v->core.img, h),
                  *cur = wk_image_store_current(v->core.img, h);
    uint64_t sum = 0;
    for (int y = box->y0; y < box->y1; y++) {
        size_t row = (size_t)y * (size_t)v->core.width;
        for (int x = box->x0 & ~7; x < box->x1; x += 8)
            sum += keys[row + x];
        for (int x = box->x0 & ~15; x < box->x1; x += 16)
            sum += second[row + x];
        for (int x = box->x0 & ~63; x < box->x1; x += 64)
            sum += tgt[row + x] + cur[row + x];
    }
    return sum;
}

/* Whether the patch certainly changes nothing in view h: none of its removed triangles shows
 * there and its added ones (twins aside) lie behind the visible surface. */
static int view_unchanged(const wk_cpu_views *v, const lm_patch *p, uint32_t h,
                          const wk_cpu_keys *k)
{
    if (!v->core.occlusion)
        return 0;
    for (uint32_t i = 0; i < p->n_removed; i++)
        if (*wk_cpu_count(v, h, p->removed[i]))
            return 0;
    return wk_cpu_box_hidden(&v->eval.box, &v->cviews[h], k);
}

/* One view's pass; `keep`: an evaluation's (its step A may be replayed, and remembered), not a
 * commit's (which changes the keys). */
static lm_status view_pass(wk_cpu_views *v, const lm_patch *p, uint32_t h, wk_cpu_keys *k,
                           int64_t *delta, int keep)
{
    pass_begin(v);
    if (view_unchanged(v, p, h, k)) {
        v->core.stats.views_skipped++;
        return LM_OK;
    }
    if (!v->core.occlusion)
        k->tmax = NULL;
    lm_status st = punch_all(v, p, h, k, keep);
    if (st == LM_OK)
        st = draw_added(v, p, h, k);
    if (st == LM_OK)
        st = fill_unresolved(v, p, h, k);
    if (st == LM_OK)
        st = shade_log(v, h, k, delta);
    wk_cpu_log *log = &v->eval.log;
    v->core.stats.regions += log->n > 0;
    v->core.stats.region_pixels += log->n;
    v->core.stats.views_skipped += log->n == 0;
    return st;
}

/* Put the keys and tile maxima back as they were before the pass. */
static void roll_back(wk_cpu_views *v, uint32_t h)
{
    wk_cpu_eval *e = &v->eval;
    wk_cpu_keys k = wk_cpu_view_keys(v, h);
    for (size_t j = 0; j < e->log.n; j++)
        k.key[e->log.idx[j]] = e->log.old[j];
    for (size_t i = 0; i < e->n_raised; i++)
        k.tmax[e->tile_idx[i]] = e->tile_old[i];
}

/* The bounds of the second least keys after the pass: a visible triangle that stays but is
 * beaten now, and every fragment of an added triangle that is not the visible one, may be the
 * second least key of its pixel (kept ones behind keep bounds that are still true). */
static void keep_second(wk_cpu_views *v, uint32_t h, const lm_patch *p)
{
    wk_cpu_eval *e = &v->eval;
    wk_cpu_keys k = wk_cpu_view_keys(v, h);
    k.tmax = NULL;
    k.second = v->second + h * v->plane;
    for (size_t j = 0; j < e->log.n; j++) {
        uint32_t q = e->log.idx[j];
        uint64_t old = e->log.old[j];
        if (old == WK_CPU_KEY_BG || old == k.key[q])
            continue;
        uint32_t id = WK_CPU_KEY_ID(old);
        if (!wk_patch_removes(&e->marks, id) || is_twin(e, id))
            k.second[q] = wk_cpu_second_of(old) < k.second[q] ? wk_cpu_second_of(old) : k.second[q];
    }
    const wk_cpu_clip all = {{0, 0, v->core.width, v->core.height}, NULL};
    for (uint32_t i = 0; i < p->n_added; i++) {
        uint32_t id = p->added[i].id;
        if (is_twin(e, id) || e->loc_stamp[id] != e->log.now)
            continue;
        for (uint32_t j = 0; j < e->loc_n[id]; j++)
            wk_cpu_draw(e->set.sub[e->loc_first[id] + j], &k, &all, NULL, 0);
    }
}

/* Keep the pass: luminance and energy, visible-pixel counts, exact tile maxima, second keys. */
static void keep(wk_cpu_views *v, uint32_t h, const lm_patch *p)
{
    wk_cpu_eval *e = &v->eval;
    wk_cpu_keys k = wk_cpu_view_keys(v, h);
    wk_image_store_commit_pixels(v->core.img, h, e->log.idx, e->luma, e->log.n);
    for (size_t j = 0; v->texf && j < e->log.n; j++) /* (unused where the surface is untextured) */
        memcpy(v->texf + 3 * (h * v->plane + e->log.idx[j]), e->texl + 3 * j, 3 * sizeof(float));
    for (size_t j = 0; j < e->log.n; j++) {
        uint64_t now = k.key[e->log.idx[j]];
        if (e->log.old[j] != WK_CPU_KEY_BG)
            (*wk_cpu_count(v, h, WK_CPU_KEY_ID(e->log.old[j])))--;
        if (now != WK_CPU_KEY_BG)
            (*wk_cpu_count(v, h, WK_CPU_KEY_ID(now)))++;
    }
    for (size_t j = 0; j < e->log.n; j++) { /* tiles raised for holes have the stamp already */
        uint32_t t = tile_of(v, e->log.xy[j]);
        if (e->tile_stamp[t] != e->log.now) {
            e->tile_stamp[t] = e->log.now;
            update_tile(v, &k, t);
        }
    }
    for (size_t i = 0; i < e->n_raised; i++)
        update_tile(v, &k, e->tile_idx[i]);
    keep_second(v, h, p);
}

/* ---- evaluate and commit ------------------------------------------------------------------ */

static void gather_view(wk_cpu_views *v, const lm_patch *p, uint32_t h)
{
    if (!v->core.occlusion) /* no visible-pixel counts: every removed triangle is searched */
        return;
    if (h + 1 < v->core.views.count)
        prefetch_subs(v, p, h + 1);
    wk_rect box = removed_box(v, p, h);
    if (box.x0 < box.x1 && (box.x1 - box.x0) * (box.y1 - box.y0) <= GATHER_MAX_PIXELS)
        v->eval.gathered += touch_rows(v, h, &box);
}

lm_status wk_cpu_evaluate(wk_views_core *c, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    wk_cpu_views *v = (wk_cpu_views *)c;
    lm_status st = LM_OK;
    for (uint32_t i = 0; st == LM_OK && i < n; i++) {
        st = prepare_patch(v, &patches[i]);
        for (uint32_t h = 0; st == LM_OK && h < v->core.views.count; h++) {
            gather_view(v, &patches[i], h);
            wk_cpu_keys k = wk_cpu_view_keys(v, h);
            st = view_pass(v, &patches[i], h, &k, &delta[i], 1);
            roll_back(v, h);
        }
        v->core.stats.evaluations++;
    }
    v->core.stats.batches++;
    return st;
}

/* What the views keep of triangle id: its kept subs. */
static void forget_tri(wk_views_core *c, uint32_t id)
{
    wk_cpu_subcache_forget(&((wk_cpu_views *)c)->subcache, id);
}

lm_status wk_cpu_commit(wk_views_core *c, const lm_patch *patch)
{
    wk_cpu_views *v = (wk_cpu_views *)c;
    lm_status st = prepare_patch(v, patch);
    if (st == LM_OK)
        st = wk_cpu_count_reserve(v, v->eval.cap_ids);
    if (st != LM_OK)
        return st; /* nothing changed yet */
    for (uint32_t h = 0; st == LM_OK && h < v->core.views.count; h++) {
        gather_view(v, patch, h);
        wk_cpu_keys k = wk_cpu_view_keys(v, h);
        int64_t unused = 0;
        st = view_pass(v, patch, h, &k, &unused, 0);
        if (st == LM_OK)
            keep(v, h, patch);
        else
            roll_back(v, h);
    }
    if (st == LM_OK) /* replica and buckets follow the patch */
        st = wk_views_core_apply(c, patch, forget_tri);
    if (st == LM_OK)
        st = wk_cpu_subcache_reserve(&v->subcache, v->core.rep.cap);
    if (st != LM_OK) {
        v->core.mesh_set = 0; /* half-applied: refuse further work until set_mesh */
        v->core.buckets_ready = 0;
    }
    return st;
}
