/* worker/render/shared/buckets.h — triangle buckets of one view (paper §4.3): the conservative
 * screen rectangle of every current triangle and a uniform grid of cells listing the triangles
 * whose rectangle touches each cell, for rectangle range queries. No GL here.
 *
 * Rectangles are half-open pixel ranges [x0, x1) x [y0, y1) in the view's window coordinates
 * (x right, y up from the bottom row, as GL). Triangle ids are the mesh's stable triangle ids. */
#ifndef LM_WORKER_BUCKETS_H
#define LM_WORKER_BUCKETS_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/patch.h"
#include "common/replica.h"
#include "common/view.h"

typedef struct wk_rect {
    int x0, y0, x1, y1;
} wk_rect;

static inline int wk_rect_empty(const wk_rect *r)
{
    return r->x0 >= r->x1 || r->y0 >= r->y1;
}

/* r := r ∪ s (an empty operand is ignored). */
void wk_rect_union(wk_rect *r, const wk_rect *s);
/* Whether rectangles a and b share a pixel. */
static inline int wk_rects_meet(const wk_rect *a, const wk_rect *b)
{
    return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

/* a ∩ b (possibly empty). */
static inline wk_rect wk_rect_intersect(const wk_rect *a, const wk_rect *b)
{
    return (wk_rect){a->x0 > b->x0 ? a->x0 : b->x0, a->y0 > b->y0 ? a->y0 : b->y0,
                     a->x1 < b->x1 ? a->x1 : b->x1, a->y1 < b->y1 ? a->y1 : b->y1};
}

/* Slack, in pixels, between our projection of a corner and the rasteriser's (which snaps to 1/256
 * pixel after its own float arithmetic): a pixel counts as touched when its centre lies within
 * this distance of the projected triangle. */
#define WK_PIXEL_SLACK 0.25f

/* How far, in pixels along x and along y, a pixel centre that a rasteriser covers may lie outside
 * the projected triangle: half a subpixel step where corners snap to 1/16 pixel (OpenGL ES asks
 * for at least four subpixel bits; llvmpipe and GPUs have eight). */
#define WK_DEPTH_REACH (1.0f / 32.0f)

/* Where a triangle lands in a view: the conservative rectangle of the pixels it may touch, clamped
 * to the view (pixels whose centre lies within WK_PIXEL_SLACK of the projected bounds; the whole
 * view if a corner is at or behind the eye or not finite; empty when it lies entirely outside),
 * and, when projectable, its corners in window coordinates for the exact overlap test. */
typedef struct wk_footprint {
    wk_rect rect;
    int projected; /* win and zmin hold the corners' window coordinates */
    float win[3][2];
    float zmin; /* least window depth a fragment may have (0 near .. 1 far; -inf if not projected
                 * or if its depth plane is unbounded): the corners' least, less the plane's change
                 * over WK_DEPTH_REACH, since a rasteriser that covers a pixel centre just outside
                 * the triangle (its corners snapped) extrapolates the depth plane there, and a
                 * sliver's plane is steep */
    float zmax; /* greatest window depth a fragment may have, likewise (+inf when not projected) */
} wk_footprint;

void wk_tri_footprint(const lm_view *v, const lm_tri_data *t, wk_footprint *out);

/* Whether a footprint may touch a pixel of r: the rectangle test, then (for projected ones) the
 * triangle against the box of r's pixel centres widened by WK_PIXEL_SLACK (separating edges).
 * Conservative. */
int wk_footprint_overlaps(const wk_footprint *f, const wk_rect *r);

typedef struct wk_buckets wk_buckets;

/* cell: the side of a grid cell in pixels (0 = default 16). */
lm_status wk_buckets_create(int width, int height, int cell, wk_buckets **out);
void wk_buckets_destroy(wk_buckets *b);
/* Forget every triangle. */
void wk_buckets_clear(wk_buckets *b);
/* Forget every triangle, then insert every alive triangle of rep with its footprint in view. */
lm_status wk_buckets_fill(wk_buckets *b, const lm_view *view, const lm_replica *rep);
/* Insert triangle `id` (not present) with its footprint (an empty rectangle is only remembered). */
lm_status wk_buckets_insert(wk_buckets *b, uint32_t id, const wk_footprint *f);
/* Remove triangle `id` (present). */
void wk_buckets_remove(wk_buckets *b, uint32_t id);
/* The stored rectangle of a present triangle (empty if absent). */
void wk_buckets_rect(const wk_buckets *b, uint32_t id, wk_rect *out);
/* The stored footprint of a present triangle. */
const wk_footprint *wk_buckets_footprint(const wk_buckets *b, uint32_t id);
/* A growable list of ids (owned by the caller; free ids with free()). */
typedef struct wk_idlist {
    uint32_t *ids;
    size_t n, cap;
} wk_idlist;
lm_status wk_idlist_reserve(wk_idlist *l, size_t need);

/* Appends to out the ids of all present triangles whose footprint may touch r
 * (wk_footprint_overlaps), each once, in no particular order. */
lm_status wk_buckets_query(wk_buckets *b, const wk_rect *r, wk_idlist *out);

#endif
