/* coordinator/compare.c — energies and image grids of models against an original. */
#include "coordinator/compare.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/patch.h"
#include "worker/views_local.h"

/* Make `m` (with its own materials) the current mesh of the views. */
static lm_status set_model(lm_views *views, const lm_mesh *m)
{
    lm_status st = wk_views_local_set_materials(views, m->materials, m->n_materials);
    if (st != LM_OK)
        return st;
    lm_tri_data *tris = NULL;
    size_t n = 0;
    st = lm_mesh_export_tris(m, &tris, &n);
    if (st == LM_OK)
        st = views->ops->set_mesh(views, tris, n);
    free(tris);
    return st;
}

lm_status co_compare_energies(const lm_mesh *original, const lm_view_set *views,
                              const char *device_spec, const lm_mesh *const *models, uint32_t n,
                              int64_t *energy, char *renderer)
{
    lm_views *v = NULL;
    lm_status st = wk_views_local_create(original, views, device_spec, &v);
    for (uint32_t i = 0; st == LM_OK && i < n; i++) {
        st = set_model(v, models[i]);
        if (st == LM_OK)
            st = v->ops->energy(v, &energy[i], NULL);
    }
    if (st == LM_OK && renderer) {
        lm_views_info info;
        v->ops->info(v, &info);
        snprintf(renderer, 128, "%s", info.renderer);
    }
    lm_views_destroy(v);
    return st;
}

lm_status co_coverage_masks(lm_views *views, uint8_t **masks)
{
    *masks = NULL;
    lm_views_info info;
    views->ops->info(views, &info);
    size_t plane = (size_t)info.width * (size_t)info.height;
    uint8_t *m = malloc(plane * info.n_views);
    if (!m)
        return lm_fail(LM_E_NOMEM, "out of memory for coverage masks");
    lm_status st = LM_OK;
    for (uint32_t i = 0; st == LM_OK && i < info.n_views; i++)
        st = wk_views_local_read_coverage(views, i, m + plane * i);
    if (st != LM_OK) {
        free(m);
        return st;
    }
    *masks = m;
    return LM_OK;
}

co_coverage co_coverage_compare(const uint8_t *original, const uint8_t *model, size_t n)
{
    co_coverage c = {0, 0, 0};
    for (size_t i = 0; i < n; i++) {
        c.original_px += original[i];
        c.missing_px += original[i] && !model[i];
        c.extra_px += !original[i] && model[i];
    }
    return c;
}

/* Copy a bottom-row-first RGBA view image into cell (row, col) of the grid (top row first). */
static void blit(lm_image *grid, const uint8_t *rgba, int w, int h, int row, int col)
{
    int x0 = col * (w + CO_COMPARE_GAP), y0 = row * (h + CO_COMPARE_GAP);
    for (int y = 0; y < h; y++) {
        const uint8_t *src = rgba + (size_t)(h - 1 - y) * (size_t)w * 4;
        uint8_t *dst = grid->pixels + ((size_t)(y0 + y) * (size_t)grid->width + (size_t)x0) * 4;
        memcpy(dst, src, (size_t)w * 4);
    }
}

static lm_image *make_canvas(int w, int h, uint32_t rows, uint32_t cols)
{
    lm_image *img = NULL;
    int W = (int)cols * w + (int)(cols - 1) * CO_COMPARE_GAP;
    int H = (int)rows * h + (int)(rows - 1) * CO_COMPARE_GAP;
    if (lm_image_create(W, H, &img) != LM_OK)
        return NULL;
    for (size_t i = 0; i < (size_t)W * (size_t)H; i++) {
        uint8_t *p = img->pixels + 4 * i;
        p[0] = p[1] = p[2] = 32;
        p[3] = 255;
    }
    return img;
}

/* Column `col` of the grid: every view of the current render. */
static lm_status fill_column(lm_views *v, lm_image *grid, uint8_t *buf, uint32_t rows, int w, int h,
                             int col)
{
    for (uint32_t i = 0; i < rows; i++) {
        lm_status st = wk_views_local_read_rgba(v, i, buf);
        if (st != LM_OK)
            return st;
        blit(grid, buf, w, h, (int)i, col);
    }
    return LM_OK;
}

lm_status co_compare_grid(const lm_mesh *original, const lm_view_set *views,
                          const char *device_spec, const lm_mesh *const *models, uint32_t n,
                          lm_image **out)
{
    *out = NULL;
    if (views->count == 0)
        return lm_fail(LM_E_INVALID, "a comparison grid needs at least one view");
    int w = views->views[0].width, h = views->views[0].height;
    lm_image *grid = make_canvas(w, h, views->count, n + 1);
    uint8_t *buf = malloc((size_t)w * (size_t)h * 4);
    lm_views *v = NULL;
    lm_status st = grid && buf ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for the image grid");
    if (st == LM_OK)
        st = wk_views_local_create(original, views, device_spec, &v);
    if (st == LM_OK)
        st = fill_column(v, grid, buf, views->count, w, h, 0);
    for (uint32_t m = 0; st == LM_OK && m < n; m++) {
        st = set_model(v, models[m]);
        if (st == LM_OK)
            st = fill_column(v, grid, buf, views->count, w, h, (int)m + 1);
    }
    lm_views_destroy(v);
    free(buf);
    if (st != LM_OK) {
        lm_image_destroy(grid);
        return st;
    }
    *out = grid;
    return LM_OK;
}
