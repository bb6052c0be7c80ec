/* coordinator/quality/report_sheet.c — the report's pictures: the contact sheet (a few held-out
 * views, columns original | initial | optimized | difference) and, where a model shows cracks,
 * the close-up of the window with the most of them, rendered CO_REPORT_ZOOM times larger. The
 * difference column is |Y(original) - Y(optimized)| of the 8-bit luminance the energy sums,
 * times 2, as a heat ramp (black, red, yellow, white). A level set's sheet has a column per level
 * and the difference of the last (coarsest). */
#include <stdlib.h>
#include <string.h>

#include "coordinator/quality/report_internal.h"

#define SHEET_DIFF_GAIN 2

/* The sheet's views out of a held-out set made at `size`. *out is malloc'ed. */
static lm_status sheet_views(const co_report *r, int size, lm_view_set **out)
{
    const lm_mesh *o = r->model[0].mesh;
    float c[3], rad;
    lm_mesh_bounding_sphere(o, c, &rad);
    lm_view_set *all = malloc(sizeof *all), *vs = malloc(sizeof *vs);
    lm_status s = all && vs ? lm_view_set_make_spec(all, &r->o->views, LM_VIEWS_HELDOUT, size, c,
                                                    rad > 0 ? rad : 1.0f)
                            : lm_fail(LM_E_NOMEM, "out of memory for views");
    if (!s) {
        vs->count = CO_REPORT_SHEET_VIEWS;
        for (uint32_t i = 0; i < CO_REPORT_SHEET_VIEWS; i++)
            vs->views[i] = all->views[r->sheet_view[i]];
    }
    free(all);
    if (s) {
        free(vs);
        return s;
    }
    *out = vs;
    return LM_OK;
}

static void heat(uint8_t d, uint8_t *px)
{
    int v = d * SHEET_DIFF_GAIN * 3;
    px[0] = (uint8_t)(v > 255 ? 255 : v);
    px[1] = (uint8_t)(v > 510 ? 255 : v > 255 ? v - 255 : 0);
    px[2] = (uint8_t)(v > 765 ? 255 : v > 510 ? v - 510 : 0);
    px[3] = 255;
}

/* The grid with one more column: the difference between its first column (the original) and its
 * last (the optimized model). Cells are cw x ch, `rows` of them. */
static lm_status add_difference(const lm_image *grid, int cw, int ch, uint32_t rows, lm_image **out)
{
    int cols = (grid->width + CO_COMPARE_GAP) / (cw + CO_COMPARE_GAP);
    lm_image *img = NULL;
    lm_status s = lm_image_create(grid->width + CO_COMPARE_GAP + cw, grid->height, &img);
    if (s)
        return s;
    memset(img->pixels, 32, (size_t)img->width * (size_t)img->height * 4);
    for (int y = 0; y < grid->height; y++) {
        uint8_t *dst = img->pixels + (size_t)y * (size_t)img->width * 4;
        const uint8_t *src = grid->pixels + (size_t)y * (size_t)grid->width * 4;
        memcpy(dst, src, (size_t)grid->width * 4);
        for (int x = grid->width; x < img->width; x++)
            dst[4 * x + 3] = 255;
    }
    int x_last = (cols - 1) * (cw + CO_COMPARE_GAP), x_diff = cols * (cw + CO_COMPARE_GAP);
    for (uint32_t row = 0; row < rows; row++)
        for (int y = 0; y < ch; y++) {
            int yy = (int)row * (ch + CO_COMPARE_GAP) + y;
            uint8_t *line = img->pixels + (size_t)yy * (size_t)img->width * 4;
            for (int x = 0; x < cw; x++) {
                int a = lm_luma(line + 4 * x), b = lm_luma(line + 4 * (x_last + x));
                heat((uint8_t)(a > b ? a - b : b - a), line + 4 * (x_diff + x));
            }
        }
    *out = img;
    return LM_OK;
}

/* The models after the original, as co_compare_grid takes them. */
static uint32_t grid_models(const co_report *r, const lm_mesh *models[CO_REPORT_MAX_MODELS])
{
    for (uint32_t i = 1; i < r->n_models; i++)
        models[i - 1] = r->model[i].mesh;
    return r->n_models - 1;
}

static lm_status contact_sheet(co_report *r)
{
    lm_view_set *vs = NULL;
    lm_image *grid = NULL;
    const lm_mesh *models[CO_REPORT_MAX_MODELS] = {0};
    uint32_t n = grid_models(r, models);
    lm_status s = sheet_views(r, r->size, &vs);
    if (!s)
        s = co_compare_grid(r->model[0].mesh, vs, r->o->device, models, n, NULL, &grid);
    if (!s)
        s = add_difference(grid, r->size, r->size, CO_REPORT_SHEET_VIEWS, &r->sheet);
    lm_image_destroy(grid);
    free(vs);
    return s;
}

/* The model whose cracks the close-up shows: the initial if it has cracks, else the optimized;
 * of levels, the one with the most (the first of equals). */
static const co_report_model *cracked(const co_report *r)
{
    if (r->levels) {
        const co_report_model *most = NULL;
        for (uint32_t k = 1; k < r->n_models; k++)
            if (r->model[k].cov.cracks_px &&
                (!most || r->model[k].cov.cracks_px > most->cov.cracks_px))
                most = &r->model[k];
        return most;
    }
    const co_report_model *i = co_report_initial(r), *o = co_report_optimized(r);
    if (i && i->cov.cracks_px)
        return i;
    return o->cov.cracks_px ? o : NULL;
}

static lm_status closeup(co_report *r)
{
    const co_report_model *m = cracked(r);
    int zoom = CO_REPORT_ZOOM;
    while (zoom > 1 && r->size * zoom > LM_MAX_VIEW_SIZE)
        zoom--;
    if (!m || zoom < 2)
        return LM_OK;
    lm_view_set *vs = NULL;
    lm_image *grid = NULL;
    const lm_mesh *models[CO_REPORT_MAX_MODELS] = {0};
    uint32_t n = grid_models(r, models);
    lm_status s = sheet_views(r, r->size * zoom, &vs);
    if (!s)
        s = co_compare_find_cracks(r->model[0].mesh, vs, r->o->device, m->mesh, r->size, &r->crop,
                                   &r->crop_cracks);
    if (!s && r->crop_cracks)
        s = co_compare_grid(r->model[0].mesh, vs, r->o->device, models, n, &r->crop, &grid);
    if (!s && grid)
        s = add_difference(grid, r->size, r->size, 1, &r->closeup);
    if (!s && grid) {
        r->closeup_of = m;
        r->zoom = zoom;
    }
    lm_image_destroy(grid);
    free(vs);
    return s;
}

lm_status co_report_pictures(co_report *r)
{
    lm_status s = contact_sheet(r);
    return s ? s : closeup(r);
}
