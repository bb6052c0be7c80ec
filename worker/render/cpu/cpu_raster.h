/* worker/render/cpu/cpu_raster.h — the CPU backend's rasteriser: a triangle of a view becomes up to
 * WK_CPU_MAX_SUBS "subs" (the triangle itself, or the fan of its polygon after clipping against
 * the near and far planes and a guard band), each with exact integer edge functions on a grid of
 * 1/256 pixel and an integer depth plane; kernels walk a sub's pixels in 8x8 tiles.
 *
 * Every pixel of a view holds a 64-bit key: window depth (32 bits, 0 near .. 2^32-1 far) above
 * the sub's tag (id << 3 | sub index). The visible surface at a pixel is the least key over the
 * subs covering it, which is what drawing in ascending id order with a LESS depth test gives, but
 * it does not depend on the order of drawing: an image may be made by any sequence of
 * min-updates, so a region can be redrawn from any subset of triangles that holds its winners.
 *
 * Exactness: coverage (top-left rule on pixel centres), depth and the key are integer functions of
 * the sub and the pixel, evaluated directly (never accumulated along a traversal), so every
 * traversal, clip rectangle or tile order gives the same bits. The setup's floating point is
 * IEEE double in a fixed order (this file is compiled with -ffp-contract=off; float
 * conversions are clamped first), so the same triangle gives the same sub on every host.
 *
 * Pixels are (x, y) with y up from the bottom row (GL window order); a pixel's centre is
 * (x + 0.5, y + 0.5). */
#ifndef LM_WORKER_CPU_RASTER_H
#define LM_WORKER_CPU_RASTER_H

#include <stddef.h>
#include <stdint.h>

#include "common/patch.h"
#include "common/view.h"
#include "worker/render/shared/buckets.h"

#define WK_CPU_SUBPIXEL 256 /* vertices snap to 1/256 pixel */
#define WK_CPU_MAX_SUBS 7   /* clipped by near, far and 4 guard planes: a fan of <= 9 corners */
#define WK_CPU_TILE 8       /* side of the tiles of the depth maxima and of the traversal */
#define WK_CPU_KEY_BG UINT64_MAX              /* the key of a background pixel */
#define WK_CPU_TAG_BG 0xFFFFFFFFu             /* its low half */
#define WK_CPU_KEY_ID(k) ((uint32_t)(k) >> 3) /* triangle id of a key (not for WK_CPU_KEY_BG) */
/* A pixel packed as y << 16 | x (views are at most LM_MAX_VIEW_SIZE = 4096 wide). */
#define WK_CPU_XY(x, y) ((uint32_t)(y) << 16 | (uint32_t)(x))
#define WK_CPU_X(xy) ((int)((xy)&0xFFFF))
#define WK_CPU_Y(xy) ((int)((xy) >> 16))

/* One sub: corners in ascending orientation (counter-clockwise in window coordinates). */
typedef struct wk_cpu_sub {
    int64_t e[3];       /* edge functions at the centre of (x0, y0), minus the fill-rule bias */
    int64_t a[3], b[3]; /* their steps per pixel in x and in y */
    int64_t z, za, zb;  /* depth plane at the centre of (x0, y0) and its steps (2^-48 units) */
    uint64_t zmin_key;  /* no fragment of this sub has a smaller key (0: unknown) */
    int x0, y0, x1, y1; /* pixels whose centres may be covered, [x0, x1) x [y0, y1), in the view */
    uint32_t tag;       /* id << 3 | sub index */
    uint8_t bias[3];    /* 1 where pixel centres on the edge are left out (not top-left) */
    /* (the rasteriser reads the fields above, the first 127 bytes; the shading those below) */
    double invw[3];    /* 1 / clip w of each corner */
    double beta[3][3]; /* each corner as barycentric weights of the source triangle's corners */
} wk_cpu_sub;

/* A view as the rasteriser uses it: its world-to-clip matrix in double, its size. */
typedef struct wk_cpu_view {
    double m[16]; /* column-major, as lm_view's view_proj */
    int width, height;
} wk_cpu_view;

void wk_cpu_view_init(const lm_view *v, wk_cpu_view *out);

/* The subs of triangle t in view v (capacity WK_CPU_MAX_SUBS); returns how many (0 when it covers
 * no pixel centre of the view for certain: outside, degenerate or not finite). */
int wk_cpu_tri_setup(const wk_cpu_view *v, const lm_tri_data *t, wk_cpu_sub *out);

/* A vertex in a view, for the test below: its snapped window position, computed exactly as
 * wk_cpu_tri_setup computes a corner's, when it lies inside every clip plane (else inside = 0). */
typedef struct wk_cpu_vcorner {
    int64_t x, y;
    int inside;
} wk_cpu_vcorner;

void wk_cpu_vcorner_make(const wk_cpu_view *v, const float pos[3], wk_cpu_vcorner *out);

/* 1 when the triangle with these corners (as wk_cpu_vcorner_make made them from its corners'
 * positions) covers no pixel centre of the view: wk_cpu_tri_setup would return 0 for it, by the
 * same arithmetic. 0 when it may cover one, or is clipped: the caller runs wk_cpu_tri_setup. A
 * large mesh's vertices are projected once per view instead of once per corner, and its many
 * triangles between pixel centres are dropped before their records are made. */
int wk_cpu_tri_covers_none(const wk_cpu_view *v, const wk_cpu_vcorner *c0, const wk_cpu_vcorner *c1,
                           const wk_cpu_vcorner *c2);

/* Unbiased edge functions of a sub at pixel (x, y) (>= 0 where it covers the pixel). */
static inline void wk_cpu_sub_edges(const wk_cpu_sub *s, int x, int y, int64_t e[3])
{
    for (int k = 0; k < 3; k++)
        e[k] = s->e[k] + s->bias[k] + s->a[k] * (x - s->x0) + s->b[k] * (y - s->y0);
}

/* A key no fragment at window depth z or beyond (z in [0, 1]) can undercut, with the margin the
 * subs' own zmin_key has. */
uint64_t wk_cpu_depth_bound(double z);

/* Whether the sub covers pixel (x, y) of its box, and its key there, by direct evaluation: what
 * the kernels below compute along their walks (for checks). */
int wk_cpu_sub_key_at(const wk_cpu_sub *s, int x, int y, uint64_t *key);

/* A view's keys with the depth maxima of its 8x8 tiles (an upper bound of every key of the tile:
 * a sub whose zmin_key exceeds it has no fragment in front there) and a lower bound of the second
 * least key of each pixel (of every triangle but the visible one), kept as its depth half: key >>
 * 32 (WK_CPU_SECOND_NONE if none). Half the bytes of a key, and as good a bound: two keys of one
 * depth differ only in their triangle's tag. */
typedef struct wk_cpu_keys {
    uint64_t *key;    /* [width * height] */
    uint64_t *tmax;   /* [tiles_w * tiles_h], may be NULL (no depth rejection) */
    uint32_t *second; /* [width * height], NULL: draws leave it alone */
    int width, height, tiles_w;
} wk_cpu_keys;

#define WK_CPU_SECOND_NONE UINT32_MAX /* no second surface: the background's depth half */

/* The depth half of a key, as the second-key bounds keep it. */
static inline uint32_t wk_cpu_second_of(uint64_t key)
{
    return (uint32_t)(key >> 32);
}

/* The least key a second-key bound allows (every key whose depth half is at least b is >= it). */
static inline uint64_t wk_cpu_second_key(uint32_t b)
{
    return (uint64_t)b << 32;
}

/* Pixels whose key changed during one evaluation pass, each once (the first old key kept). */
typedef struct wk_cpu_log {
    uint32_t *stamp; /* [width * height]: == now where a pixel is in the log */
    uint32_t now;
    uint32_t *idx; /* [capacity width * height] pixel indices */
    uint32_t *xy;  /* the same pixels as WK_CPU_XY */
    uint64_t *old; /* their keys before the pass */
    uint8_t *flag; /* what the pass did there first (caller's meaning) */
    size_t n;
} wk_cpu_log;

/* Log pixel p (key old before the pass) unless it is in the log already. */
static inline void wk_cpu_log_pixel(wk_cpu_log *log, uint32_t p, uint32_t xy, uint64_t old,
                                    uint8_t flag)
{
    if (log->stamp[p] == log->now)
        return;
    log->stamp[p] = log->now;
    log->idx[log->n] = p;
    log->xy[log->n] = xy;
    log->old[log->n] = old;
    log->flag[log->n] = flag;
    log->n++;
}

/* Where a kernel may touch: a rectangle and optionally a mask of the view's tiles (1 = may). */
typedef struct wk_cpu_clip {
    wk_rect rect;
    const uint8_t *tile_mask; /* [tiles_w * tiles_h] or NULL */
} wk_cpu_clip;

/* Draw sub s: key[p] = min(key[p], its key at p) over the covered pixels of clip; tiles whose
 * maximum lies in front of the sub are skipped. With a log, every pixel that changes is logged
 * (flag `flag` when new to it). With k->second (and no log, no tile maxima), the second least key
 * is kept too: a key that loses (and is not the visible one itself) lowers it. Returns the
 * number of pixels that changed. */
size_t wk_cpu_draw(const wk_cpu_sub *s, wk_cpu_keys *k, const wk_cpu_clip *clip, wk_cpu_log *log,
                   uint8_t flag);

/* The pixels of clip where s is the visible surface (key's low half == tag: the tag is unique to
 * the sub, so these are covered by it), appended to out as WK_CPU_XY (capacity enough for them:
 * at most the clip's area); stops after `limit`. Returns how many were appended. */
size_t wk_cpu_owned(const wk_cpu_sub *s, const wk_cpu_keys *k, const wk_rect *clip, uint32_t *out,
                    size_t limit);

/* The pixels of the view where s is the visible surface (as wk_cpu_owned finds them), up to
 * `limit`, logged with flag `flag` (each must be new to the log: a pixel has one visible sub) and,
 * when `clear`, set to the background (WK_CPU_KEY_BG). Returns how many. */
size_t wk_cpu_log_owned(const wk_cpu_sub *s, wk_cpu_keys *k, wk_cpu_log *log, uint8_t flag,
                        int clear, size_t limit);

/* Recompute the exact maxima of the tiles that rectangle r touches. */
void wk_cpu_keys_update_tiles(wk_cpu_keys *k, const wk_rect *r);

#endif
