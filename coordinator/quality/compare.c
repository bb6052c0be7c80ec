/* coordinator/quality/compare.c — energies, silhouette coverage, image grids (whole views or a
 * close-up window) of models against an original, and the search for a model's worst cracks. */
#include "coordinator/quality/compare.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/patch.h"
#include "coordinator/views/views.h"

/* Views of the original over `views` on `device`, with no current mesh yet. */
static lm_status original_views(const lm_mesh *original, const lm_view_set *views,
                                const char *device, lm_views **out)
{
    co_views_desc d = {.original = original, .views = views, .device = device};
    return co_views_create(&d, out);
}

/* Make `m` (with its own materials) the current mesh of the views. The previous model goes first:
 * its triangles may use materials that m has not. */
static lm_status set_model(lm_views *views, const lm_mesh *m)
{
    const lm_tri_data none = {0};
    lm_status st = views->ops->set_mesh(views, &none, 0);
    if (st == LM_OK)
        st = views->ops->set_materials(views, m->materials, m->n_materials);
    return st == LM_OK ? lm_views_set_mesh_from(views, m) : st;
}

/* Energy (total and per view, which may be NULL) and, where depth images exist, coverage of the
 * mesh set in v against the original's masks `om`. */
static lm_status judge_model(lm_views *v, const uint8_t *om, int64_t *energy, int64_t *per_view,
                             co_coverage *cov)
{
    lm_status st = v->ops->energy(v, energy, per_view);
    if (st != LM_OK || !cov || !om)
        return st;
    uint8_t *mm = NULL;
    st = co_coverage_masks(v, &mm);
    lm_views_info info;
    v->ops->info(v, &info);
    if (st == LM_OK)
        st = co_coverage_compare(om, mm, info.width, info.height, info.n_views, cov);
    free(mm);
    return st;
}

lm_status co_compare_energies(const lm_mesh *original, const lm_view_set *views,
                              const char *device_spec, const lm_mesh *const *models, uint32_t n,
                              int64_t *energy, int64_t *per_view, co_coverage *cov, char *renderer)
{
    lm_views *v = NULL;
    uint8_t *om = NULL;
    if (cov)
        memset(cov, 0, n * sizeof *cov);
    lm_status st = original_views(original, views, device_spec, &v);
    if (st == LM_OK && cov && co_coverage_masks(v, &om) != LM_OK)
        lm_clear_error(); /* no depth images on this device: energies only */
    for (uint32_t i = 0; st == LM_OK && i < n; i++) {
        st = set_model(v, models[i]);
        if (st == LM_OK)
            st = judge_model(v, om, &energy[i],
                             per_view ? per_view + (size_t)i * views->count : NULL,
                             cov ? &cov[i] : NULL);
    }
    if (st == LM_OK && renderer) {
        lm_views_info info;
        v->ops->info(v, &info);
        snprintf(renderer, 128, "%s", info.renderer);
    }
    free(om);
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
        st = views->ops->read_image(views, LM_IMAGE_COVERAGE, i, m + plane * i);
    if (st != LM_OK) {
        free(m);
        return st;
    }
    *masks = m;
    return LM_OK;
}

int co_crack_margin(int width)
{
    return width / 128 > 2 ? width / 128 : 2;
}

void co_coverage_print_json(FILE *fp, const co_coverage *c)
{
    if (!c->measured) {
        fputs("null", fp);
        return;
    }
    fprintf(
        fp,
        "{\"original_px\": %llu, \"missing_px\": %llu, \"extra_px\": %llu, \"cracks_px\": %llu}",
        (unsigned long long)c->original_px, (unsigned long long)c->missing_px,
        (unsigned long long)c->extra_px, (unsigned long long)c->cracks_px);
}

/* Summed-area table of a w x h byte plane: sat is (w + 1) x (h + 1), zero first row and column. */
static void sat_build(const uint8_t *plane, int w, int h, uint32_t *sat)
{
    size_t W = (size_t)w + 1;
    memset(sat, 0, W * sizeof *sat);
    for (int y = 1; y <= h; y++) {
        uint32_t *row = sat + (size_t)y * W;
        row[0] = 0;
        for (int x = 1; x <= w; x++)
            row[x] = plane[(size_t)(y - 1) * (size_t)w + (size_t)(x - 1)] + row[x - 1] +
                     row[x - W] - row[x - 1 - W];
    }
}

/* Sum of the plane over [x0, x0 + s) x [y0, y0 + s) (inside the image). */
static uint32_t sat_box(const uint32_t *sat, int w, int x0, int y0, int s)
{
    size_t W = (size_t)w + 1;
    const uint32_t *lo = sat + (size_t)y0 * W + (size_t)x0, *hi = lo + (size_t)s * W;
    return hi[s] - hi[0] - lo[s] + lo[0];
}

/* cracks[i] = 1 where the original is covered, the model is not, and the original has no
 * background within `margin` pixels (nor the image border). bg is a scratch plane, sat a table. */
static void crack_plane(const uint8_t *om, const uint8_t *mm, int w, int h, int margin, uint8_t *bg,
                        uint32_t *sat, uint8_t *cracks)
{
    size_t n = (size_t)w * (size_t)h;
    for (size_t i = 0; i < n; i++)
        bg[i] = !om[i];
    sat_build(bg, w, h, sat);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            int inside = x >= margin && y >= margin && x + margin < w && y + margin < h;
            cracks[i] = om[i] && !mm[i] && inside &&
                        sat_box(sat, w, x - margin, y - margin, 2 * margin + 1) == 0;
        }
}

lm_status co_coverage_compare(const uint8_t *original, const uint8_t *model, int w, int h,
                              uint32_t views, co_coverage *out)
{
    size_t plane = (size_t)w * (size_t)h;
    uint8_t *bg = malloc(plane * 2);
    uint32_t *sat = malloc(((size_t)w + 1) * ((size_t)h + 1) * sizeof *sat);
    memset(out, 0, sizeof *out);
    if (!bg || !sat) {
        free(bg);
        free(sat);
        return lm_fail(LM_E_NOMEM, "out of memory comparing coverage");
    }
    out->measured = 1;
    for (uint32_t v = 0; v < views; v++) {
        const uint8_t *om = original + plane * v, *mm = model + plane * v;
        crack_plane(om, mm, w, h, co_crack_margin(w), bg, sat, bg + plane);
        for (size_t i = 0; i < plane; i++) {
            out->original_px += om[i];
            out->missing_px += om[i] && !mm[i];
            out->extra_px += !om[i] && mm[i];
            out->cracks_px += bg[plane + i];
        }
    }
    free(bg);
    free(sat);
    return LM_OK;
}

/* Copy window c of a bottom-row-first RGBA view image (w x h) into cell (row, col) of the grid
 * (top row first; cells are c->w x c->h). */
static void blit(lm_image *grid, const uint8_t *rgba, int w, int h, const co_crop *c, int row,
                 int col)
{
    int x0 = col * (c->w + CO_COMPARE_GAP), y0 = row * (c->h + CO_COMPARE_GAP);
    for (int y = 0; y < c->h; y++) {
        const uint8_t *src = rgba + ((size_t)(h - 1 - (c->y + y)) * (size_t)w + (size_t)c->x) * 4;
        uint8_t *dst = grid->pixels + ((size_t)(y0 + y) * (size_t)grid->width + (size_t)x0) * 4;
        memcpy(dst, src, (size_t)c->w * 4);
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

/* The rows of a grid: every view whole, or the single crop. */
typedef struct grid_rows {
    uint32_t count;
    const co_crop *crop; /* NULL: whole views */
    int w, h;            /* image side */
} grid_rows;

/* Column `col` of the grid from the current render. */
static lm_status fill_column(lm_views *v, lm_image *grid, uint8_t *buf, const grid_rows *r, int col)
{
    for (uint32_t i = 0; i < r->count; i++) {
        co_crop whole = {i, 0, 0, r->w, r->h};
        const co_crop *c = r->crop ? r->crop : &whole;
        lm_status st = v->ops->read_image(v, LM_IMAGE_RGBA, c->view, buf);
        if (st != LM_OK)
            return st;
        blit(grid, buf, r->w, r->h, c, (int)i, col);
    }
    return LM_OK;
}

static lm_status check_crop(const lm_view_set *views, const co_crop *c)
{
    int w = views->views[0].width, h = views->views[0].height;
    if (c->view >= views->count || c->x < 0 || c->y < 0 || c->w < 1 || c->h < 1 ||
        c->x > w - c->w || c->y > h - c->h)
        return lm_fail(LM_E_RANGE,
                       "close-up window %dx%d at (%d, %d) of view %u is outside the "
                       "%u views of %dx%d",
                       c->w, c->h, c->x, c->y, c->view, views->count, w, h);
    return LM_OK;
}

lm_status co_compare_grid(const lm_mesh *original, const lm_view_set *views,
                          const char *device_spec, const lm_mesh *const *models, uint32_t n,
                          const co_crop *crop, lm_image **out)
{
    *out = NULL;
    if (views->count == 0)
        return lm_fail(LM_E_INVALID, "a comparison grid needs at least one view");
    if (crop && check_crop(views, crop) != LM_OK)
        return LM_E_RANGE;
    grid_rows r = {crop ? 1 : views->count, crop, views->views[0].width, views->views[0].height};
    lm_image *grid = make_canvas(crop ? crop->w : r.w, crop ? crop->h : r.h, r.count, n + 1);
    uint8_t *buf = malloc((size_t)r.w * (size_t)r.h * 4);
    lm_views *v = NULL;
    lm_status st = grid && buf ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for the image grid");
    if (st == LM_OK)
        st = original_views(original, views, device_spec, &v);
    if (st == LM_OK)
        st = fill_column(v, grid, buf, &r, 0);
    for (uint32_t m = 0; st == LM_OK && m < n; m++) {
        st = set_model(v, models[m]);
        if (st == LM_OK)
            st = fill_column(v, grid, buf, &r, (int)m + 1);
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

/* Best side x side window of a plane (bottom row first): its count, and *c (top-down y). */
static uint64_t best_window(const uint8_t *plane, int w, int h, int side, uint32_t *sat, co_crop *c)
{
    sat_build(plane, w, h, sat);
    uint64_t best = 0;
    for (int y = 0; y + side <= h; y++)
        for (int x = 0; x + side <= w; x++) {
            uint32_t n = sat_box(sat, w, x, y, side);
            if (n > best)
                best = n, c->x = x, c->y = h - y - side;
        }
    return best;
}

/* The window over all views with the most crack pixels of the model (masks om, mm). */
static lm_status worst_window(const uint8_t *om, const uint8_t *mm, uint32_t views, int w, int h,
                              int side, co_crop *out, uint64_t *cracks)
{
    size_t plane = (size_t)w * (size_t)h;
    uint8_t *scratch = malloc(plane * 2);
    uint32_t *sat = malloc(((size_t)w + 1) * ((size_t)h + 1) * sizeof *sat);
    if (!scratch || !sat) {
        free(scratch);
        free(sat);
        return lm_fail(LM_E_NOMEM, "out of memory for the crack search");
    }
    *out = (co_crop){0, 0, 0, side, side};
    *cracks = 0;
    for (uint32_t i = 0; i < views; i++) {
        crack_plane(om + plane * i, mm + plane * i, w, h, co_crack_margin(w), scratch, sat,
                    scratch + plane);
        co_crop c = {i, 0, 0, side, side};
        uint64_t n = best_window(scratch + plane, w, h, side, sat, &c);
        if (n > *cracks)
            *cracks = n, *out = c;
    }
    free(scratch);
    free(sat);
    return LM_OK;
}

lm_status co_compare_find_cracks(const lm_mesh *original, const lm_view_set *views,
                                 const char *device_spec, const lm_mesh *model, int side,
                                 co_crop *out, uint64_t *cracks)
{
    int w = views->views[0].width, h = views->views[0].height;
    if (side < 1 || side > w || side > h)
        return lm_fail(LM_E_RANGE, "a close-up of %d pixels does not fit views of %dx%d", side, w,
                       h);
    lm_views *v = NULL;
    uint8_t *om = NULL, *mm = NULL;
    lm_status st = original_views(original, views, device_spec, &v);
    if (st == LM_OK)
        st = co_coverage_masks(v, &om);
    if (st == LM_OK)
        st = set_model(v, model);
    if (st == LM_OK)
        st = co_coverage_masks(v, &mm);
    if (st == LM_OK)
        st = worst_window(om, mm, views->count, w, h, side, out, cracks);
    free(om);
    free(mm);
    lm_views_destroy(v);
    return st;
}
