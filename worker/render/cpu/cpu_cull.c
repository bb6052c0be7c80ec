/* worker/render/cpu/cpu_cull.c — the box of a patch's corners against a view's depth tiles (see
 * cpu_cull.h). Double precision in a fixed order, as the triangle setup. */
#include "worker/render/cpu/cpu_cull.h"

#include <math.h>

void wk_cpu_box_clear(wk_cpu_box *b)
{
    b->empty = 1;
}

void wk_cpu_box_add(wk_cpu_box *b, const lm_tri_data *t)
{
    for (int k = 0; k < 3; k++) {
        for (int a = 0; a < 3; a++) {
            double x = t->c[k].pos[a];
            double lo = isfinite(x) ? x : -INFINITY, hi = isfinite(x) ? x : INFINITY;
            b->lo[a] = b->empty || lo < b->lo[a] ? lo : b->lo[a];
            b->hi[a] = b->empty || hi > b->hi[a] ? hi : b->hi[a];
        }
        b->empty = 0;
    }
}

/* The window box and nearest depth of the box's corners; 0 unless all are well inside the depth
 * range (then no clipping is involved). */
static int project_box(const wk_cpu_box *b, const wk_cpu_view *v, double lo[2], double hi[2],
                       double *zmin)
{
    const double *m = v->m;
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    *zmin = INFINITY;
    for (int i = 0; i < 8; i++) {
        double p[3] = {i & 1 ? b->hi[0] : b->lo[0], i & 2 ? b->hi[1] : b->lo[1],
                       i & 4 ? b->hi[2] : b->lo[2]};
        double c[4];
        for (int r = 0; r < 4; r++)
            c[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
        if (!(c[3] > 0.0) || !(c[2] + c[3] > 0.0) || !(c[3] - c[2] > 0.0))
            return 0;
        double inv = 1.0 / c[3],
               win[2] = {(c[0] * inv * 0.5 + 0.5) * v->width, (c[1] * inv * 0.5 + 0.5) * v->height};
        for (int a = 0; a < 2; a++) {
            lo[a] = win[a] < lo[a] ? win[a] : lo[a];
            hi[a] = win[a] > hi[a] ? win[a] : hi[a];
        }
        double z = c[2] * inv * 0.5 + 0.5;
        *zmin = z < *zmin ? z : *zmin;
    }
    return isfinite(lo[0]) && isfinite(lo[1]) && isfinite(hi[0]) && isfinite(hi[1]);
}

int wk_cpu_box_hidden(const wk_cpu_box *b, const wk_cpu_view *v, const wk_cpu_keys *k)
{
    double lo[2], hi[2], zmin;
    if (b->empty)
        return 1;
    if (!k->tmax || !project_box(b, v, lo, hi, &zmin))
        return 0;
    /* pixels whose centres may be covered, with a pixel to spare for snapping */
    double x0 = floor(lo[0] - 1.0), y0 = floor(lo[1] - 1.0);
    double x1 = ceil(hi[0] + 1.0), y1 = ceil(hi[1] + 1.0);
    if (x1 <= 0 || y1 <= 0 || x0 >= v->width || y0 >= v->height)
        return 1; /* off the view */
    int tx0 = x0 > 0 ? (int)x0 / WK_CPU_TILE : 0, ty0 = y0 > 0 ? (int)y0 / WK_CPU_TILE : 0;
    int tx1 = (x1 < v->width ? (int)x1 : v->width - 1) / WK_CPU_TILE;
    int ty1 = (y1 < v->height ? (int)y1 : v->height - 1) / WK_CPU_TILE;
    uint64_t bound = wk_cpu_depth_bound(zmin);
    for (int ty = ty0; ty <= ty1; ty++)
        for (int tx = tx0; tx <= tx1; tx++)
            if (k->tmax[ty * k->tiles_w + tx] >= bound)
                return 0;
    return 1;
}
