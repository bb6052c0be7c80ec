/* coordinator/simplify/footprint.c — per-view bounding rectangles of changes and their overlap. */
#include "coordinator/simplify/footprint.h"

#include <math.h>

#define CO_FP_FAR 1000000 /* "the whole plane", and the clamp of projected coordinates */

void co_fp_clear(co_rect *fp, uint32_t n)
{
    for (uint32_t h = 0; h < n; h++)
        fp[h] = (co_rect){1, 1, 0, 0};
}

static int32_t clamp_px(double x)
{
    return x < -CO_FP_FAR ? -CO_FP_FAR : x > CO_FP_FAR ? CO_FP_FAR : (int32_t)x;
}

static void grow(co_rect *r, int32_t x0, int32_t y0, int32_t x1, int32_t y1)
{
    if (r->x0 > r->x1) {
        *r = (co_rect){x0, y0, x1, y1};
        return;
    }
    r->x0 = x0 < r->x0 ? x0 : r->x0;
    r->y0 = y0 < r->y0 ? y0 : r->y0;
    r->x1 = x1 > r->x1 ? x1 : r->x1;
    r->y1 = y1 > r->y1 ? y1 : r->y1;
}

void co_fp_grow_box(co_rect *r, const float lo[2], const float hi[2])
{
    grow(r, clamp_px(floor(lo[0])) - 1, clamp_px(floor(lo[1])) - 1, clamp_px(ceil(hi[0])) + 1,
         clamp_px(ceil(hi[1])) + 1);
}

void co_fp_grow_plane(co_rect *r)
{
    grow(r, -CO_FP_FAR, -CO_FP_FAR, CO_FP_FAR, CO_FP_FAR);
}

int co_fp_project(const lm_view *v, const float pos[3], float win[2])
{
    return lm_view_project(v, pos, win, NULL) && isfinite(win[0]) && isfinite(win[1]);
}

void co_fp_add_tri(co_rect *fp, const lm_view_set *vs, const lm_tri_data *t)
{
    for (uint32_t h = 0; h < vs->count; h++) {
        float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        int all = 1;
        for (int k = 0; k < 3 && all; k++) {
            float win[2];
            all = co_fp_project(&vs->views[h], t->c[k].pos, win);
            for (int d = 0; d < 2 && all; d++) {
                lo[d] = win[d] < lo[d] ? win[d] : lo[d];
                hi[d] = win[d] > hi[d] ? win[d] : hi[d];
            }
        }
        if (!all)
            co_fp_grow_plane(&fp[h]);
        else
            co_fp_grow_box(&fp[h], lo, hi);
    }
}

void co_fp_union(co_rect *a, const co_rect *b, uint32_t n)
{
    for (uint32_t h = 0; h < n; h++)
        if (b[h].x0 <= b[h].x1)
            grow(&a[h], b[h].x0, b[h].y0, b[h].x1, b[h].y1);
}

int co_fp_meet(const co_rect *a, const co_rect *b, uint32_t n)
{
    for (uint32_t h = 0; h < n; h++)
        if (a[h].x0 <= a[h].x1 && b[h].x0 <= b[h].x1 && a[h].x0 <= b[h].x1 && b[h].x0 <= a[h].x1 &&
            a[h].y0 <= b[h].y1 && b[h].y0 <= a[h].y1)
            return 1;
    return 0;
}
