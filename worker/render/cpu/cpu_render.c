/* worker/render/cpu/cpu_render.c — a full render of one view on the CPU: every triangle's subs
 * drawn into the keys (the visible surface is the least key, whatever the order; the second least
 * is kept too), the visible pixels of each triangle counted, then every visible triangle shaded
 * once at exactly its pixels (deferred shading: each pixel's colour is computed once, by the same
 * function a redrawn region uses). */
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "worker/render/cpu/cpu_views_internal.h"

lm_status wk_cpu_count_reserve(wk_cpu_views *v, size_t need)
{
    if (need <= v->cap_count)
        return LM_OK;
    size_t cap = lm_grow_cap(v->cap_count, need, 1024, SIZE_MAX), n = v->core.views.count;
    uint32_t *c = realloc(v->count, cap * n * sizeof *c);
    if (!c)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu visible-pixel counts", cap);
    memset(c + v->cap_count * n, 0, (cap - v->cap_count) * n * sizeof *c);
    v->count = c;
    v->cap_count = cap;
    return LM_OK;
}

static size_t source_ids(const wk_cpu_source *src)
{
    return src->mesh ? src->mesh->n_tris : src->rep->cap;
}

/* The record of triangle id, or NULL when it is not alive (tmp holds a mesh triangle's). */
static const lm_tri_data *source_tri(const wk_cpu_source *src, uint32_t id, lm_tri_data *tmp)
{
    if (src->mesh) {
        if (!src->mesh->tri_alive[id])
            return NULL;
        lm_tri_data_from_mesh(src->mesh, id, tmp);
        return tmp;
    }
    return src->rep->alive[id] ? &src->rep->tris[id] : NULL;
}

/* A mesh source's vertices in view h (v->vc), for wk_cpu_tri_covers_none; 0 when out of memory
 * (every triangle then takes the full setup: the same image, slower). */
static int project_vertices(wk_cpu_views *v, uint32_t h, const lm_mesh *m)
{
    if (m->n_verts > v->cap_vc) {
        wk_cpu_vcorner *vc = realloc(v->vc, (size_t)m->n_verts * sizeof *vc);
        if (!vc)
            return 0;
        v->vc = vc;
        v->cap_vc = m->n_verts;
    }
    for (uint32_t i = 0; i < m->n_verts; i++)
        wk_cpu_vcorner_make(&v->cviews[h], m->pos[i], &v->vc[i]);
    return 1;
}

/* 1 when mesh triangle id is alive and may cover a pixel centre of view h (vertices projected). */
static int mesh_tri_may_cover(const wk_cpu_views *v, uint32_t h, const lm_mesh *m, uint32_t id)
{
    if (!m->tri_alive[id])
        return 0;
    const lm_tri *t = &m->tris[id];
    const wk_cpu_vcorner *c0 = &v->vc[m->wedges[t->w[0]].vertex];
    const wk_cpu_vcorner *c1 = &v->vc[m->wedges[t->w[1]].vertex];
    const wk_cpu_vcorner *c2 = &v->vc[m->wedges[t->w[2]].vertex];
    return !wk_cpu_tri_covers_none(&v->cviews[h], c0, c1, c2);
}

static void draw_all(wk_cpu_views *v, uint32_t h, const wk_cpu_source *src)
{
    wk_cpu_keys k = wk_cpu_view_keys(v, h);
    k.tmax = NULL; /* maxima are made at the end */
    k.second = v->second + h * v->plane;
    for (size_t p = 0; p < v->plane; p++) {
        k.key[p] = WK_CPU_KEY_BG;
        k.second[p] = WK_CPU_SECOND_NONE;
    }
    const wk_cpu_clip all = {{0, 0, v->core.width, v->core.height}, NULL};
    wk_cpu_sub subs[WK_CPU_MAX_SUBS];
    lm_tri_data tmp;
    size_t n_ids = source_ids(src);
    /* a mesh (the original: its targets) has its vertices projected once, and its triangles that
       cover no pixel centre dropped before their records are made: the same subs are drawn */
    int early = src->mesh && project_vertices(v, h, src->mesh);
    for (size_t id = 0; id < n_ids; id++) {
        if (early && !mesh_tri_may_cover(v, h, src->mesh, (uint32_t)id))
            continue;
        const lm_tri_data *t = source_tri(src, (uint32_t)id, &tmp);
        int n = t ? wk_cpu_tri_setup(&v->cviews[h], t, subs) : 0;
        for (int i = 0; i < n; i++)
            wk_cpu_draw(&subs[i], &k, &all, NULL, 0);
    }
}

/* Colour and luminance of the pixels each visible triangle owns. */
static void shade_all(wk_cpu_views *v, uint32_t h, const wk_cpu_source *src, int table, uint8_t *y,
                      const uint32_t *cnt)
{
    wk_cpu_keys k = wk_cpu_view_keys(v, h);
    uint8_t *rgba = v->rgba + h * v->plane * 4;
    for (size_t p = 0; p < v->plane; p++) {
        rgba[4 * p] = rgba[4 * p + 1] = rgba[4 * p + 2] = WK_CPU_BACKGROUND;
        rgba[4 * p + 3] = 255;
        y[p] = WK_CPU_BACKGROUND;
    }
    const lm_view *view = &v->core.views.views[h];
    const wk_rect all = {0, 0, v->core.width, v->core.height};
    wk_cpu_sub subs[WK_CPU_MAX_SUBS];
    wk_cpu_shade sh;
    lm_tri_data tmp;
    uint8_t *rgb = v->eval.rgb, *lum = v->eval.luma;
    size_t n_ids = source_ids(src);
    for (size_t id = 0; id < n_ids; id++) {
        const lm_tri_data *t = cnt[id] ? source_tri(src, (uint32_t)id, &tmp) : NULL;
        int n = t ? wk_cpu_tri_setup(&v->cviews[h], t, subs) : 0;
        for (int i = 0; i < n; i++) {
            size_t m = wk_cpu_owned(&subs[i], &k, &all, v->eval.owned, cnt[id]);
            if (m)
                wk_cpu_shade_setup(&subs[i], t, view->dir, &v->mats[table], &sh);
            float *texl = v->eval.texl;
            wk_cpu_shade_pixels(&subs[i], &sh, v->eval.owned, m, rgb, lum, texl, 0);
            for (size_t j = 0; j < m; j++) {
                uint32_t xy = v->eval.owned[j];
                size_t p = (size_t)WK_CPU_Y(xy) * v->core.width + WK_CPU_X(xy);
                if (v->texf && sh.tex)
                    memcpy(v->texf + 3 * (h * v->plane + p), texl + 3 * j, 3 * sizeof *texl);
                rgba[4 * p] = rgb[j];
                rgba[4 * p + 1] = rgb[m + j];
                rgba[4 * p + 2] = rgb[2 * m + j];
                y[p] = lum[j];
            }
        }
    }
}

lm_status wk_cpu_render_view(wk_cpu_views *v, uint32_t h, const wk_cpu_source *src, int table,
                             uint8_t *y, uint32_t *count)
{
    size_t n_ids = source_ids(src);
    uint32_t *cnt = count ? count : calloc(n_ids ? n_ids : 1, sizeof *cnt);
    if (!cnt)
        return lm_fail(LM_E_NOMEM, "out of memory counting %zu triangles' pixels", n_ids);
    if (count)
        memset(cnt, 0, n_ids * sizeof *cnt);
    draw_all(v, h, src);
    const uint64_t *key = v->keys + h * v->plane;
    for (size_t p = 0; p < v->plane; p++)
        if (key[p] != WK_CPU_KEY_BG)
            cnt[WK_CPU_KEY_ID(key[p])]++;
    shade_all(v, h, src, table, y, cnt);
    wk_cpu_keys k = wk_cpu_view_keys(v, h);
    const wk_rect all = {0, 0, v->core.width, v->core.height};
    wk_cpu_keys_update_tiles(&k, &all);
    if (!count)
        free(cnt);
    return LM_OK;
}
