/* worker/render/shared/buckets.c — triangle buckets of one view: per-triangle conservative screen
 * rectangles and a uniform grid of cells listing triangle ids, with time-stamped (deduplicating)
 * rectangle queries. A grid rather than the paper's per-row/per-column tables: one lookup per cell
 * instead of two unions and an intersection, and the candidate set is already the rectangle test's.
 */
#include "worker/render/shared/buckets.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

#define WK_BUCKET_DEFAULT_CELL 16

typedef struct wk_cell {
    uint32_t *ids;
    uint32_t n, cap;
} wk_cell;

struct wk_buckets {
    int width, height, cell, gw, gh;
    wk_cell *cells;   /* [gw * gh] */
    size_t cap_ids;   /* size of the per-id arrays below */
    wk_footprint *fp; /* [cap_ids] footprint of each present triangle */
    uint8_t *present;
    uint32_t *stamp; /* last query that met each id */
    uint32_t now;    /* current query stamp */
};

void wk_rect_union(wk_rect *r, const wk_rect *s)
{
    if (wk_rect_empty(s))
        return;
    if (wk_rect_empty(r)) {
        *r = *s;
        return;
    }
    r->x0 = s->x0 < r->x0 ? s->x0 : r->x0;
    r->y0 = s->y0 < r->y0 ? s->y0 : r->y0;
    r->x1 = s->x1 > r->x1 ? s->x1 : r->x1;
    r->y1 = s->y1 > r->y1 ? s->y1 : r->y1;
}

static int clamp_coord(double x, int hi)
{
    if (x < 0)
        return 0;
    if (x > hi)
        return hi;
    return (int)x;
}

/* Window depth of p (0 at the near plane, 1 at the far plane) given its clip w. */
static float window_depth(const lm_view *v, const float p[3], float w)
{
    const float *m = v->view_proj;
    float z = m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14];
    return z / w * 0.5f + 0.5f;
}

/* Widen [zmin, zmax] by the depth plane's greatest change over WK_DEPTH_REACH in x and y
 * (unbounded when the projected triangle has no area). */
static void widen_depths(const float (*win)[2], const float z[3], wk_footprint *out)
{
    double ex1 = (double)win[1][0] - win[0][0], ey1 = (double)win[1][1] - win[0][1];
    double ex2 = (double)win[2][0] - win[0][0], ey2 = (double)win[2][1] - win[0][1];
    double area2 = ex1 * ey2 - ey1 * ex2, dz1 = (double)z[1] - z[0], dz2 = (double)z[2] - z[0];
    double gx = (dz1 * ey2 - dz2 * ey1) / area2, gy = (dz2 * ex1 - dz1 * ex2) / area2;
    double reach = (fabs(gx) + fabs(gy)) * WK_DEPTH_REACH;
    if (!(reach < 1.0)) { /* no area, or a plane steeper than the whole depth range a pixel */
        out->zmin = -INFINITY;
        out->zmax = INFINITY;
        return;
    }
    out->zmin = (float)(out->zmin - reach);
    out->zmax = (float)(out->zmax + reach);
}

void wk_tri_footprint(const lm_view *v, const lm_tri_data *t, wk_footprint *out)
{
    float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, zc[3];
    out->projected = 0;
    out->zmin = INFINITY;
    out->zmax = -INFINITY;
    for (int k = 0; k < 3; k++) {
        float *win = out->win[k], w, z = NAN;
        if (lm_view_project(v, t->c[k].pos, win, &w))
            z = window_depth(v, t->c[k].pos, w);
        if (!isfinite(z) || !isfinite(win[0]) || !isfinite(win[1])) {
            out->rect = (wk_rect){0, 0, v->width, v->height};
            out->zmin = -INFINITY;
            out->zmax = INFINITY;
            return;
        }
        zc[k] = z;
        out->zmin = z < out->zmin ? z : out->zmin;
        out->zmax = z > out->zmax ? z : out->zmax;
        for (int a = 0; a < 2; a++) {
            lo[a] = win[a] < lo[a] ? win[a] : lo[a];
            hi[a] = win[a] > hi[a] ? win[a] : hi[a];
        }
    }
    /* pixel i may be touched when its centre i + 0.5 lies in [lo - slack, hi + slack] */
    const double d = WK_PIXEL_SLACK + 0.5;
    out->rect.x0 = clamp_coord(ceil(lo[0] - d), v->width);
    out->rect.y0 = clamp_coord(ceil(lo[1] - d), v->height);
    out->rect.x1 = clamp_coord(floor(hi[0] - 0.5 + WK_PIXEL_SLACK) + 1.0, v->width);
    out->rect.y1 = clamp_coord(floor(hi[1] - 0.5 + WK_PIXEL_SLACK) + 1.0, v->height);
    out->projected = 1;
    widen_depths((const float(*)[2])out->win, zc, out);
}

/* Some corner of [x0,x1]x[y0,y1] is not strictly outside edge a->b (whose inside has sign s): the
 * edge function is linear, so the corner furthest inside decides. */
static int edge_admits(const float *a, const float *b, float s, const float box[4])
{
    float ex = b[0] - a[0], ey = b[1] - a[1];
    float px = box[-ey * s >= 0.0f ? 2 : 0] - a[0], py = box[ex * s >= 0.0f ? 3 : 1] - a[1];
    return (ex * py - ey * px) * s >= 0.0f;
}

int wk_footprint_overlaps(const wk_footprint *f, const wk_rect *r)
{
    if (wk_rect_empty(&f->rect) || wk_rect_empty(r) || !wk_rects_meet(&f->rect, r))
        return 0;
    if (!f->projected ||
        (f->rect.x0 >= r->x0 && f->rect.y0 >= r->y0 && f->rect.x1 <= r->x1 && f->rect.y1 <= r->y1))
        return 1; /* every pixel it may touch lies in r */
    const float(*w)[2] = f->win;
    float area =
        (w[1][0] - w[0][0]) * (w[2][1] - w[0][1]) - (w[1][1] - w[0][1]) * (w[2][0] - w[0][0]);
    if (!(fabsf(area) > 1e-3f))
        return 1; /* (nearly) degenerate: keep it */
    float s = area > 0 ? 1.0f : -1.0f;
    const float d = 0.5f - WK_PIXEL_SLACK; /* pixel centres of r, widened by the slack */
    const float box[4] = {(float)r->x0 + d, (float)r->y0 + d, (float)r->x1 - d, (float)r->y1 - d};
    return edge_admits(w[0], w[1], s, box) && edge_admits(w[1], w[2], s, box) &&
           edge_admits(w[2], w[0], s, box);
}

lm_status wk_idlist_reserve(wk_idlist *l, size_t need)
{
    if (need <= l->cap)
        return LM_OK;
    size_t cap = lm_grow_cap(l->cap, need, 64, SIZE_MAX);
    uint32_t *ids = realloc(l->ids, cap * sizeof *ids);
    if (!ids)
        return lm_fail(LM_E_NOMEM, "out of memory growing an id list to %zu", cap);
    l->ids = ids;
    l->cap = cap;
    return LM_OK;
}

lm_status wk_buckets_create(int width, int height, int cell, wk_buckets **out)
{
    if (width < 1 || height < 1 || width > LM_MAX_VIEW_SIZE || height > LM_MAX_VIEW_SIZE)
        return lm_fail(LM_E_RANGE, "bucket grid size %dx%d is out of range", width, height);
    wk_buckets *b = calloc(1, sizeof *b);
    if (!b)
        return lm_fail(LM_E_NOMEM, "out of memory creating triangle buckets");
    b->width = width;
    b->height = height;
    b->cell = cell > 0 ? cell : WK_BUCKET_DEFAULT_CELL;
    b->gw = (width + b->cell - 1) / b->cell;
    b->gh = (height + b->cell - 1) / b->cell;
    b->cells = calloc((size_t)b->gw * b->gh, sizeof *b->cells);
    if (!b->cells) {
        free(b);
        return lm_fail(LM_E_NOMEM, "out of memory creating triangle buckets");
    }
    *out = b;
    return LM_OK;
}

void wk_buckets_destroy(wk_buckets *b)
{
    if (!b)
        return;
    for (int i = 0; i < b->gw * b->gh; i++)
        free(b->cells[i].ids);
    free(b->cells);
    free(b->fp);
    free(b->present);
    free(b->stamp);
    free(b);
}

void wk_buckets_clear(wk_buckets *b)
{
    for (int i = 0; i < b->gw * b->gh; i++)
        b->cells[i].n = 0;
    if (b->cap_ids)
        memset(b->present, 0, b->cap_ids);
}

static lm_status grow_ids(wk_buckets *b, uint32_t id)
{
    if (id < b->cap_ids)
        return LM_OK;
    size_t cap = lm_grow_cap(b->cap_ids, (size_t)id + 1, 256, SIZE_MAX);
    if (!LM_RESIZE(&b->fp, cap) || !LM_RESIZE(&b->present, cap) || !LM_RESIZE(&b->stamp, cap))
        return lm_fail(LM_E_NOMEM, "out of memory growing triangle buckets to %zu ids", cap);
    memset(b->present + b->cap_ids, 0, cap - b->cap_ids);
    memset(b->stamp + b->cap_ids, 0, (cap - b->cap_ids) * sizeof *b->stamp);
    b->cap_ids = cap;
    return LM_OK;
}

static lm_status cell_push(wk_cell *c, uint32_t id)
{
    if (c->n == c->cap) {
        uint32_t cap = c->cap ? c->cap * 2 : 16;
        uint32_t *ids = realloc(c->ids, (size_t)cap * sizeof *ids);
        if (!ids)
            return lm_fail(LM_E_NOMEM, "out of memory growing a triangle bucket");
        c->ids = ids;
        c->cap = cap;
    }
    c->ids[c->n++] = id;
    return LM_OK;
}

/* Cell index range [cx0, cx1] x [cy0, cy1] a non-empty rectangle covers. */
static void cell_range(const wk_buckets *b, const wk_rect *r, int c[4])
{
    c[0] = r->x0 / b->cell;
    c[1] = r->y0 / b->cell;
    c[2] = (r->x1 - 1) / b->cell;
    c[3] = (r->y1 - 1) / b->cell;
}

static wk_rect clip_rect(const wk_buckets *b, const wk_rect *in)
{
    wk_rect r = *in;
    r.x0 = r.x0 < 0 ? 0 : r.x0;
    r.y0 = r.y0 < 0 ? 0 : r.y0;
    r.x1 = r.x1 > b->width ? b->width : r.x1;
    r.y1 = r.y1 > b->height ? b->height : r.y1;
    return r;
}

lm_status wk_buckets_insert(wk_buckets *b, uint32_t id, const wk_footprint *f)
{
    lm_status st = grow_ids(b, id);
    if (st != LM_OK)
        return st;
    LM_ASSERT(!b->present[id]);
    b->present[id] = 1;
    b->fp[id] = *f;
    b->fp[id].rect = clip_rect(b, &f->rect);
    const wk_rect *r = &b->fp[id].rect;
    if (wk_rect_empty(r))
        return LM_OK;
    int c[4];
    cell_range(b, r, c);
    for (int y = c[1]; y <= c[3]; y++)
        for (int x = c[0]; x <= c[2]; x++)
            if ((st = cell_push(&b->cells[y * b->gw + x], id)) != LM_OK)
                return st;
    return LM_OK;
}

lm_status wk_buckets_fill(wk_buckets *b, const lm_view *view, const lm_replica *rep)
{
    wk_buckets_clear(b);
    for (size_t id = 0; id < rep->cap; id++) {
        if (!rep->alive[id])
            continue;
        wk_footprint f;
        wk_tri_footprint(view, &rep->tris[id], &f);
        lm_status st = wk_buckets_insert(b, (uint32_t)id, &f);
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}

void wk_buckets_remove(wk_buckets *b, uint32_t id)
{
    LM_ASSERT(id < b->cap_ids && b->present[id]);
    b->present[id] = 0;
    const wk_rect *r = &b->fp[id].rect;
    if (wk_rect_empty(r))
        return;
    int c[4];
    cell_range(b, r, c);
    for (int y = c[1]; y <= c[3]; y++)
        for (int x = c[0]; x <= c[2]; x++) {
            wk_cell *cell = &b->cells[y * b->gw + x];
            for (uint32_t i = 0; i < cell->n; i++)
                if (cell->ids[i] == id) {
                    cell->ids[i] = cell->ids[--cell->n];
                    break;
                }
        }
}

const wk_footprint *wk_buckets_footprint(const wk_buckets *b, uint32_t id)
{
    LM_ASSERT(id < b->cap_ids && b->present[id]);
    return &b->fp[id];
}

void wk_buckets_rect(const wk_buckets *b, uint32_t id, wk_rect *out)
{
    if (id < b->cap_ids && b->present[id])
        *out = b->fp[id].rect;
    else
        *out = (wk_rect){0, 0, 0, 0};
}

lm_status wk_buckets_query(wk_buckets *b, const wk_rect *query, wk_idlist *out)
{
    wk_rect clipped = clip_rect(b, query), *r = &clipped;
    if (wk_rect_empty(r))
        return LM_OK;
    if (++b->now == 0) { /* stamps wrapped: forget them all */
        memset(b->stamp, 0, b->cap_ids * sizeof *b->stamp);
        b->now = 1;
    }
    int c[4];
    cell_range(b, r, c);
    for (int y = c[1]; y <= c[3]; y++)
        for (int x = c[0]; x <= c[2]; x++) {
            const wk_cell *cell = &b->cells[y * b->gw + x];
            lm_status st = wk_idlist_reserve(out, out->n + cell->n);
            if (st != LM_OK)
                return st;
            for (uint32_t i = 0; i < cell->n; i++) {
                uint32_t id = cell->ids[i];
                if (b->stamp[id] == b->now)
                    continue;
                b->stamp[id] = b->now;
                if (wk_footprint_overlaps(&b->fp[id], r))
                    out->ids[out->n++] = id;
            }
        }
    return LM_OK;
}
