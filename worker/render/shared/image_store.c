/* worker/render/shared/image_store.c — target and current luminance images per view, exact int64
 * energies, region ΔE and commit, and the oracle's box-blurred squared-difference images (integer
 * sums). */
#include "worker/render/shared/image_store.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct wk_image_store {
    uint32_t n_views;
    int width, height;
    size_t plane; /* width * height */
    uint8_t *target;
    uint8_t *current;
    int64_t *energy;  /* [n_views] */
    float *depth;     /* [n_views * plane] or NULL */
    float *depth_max; /* [n_views * tiles] the greatest depth of each DEPTH_TILE² tile, or NULL */
    int tiles_w, tiles_h;
    uint32_t *depth_version; /* [n_views] changes whenever the view's depth image does */
};

/* Side of the tiles whose greatest depth is kept: a footprint's rows whose tiles all lie nearer
 * than its nearest corner are hidden without looking at their pixels. */
#define DEPTH_TILE 8

void wk_luma_from_rgba(const uint8_t *rgba, size_t n_pixels, uint8_t *out)
{
    for (size_t i = 0; i < n_pixels; i++)
        out[i] = lm_luma(rgba + 4 * i);
}

lm_status wk_image_store_create(uint32_t n_views, int width, int height, wk_image_store **out)
{
    if (n_views < 1 || n_views > 4096 || width < 1 || height < 1 || width > 16384 || height > 16384)
        return lm_fail(LM_E_RANGE, "image store of %u views of %dx%d is out of range", n_views,
                       width, height);
    wk_image_store *s = calloc(1, sizeof *s);
    if (!s)
        return lm_fail(LM_E_NOMEM, "out of memory creating the image store");
    s->n_views = n_views;
    s->width = width;
    s->height = height;
    s->plane = (size_t)width * height;
    s->target = calloc(n_views, s->plane);
    s->current = calloc(n_views, s->plane);
    s->energy = calloc(n_views, sizeof *s->energy);
    if (!s->target || !s->current || !s->energy) {
        wk_image_store_destroy(s);
        return lm_fail(LM_E_NOMEM, "out of memory for %u images of %dx%d", n_views, width, height);
    }
    *out = s;
    return LM_OK;
}

void wk_image_store_destroy(wk_image_store *s)
{
    if (!s)
        return;
    free(s->target);
    free(s->current);
    free(s->energy);
    free(s->depth);
    free(s->depth_max);
    free(s->depth_version);
    free(s);
}

int64_t wk_image_store_energy_recompute(const wk_image_store *s, uint32_t view)
{
    LM_ASSERT(view < s->n_views);
    const uint8_t *t = s->target + view * s->plane, *y = s->current + view * s->plane;
    int64_t e = 0;
    for (size_t i = 0; i < s->plane; i++) {
        int d = (int)t[i] - (int)y[i];
        e += d * d;
    }
    return e;
}

void wk_image_store_set_target(wk_image_store *s, uint32_t view, const uint8_t *y)
{
    LM_ASSERT(view < s->n_views);
    memcpy(s->target + view * s->plane, y, s->plane);
    s->energy[view] = wk_image_store_energy_recompute(s, view);
}

void wk_image_store_set_current(wk_image_store *s, uint32_t view, const uint8_t *y)
{
    LM_ASSERT(view < s->n_views);
    memcpy(s->current + view * s->plane, y, s->plane);
    s->energy[view] = wk_image_store_energy_recompute(s, view);
}

const uint8_t *wk_image_store_target(const wk_image_store *s, uint32_t view)
{
    LM_ASSERT(view < s->n_views);
    return s->target + view * s->plane;
}

const uint8_t *wk_image_store_current(const wk_image_store *s, uint32_t view)
{
    LM_ASSERT(view < s->n_views);
    return s->current + view * s->plane;
}

static void check_region(const wk_image_store *s, uint32_t view, const wk_rect *r)
{
    LM_ASSERT(view < s->n_views);
    LM_ASSERT(r->x0 >= 0 && r->y0 >= 0 && r->x1 <= s->width && r->y1 <= s->height);
}

int64_t wk_image_store_region_delta(const wk_image_store *s, uint32_t view, const wk_rect *r,
                                    const uint8_t *region)
{
    check_region(s, view, r);
    if (wk_rect_empty(r))
        return 0;
    int rw = r->x1 - r->x0;
    int64_t delta = 0;
    for (int y = r->y0; y < r->y1; y++) {
        size_t row = view * s->plane + (size_t)y * s->width + r->x0;
        const uint8_t *t = s->target + row, *cur = s->current + row;
        const uint8_t *nw = region + (size_t)(y - r->y0) * rw;
        int32_t acc = 0; /* |row| <= 4096 pixels * 65025 fits in 32 bits */
        for (int x = 0; x < rw; x++) {
            int a = (int)t[x] - (int)nw[x], b = (int)t[x] - (int)cur[x];
            acc += a * a - b * b;
        }
        delta += acc;
    }
    return delta;
}

void wk_image_store_commit_region(wk_image_store *s, uint32_t view, const wk_rect *r,
                                  const uint8_t *region)
{
    if (wk_rect_empty(r))
        return;
    s->energy[view] += wk_image_store_region_delta(s, view, r, region);
    int rw = r->x1 - r->x0;
    for (int y = r->y0; y < r->y1; y++)
        memcpy(s->current + view * s->plane + (size_t)y * s->width + r->x0,
               region + (size_t)(y - r->y0) * rw, (size_t)rw);
}

void wk_image_store_commit_pixels(wk_image_store *s, uint32_t view, const uint32_t *idx,
                                  const uint8_t *y, size_t n)
{
    LM_ASSERT(view < s->n_views);
    const uint8_t *t = s->target + view * s->plane;
    uint8_t *cur = s->current + view * s->plane;
    int64_t delta = 0;
    for (size_t i = 0; i < n; i++) {
        LM_ASSERT(idx[i] < s->plane);
        int a = (int)t[idx[i]] - (int)y[i], b = (int)t[idx[i]] - (int)cur[idx[i]];
        delta += a * a - b * b;
        cur[idx[i]] = y[i];
    }
    s->energy[view] += delta;
}

void wk_image_store_energies(const wk_image_store *s, int64_t *total, int64_t *per_view)
{
    int64_t sum = 0;
    for (uint32_t h = 0; h < s->n_views; h++) {
        if (per_view)
            per_view[h] = s->energy[h];
        sum += s->energy[h];
    }
    if (total)
        *total = sum;
}

int64_t wk_image_store_energy(const wk_image_store *s, uint32_t view)
{
    LM_ASSERT(view < s->n_views);
    return s->energy[view];
}

/* One direction of a separable box sum: out[i] = Σ_{|k| <= r} in[i + k*step], clipped to n. */
static void box_line(const uint32_t *in, uint32_t *out, int n, size_t step, int r)
{
    uint32_t acc = 0;
    for (int i = 0; i < r && i < n; i++)
        acc += in[(size_t)i * step];
    for (int i = 0; i < n; i++) {
        if (i + r < n)
            acc += in[(size_t)(i + r) * step];
        if (i - r - 1 >= 0)
            acc -= in[(size_t)(i - r - 1) * step];
        out[(size_t)i * step] = acc;
    }
}

lm_status wk_image_store_blurred_diff(const wk_image_store *s, uint32_t view, int radius,
                                      uint32_t *out)
{
    LM_ASSERT(view < s->n_views);
    if (radius < 0 || radius > 64)
        return lm_fail(LM_E_RANGE, "blur radius %d is outside 0..64", radius);
    uint32_t *tmp = malloc(s->plane * sizeof *tmp);
    if (!tmp)
        return lm_fail(LM_E_NOMEM, "out of memory blurring a %dx%d image", s->width, s->height);
    const uint8_t *t = s->target + view * s->plane, *y = s->current + view * s->plane;
    for (size_t i = 0; i < s->plane; i++) {
        int d = (int)t[i] - (int)y[i];
        out[i] = (uint32_t)(d * d);
    }
    for (int row = 0; row < s->height; row++)
        box_line(out + (size_t)row * s->width, tmp + (size_t)row * s->width, s->width, 1, radius);
    for (int col = 0; col < s->width; col++)
        box_line(tmp + col, out + col, s->height, (size_t)s->width, radius);
    free(tmp);
    return LM_OK;
}

lm_status wk_image_store_enable_depth(wk_image_store *s)
{
    if (s->depth)
        return LM_OK;
    s->tiles_w = (s->width + DEPTH_TILE - 1) / DEPTH_TILE;
    s->tiles_h = (s->height + DEPTH_TILE - 1) / DEPTH_TILE;
    size_t tiles = (size_t)s->tiles_w * (size_t)s->tiles_h;
    s->depth = malloc(s->n_views * s->plane * sizeof *s->depth);
    s->depth_max = malloc(s->n_views * tiles * sizeof *s->depth_max);
    s->depth_version = calloc(s->n_views, sizeof *s->depth_version);
    if (!s->depth || !s->depth_max || !s->depth_version) {
        free(s->depth);
        free(s->depth_max);
        free(s->depth_version);
        s->depth = s->depth_max = NULL;
        s->depth_version = NULL;
        return lm_fail(LM_E_NOMEM, "out of memory for %u depth images", s->n_views);
    }
    for (size_t i = 0; i < s->n_views * s->plane; i++)
        s->depth[i] = 1.0f;
    for (size_t i = 0; i < s->n_views * tiles; i++)
        s->depth_max[i] = 1.0f;
    return LM_OK;
}

/* Recompute the tile maxima of view over the tiles that r touches. */
static void depth_max_update(wk_image_store *s, uint32_t view, const wk_rect *r)
{
    const float *z = s->depth + view * s->plane;
    float *t = s->depth_max + view * (size_t)s->tiles_w * s->tiles_h;
    s->depth_version[view]++;
    for (int ty = r->y0 / DEPTH_TILE; ty * DEPTH_TILE < r->y1; ty++) {
        int y1 = (ty + 1) * DEPTH_TILE < s->height ? (ty + 1) * DEPTH_TILE : s->height;
        for (int tx = r->x0 / DEPTH_TILE; tx * DEPTH_TILE < r->x1; tx++) {
            int x1 = (tx + 1) * DEPTH_TILE < s->width ? (tx + 1) * DEPTH_TILE : s->width;
            float m = -INFINITY;
            int nan = 0;
            for (int y = ty * DEPTH_TILE; y < y1; y++)
                for (int x = tx * DEPTH_TILE; x < x1; x++) {
                    float v = z[(size_t)y * s->width + x];
                    m = v > m ? v : m;
                    nan |= v != v;
                }
            t[(size_t)ty * s->tiles_w + tx] = nan ? INFINITY : m; /* NaN is never "in front" */
        }
    }
}

/* At row y of r (its first row or the first of a tile row): the last row of y's tile row within
 * r when every pixel there lies nearer than limit by the tile maxima (those rows are hidden),
 * else y - 1. */
static int rows_in_front(const wk_image_store *s, uint32_t view, const wk_rect *r, int y,
                         float limit)
{
    if (y != r->y0 && y % DEPTH_TILE != 0)
        return y - 1;
    int ty = y / DEPTH_TILE, next = (ty + 1) * DEPTH_TILE;
    const float *t = s->depth_max + (view * (size_t)s->tiles_h + ty) * s->tiles_w;
    for (int tx = r->x0 / DEPTH_TILE; tx * DEPTH_TILE < r->x1; tx++)
        if (!(t[tx] < limit))
            return y - 1;
    return (next < r->y1 ? next : r->y1) - 1;
}

int wk_image_store_has_depth(const wk_image_store *s)
{
    return s->depth != NULL;
}

void wk_image_store_set_depth(wk_image_store *s, uint32_t view, const float *z)
{
    LM_ASSERT(view < s->n_views && s->depth);
    memcpy(s->depth + view * s->plane, z, s->plane * sizeof *z);
    const wk_rect whole = {0, 0, s->width, s->height};
    depth_max_update(s, view, &whole);
}

void wk_image_store_commit_depth(wk_image_store *s, uint32_t view, const wk_rect *r,
                                 const float *region)
{
    check_region(s, view, r);
    LM_ASSERT(s->depth);
    int rw = r->x1 - r->x0;
    for (int y = r->y0; y < r->y1; y++)
        memcpy(s->depth + view * s->plane + (size_t)y * s->width + r->x0,
               region + (size_t)(y - r->y0) * rw, (size_t)rw * sizeof *region);
    if (!wk_rect_empty(r))
        depth_max_update(s, view, r);
}

uint32_t wk_image_store_depth_version(const wk_image_store *s, uint32_t view)
{
    LM_ASSERT(view < s->n_views);
    return s->depth_version ? s->depth_version[view] : 0;
}

int wk_image_store_hidden(const wk_image_store *s, uint32_t view, const wk_rect *r, float zmin,
                          float eps)
{
    check_region(s, view, r);
    if (!s->depth || !(zmin - eps > 0.0f))
        return 0;
    float limit = zmin - eps;
    for (int y = r->y0; y < r->y1; y++) {
        int last = rows_in_front(s, view, r, y, limit);
        if (last >= y) {
            y = last; /* rows y..last are hidden */
            continue;
        }
        const float *row = s->depth + view * s->plane + (size_t)y * s->width;
        for (int x = r->x0; x < r->x1; x++)
            if (!(row[x] < limit))
                return 0;
    }
    return 1;
}

/* One edge a->b of a projected triangle as a bound on the columns of row y whose pixel centres,
 * widened by WK_PIXEL_SLACK, meet the inside of the edge (inside where s * cross(b - a, p - a)
 * >= 0), with a pixel of extra slack for rounding. The bound is linear in y, x(y) = m * y + q:
 * a lower one (columns >= ceil(x) - 1), an upper one (columns <= floor(x) + 1), or, for a
 * horizontal edge, rows where B * y + q < 0 lie wholly outside. */
typedef struct edge_bound {
    int kind; /* 1 lower, -1 upper, 0 horizontal */
    double m, q;
} edge_bound;

static edge_bound edge_bound_make(const float *a, const float *b, float s)
{
    const double d = WK_PIXEL_SLACK;
    double A = -s * ((double)b[1] - a[1]), B = s * ((double)b[0] - a[0]);
    double py = B > 0 ? 0.5 + d : 0.5 - d; /* pixel row y is tested at y + py */
    double C = B * (py - a[1]) - A * a[0]; /* E(px, y) = A * px + B * y + C */
    if (A > 0)
        return (edge_bound){1, -B / A, -C / A - 0.5 - d}; /* px = x + 0.5 + d */
    if (A < 0)
        return (edge_bound){-1, -B / A, -C / A - 0.5 + d}; /* px = x + 0.5 - d */
    return (edge_bound){0, B, C};
}

/* ceil and floor of v clamped to +-1e9 (an edge nearly along the row gives huge values). */
static int ceil_clamped(double v)
{
    v = v < -1e9 ? -1e9 : v > 1e9 ? 1e9 : v;
    int i = (int)v;
    return i + (v > i);
}

static int floor_clamped(double v)
{
    v = v < -1e9 ? -1e9 : v > 1e9 ? 1e9 : v;
    int i = (int)v;
    return i - (v < i);
}

static void edge_span(const edge_bound *e, int y, int *lo, int *hi)
{
    double x = e->m * y + e->q;
    if (e->kind > 0) {
        int xl = ceil_clamped(x) - 1;
        *lo = xl > *lo ? xl : *lo;
    } else if (e->kind < 0) {
        int xh = floor_clamped(x) + 1;
        *hi = xh < *hi ? xh : *hi;
    } else if (x < 0) {
        *hi = *lo - 1; /* the whole row is outside */
    }
}

int wk_image_store_hidden_tri(const wk_image_store *s, uint32_t view, const wk_footprint *f,
                              float eps)
{
    return wk_image_store_hidden_tri_in(s, view, f, &f->rect, eps);
}

int wk_image_store_hidden_tri_in(const wk_image_store *s, uint32_t view, const wk_footprint *f,
                                 const wk_rect *clip, float eps)
{
    return wk_image_store_hidden_tri_witness(s, view, f, clip, eps, NULL);
}

int wk_image_store_hidden_tri_witness(const wk_image_store *s, uint32_t view, const wk_footprint *f,
                                      const wk_rect *clip, float eps, int witness[2])
{
    if (witness)
        witness[0] = witness[1] = -1;
    wk_rect c = wk_rect_intersect(&f->rect, clip), *r = &c;
    if (wk_rect_empty(r))
        return 1; /* no pixel of clip */
    if (!f->projected)
        return wk_image_store_hidden(s, view, r, f->zmin, eps);
    check_region(s, view, r);
    if (!s->depth || !(f->zmin - eps > 0.0f))
        return 0;
    const float(*w)[2] = f->win;
    double area = ((double)w[1][0] - w[0][0]) * ((double)w[2][1] - w[0][1]) -
                  ((double)w[1][1] - w[0][1]) * ((double)w[2][0] - w[0][0]);
    if (!(fabs(area) > 1e-3))
        return wk_image_store_hidden(s, view, r, f->zmin, eps);
    float sg = area > 0 ? 1.0f : -1.0f, limit = f->zmin - eps;
    edge_bound e[3];
    int edges = 0; /* set up on the first rows that need them */
    for (int y = r->y0; y < r->y1; y++) {
        int last = rows_in_front(s, view, r, y, limit);
        if (last >= y) {
            y = last; /* rows y..last are hidden */
            continue;
        }
        if (!edges) {
            for (int k = 0; k < 3; k++)
                e[k] = edge_bound_make(w[k], w[(k + 1) % 3], sg);
            edges = 1;
        }
        int lo = r->x0, hi = r->x1 - 1;
        for (int k = 0; k < 3 && lo <= hi; k++)
            edge_span(&e[k], y, &lo, &hi);
        const float *row = s->depth + view * s->plane + (size_t)y * s->width;
        for (int x = lo; x <= hi; x++)
            if (!(row[x] < limit)) {
                if (witness)
                    witness[0] = x, witness[1] = y;
                return 0;
            }
    }
    return 1;
}

lm_status wk_image_store_potentials(const wk_image_store *s, const lm_view_set *views, int radius,
                                    const float (*points)[3], size_t n, int64_t *out)
{
    LM_ASSERT(views->count == s->n_views);
    uint32_t *blur = malloc(s->plane * sizeof *blur);
    if (!blur)
        return lm_fail(LM_E_NOMEM, "out of memory for the oracle's images");
    memset(out, 0, n * sizeof *out);
    lm_status st = LM_OK;
    for (uint32_t h = 0; st == LM_OK && h < s->n_views; h++) {
        st = wk_image_store_blurred_diff(s, h, radius, blur);
        for (size_t i = 0; st == LM_OK && i < n; i++) {
            float win[2];
            if (!lm_view_project(&views->views[h], points[i], win, NULL))
                continue;
            if (!(win[0] >= 0 && win[0] < s->width && win[1] >= 0 && win[1] < s->height))
                continue;
            out[i] += blur[(size_t)win[1] * s->width + (size_t)win[0]];
        }
    }
    free(blur);
    return st;
}
