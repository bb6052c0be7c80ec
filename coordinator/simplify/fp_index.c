/* coordinator/simplify/fp_index.c — the per-view grids of footprint rectangles (fp_index.h):
 * records (entry, generation, the rectangle clamped to int16) in cells of CO_FPX_CELL pixels, one
 * ring of cells beyond the image's edges, stale records swept in bulk. */
#include "coordinator/simplify/fp_index.h"

#include <stdlib.h>

#include "common/grow.h"

#define CO_FPX_CELL 8           /* pixels on a cell's side */
#define CO_FPX_SWEEP_SLACK 4096 /* stale records tolerated beyond a quarter of the live ones */

typedef struct fpx_rec {
    uint32_t entry, gen;
    int16_t x0, y0, x1, y1; /* the rectangle, clamped (a monotonic map: meeting ones still meet) */
} fpx_rec;

typedef struct fpx_cell {
    fpx_rec *r;
    uint32_t n, cap;
} fpx_cell;

typedef struct fpx_view {
    int32_t w, h;    /* the view's pixels */
    uint32_t gw, gh; /* cells across and down, the outer ring included */
    fpx_cell *cells; /* [gw * gh] */
} fpx_view;

struct co_fpx {
    uint32_t n_views;
    fpx_view v[LM_MAX_VIEWS];
    uint32_t *gen, *n_reg; /* per entry: its footprint's generation and records */
    uint32_t cap_entries;
    uint64_t live, total; /* records of latest footprints, and all records */
};

lm_status co_fpx_create(const lm_view_set *vs, co_fpx **out)
{
    *out = NULL;
    co_fpx *x = calloc(1, sizeof *x);
    if (!x)
        return lm_fail(LM_E_NOMEM, "out of memory for the footprint index");
    x->n_views = vs->count;
    for (uint32_t h = 0; h < vs->count; h++) {
        fpx_view *v = &x->v[h];
        v->w = vs->views[h].width > 0 ? vs->views[h].width : 1;
        v->h = vs->views[h].height > 0 ? vs->views[h].height : 1;
        v->gw = (uint32_t)(v->w + CO_FPX_CELL - 1) / CO_FPX_CELL + 2;
        v->gh = (uint32_t)(v->h + CO_FPX_CELL - 1) / CO_FPX_CELL + 2;
        v->cells = calloc((size_t)v->gw * v->gh, sizeof *v->cells);
        if (!v->cells) {
            co_fpx_destroy(x);
            return lm_fail(LM_E_NOMEM, "out of memory for the footprint index");
        }
    }
    *out = x;
    return LM_OK;
}

void co_fpx_destroy(co_fpx *x)
{
    if (!x)
        return;
    for (uint32_t h = 0; h < x->n_views; h++) {
        fpx_view *v = &x->v[h];
        for (size_t c = 0; v->cells && c < (size_t)v->gw * v->gh; c++)
            free(v->cells[c].r);
        free(v->cells);
    }
    free(x->gen);
    free(x->n_reg);
    free(x);
}

/* The cell column (or row) of pixel p on a side of `size` pixels: 0 before it, n - 1 after it. */
static uint32_t cell_of(int32_t p, int32_t size, uint32_t n)
{
    return p < 0 ? 0 : p >= size ? n - 1 : (uint32_t)(p / CO_FPX_CELL) + 1;
}

static int16_t clamp16(int32_t p)
{
    return (int16_t)(p < INT16_MIN ? INT16_MIN : p > INT16_MAX ? INT16_MAX : p);
}

/* Empty as co_fp_meet reads it (it never meets anything). */
static int rect_empty(const co_rect *r)
{
    return r->x0 > r->x1;
}

/* The cells under r: columns c[0]..c[1], rows c[2]..c[3] (an upside-down y range, which grow
 * never makes, still covers every pixel co_fp_meet could find it meeting). */
static void cells_under(const fpx_view *v, const co_rect *r, uint32_t c[4])
{
    int32_t y0 = r->y0 < r->y1 ? r->y0 : r->y1, y1 = r->y0 < r->y1 ? r->y1 : r->y0;
    c[0] = cell_of(r->x0, v->w, v->gw);
    c[1] = cell_of(r->x1, v->w, v->gw);
    c[2] = cell_of(y0, v->h, v->gh);
    c[3] = cell_of(y1, v->h, v->gh);
}

/* Drop the records whose entry has a newer footprint (or none). */
static void sweep(co_fpx *x)
{
    for (uint32_t h = 0; h < x->n_views; h++) {
        fpx_view *v = &x->v[h];
        for (size_t c = 0; c < (size_t)v->gw * v->gh; c++) {
            fpx_cell *cell = &v->cells[c];
            uint32_t k = 0;
            for (uint32_t i = 0; i < cell->n; i++)
                if (cell->r[i].gen == x->gen[cell->r[i].entry])
                    cell->r[k++] = cell->r[i];
            cell->n = k;
        }
    }
    x->total = x->live;
}

static lm_status room_for_entry(co_fpx *x, uint32_t i)
{
    if (i < x->cap_entries)
        return LM_OK;
    uint32_t cap = x->cap_entries, cap2 = x->cap_entries;
    if (!LM_GROW32(&x->gen, &cap, (size_t)i + 1, 1024) ||
        !LM_GROW32(&x->n_reg, &cap2, (size_t)i + 1, 1024) || cap != cap2)
        return lm_fail(LM_E_NOMEM, "out of memory for the footprint index");
    for (uint32_t k = x->cap_entries; k < cap; k++)
        x->gen[k] = x->n_reg[k] = 0;
    x->cap_entries = cap;
    return LM_OK;
}

void co_fpx_drop(co_fpx *x, uint32_t i)
{
    if (i >= x->cap_entries)
        return;
    x->live -= x->n_reg[i];
    x->n_reg[i] = 0;
    x->gen[i]++;
}

static lm_status add_rect(co_fpx *x, uint32_t h, uint32_t i, const co_rect *r)
{
    fpx_view *v = &x->v[h];
    fpx_rec rec = {.entry = i,
                   .gen = x->gen[i],
                   .x0 = clamp16(r->x0),
                   .y0 = clamp16(r->y0),
                   .x1 = clamp16(r->x1),
                   .y1 = clamp16(r->y1)};
    uint32_t c[4];
    cells_under(v, r, c);
    for (uint32_t cy = c[2]; cy <= c[3]; cy++)
        for (uint32_t cx = c[0]; cx <= c[1]; cx++) {
            fpx_cell *cell = &v->cells[(size_t)cy * v->gw + cx];
            if (!LM_GROW32(&cell->r, &cell->cap, (size_t)cell->n + 1, 8))
                return lm_fail(LM_E_NOMEM, "out of memory for the footprint index");
            cell->r[cell->n++] = rec;
            x->n_reg[i]++;
            x->live++;
            x->total++;
        }
    return LM_OK;
}

lm_status co_fpx_put(co_fpx *x, uint32_t i, const co_rect *fp)
{
    lm_status st = room_for_entry(x, i);
    if (st != LM_OK)
        return st;
    co_fpx_drop(x, i);
    for (uint32_t h = 0; h < x->n_views && st == LM_OK; h++)
        if (!rect_empty(&fp[h]))
            st = add_rect(x, h, i, &fp[h]);
    if (st == LM_OK && x->total > x->live + x->live / 4 + CO_FPX_SWEEP_SLACK)
        sweep(x);
    return st;
}

/* The records of one view's cells under r whose rectangles meet r. */
static void query_view(co_fpx *x, uint32_t h, const co_rect *r, void (*hit)(void *ctx, uint32_t i),
                       void *ctx)
{
    const fpx_view *v = &x->v[h];
    int16_t x0 = clamp16(r->x0), y0 = clamp16(r->y0), x1 = clamp16(r->x1), y1 = clamp16(r->y1);
    uint32_t c[4];
    cells_under(v, r, c);
    for (uint32_t cy = c[2]; cy <= c[3]; cy++)
        for (uint32_t cx = c[0]; cx <= c[1]; cx++) {
            const fpx_cell *cell = &v->cells[(size_t)cy * v->gw + cx];
            for (uint32_t k = 0; k < cell->n; k++) {
                const fpx_rec *c = &cell->r[k];
                if (c->x0 <= x1 && x0 <= c->x1 && c->y0 <= y1 && y0 <= c->y1 &&
                    c->gen == x->gen[c->entry])
                    hit(ctx, c->entry);
            }
        }
}

void co_fpx_query(co_fpx *x, const co_rect *fp, void (*hit)(void *ctx, uint32_t i), void *ctx)
{
    for (uint32_t h = 0; h < x->n_views; h++)
        if (!rect_empty(&fp[h]))
            query_view(x, h, &fp[h], hit, ctx);
}
