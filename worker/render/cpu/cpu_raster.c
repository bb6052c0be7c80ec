/* worker/render/cpu/cpu_raster.c — triangle setup (projection, clipping against the near and far
 * planes and a guard band, snapping to 1/256 pixel, edge functions with the top-left rule, the
 * depth plane) and the tile kernels that draw subs into a view's keys (see cpu_raster.h). */
#include "worker/render/cpu/cpu_raster.h"

#include <float.h>
#include <math.h>
#include <string.h>

#if FLT_EVAL_METHOD != 0
#error "the CPU rasteriser needs IEEE arithmetic without excess precision (FLT_EVAL_METHOD 0)"
#endif

#define GUARD 256.0 /* guard band: |x|, |y| <= GUARD * w in clip space (~2^19 px at most) */
#define N_PLANES 6
#define MAX_CORNERS 9
#define DEPTH_ONE 281474976710656.0 /* 2^48: the depth plane's unit is 2^-48 of the depth range */
#define DEPTH_LIM_Z 4503599627370496.0   /* 2^52 */
#define DEPTH_LIM_STEP 562949953421312.0 /* 2^49 per pixel: steeper planes are clamped */
#define COORD_LIM 268435456.0          /* 2^28 subpixels: products of differences stay below 2^59 */
#define ZMIN_MARGIN ((int64_t)1 << 17) /* two key units: the plane's rounding stays far below */

/* A corner during clipping: clip coordinates and weights of the source triangle's corners. */
typedef struct corner {
    double c[4];
    double beta[3];
} corner;

static double plane_dist(const corner *v, int p)
{
    switch (p) {
    case 0:
        return v->c[2] + v->c[3]; /* near */
    case 1:
        return v->c[3] - v->c[2]; /* far */
    case 2:
        return GUARD * v->c[3] + v->c[0];
    case 3:
        return GUARD * v->c[3] - v->c[0];
    case 4:
        return GUARD * v->c[3] + v->c[1];
    default:
        return GUARD * v->c[3] - v->c[1];
    }
}

static int outcode(const corner *v)
{
    const double x = v->c[0], y = v->c[1], z = v->c[2], gw = GUARD * v->c[3];
    return (z + v->c[3] < 0.0) | (v->c[3] - z < 0.0) << 1 | (gw + x < 0.0) << 2 |
           (gw - x < 0.0) << 3 | (gw + y < 0.0) << 4 | (gw - y < 0.0) << 5;
}

/* Sutherland-Hodgman against one plane; intersections are computed from the inside corner towards
 * the outside one, so that two triangles sharing an edge get the same new corner. */
static int clip_plane(const corner *in, int n, int p, corner *out)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        const corner *a = &in[i], *b = &in[(i + 1) % n];
        double da = plane_dist(a, p), db = plane_dist(b, p);
        if (da >= 0.0)
            out[m++] = *a;
        if ((da >= 0.0) != (db >= 0.0)) {
            const corner *u = da >= 0.0 ? a : b, *o = da >= 0.0 ? b : a;
            double du = da >= 0.0 ? da : db, dout = da >= 0.0 ? db : da;
            double t = du / (du - dout);
            corner *r = &out[m++];
            for (int k = 0; k < 4; k++)
                r->c[k] = u->c[k] + t * (o->c[k] - u->c[k]);
            for (int k = 0; k < 3; k++)
                r->beta[k] = u->beta[k] + t * (o->beta[k] - u->beta[k]);
        }
    }
    return m;
}

void wk_cpu_view_init(const lm_view *v, wk_cpu_view *out)
{
    for (int i = 0; i < 16; i++)
        out->m[i] = v->view_proj[i];
    out->width = v->width;
    out->height = v->height;
}

/* Clip coordinates of one position; the sum of (c - c) over them: 0 when all are finite, NaN
 * otherwise. The one projection of the rasteriser (triangles' corners and vertices alike). */
static inline double project_one(const double *m, const float pos[3], double c[4])
{
    double p0 = pos[0], p1 = pos[1], p2 = pos[2], finite = 0.0;
    for (int r = 0; r < 4; r++) {
        c[r] = m[r] * p0 + m[4 + r] * p1 + m[8 + r] * p2 + m[12 + r];
        finite += c[r] - c[r]; /* NaN once any is infinite or NaN */
    }
    return finite;
}

/* Clip coordinates of the triangle's corners; 0 when not finite. */
static int project_corners(const wk_cpu_view *v, const lm_tri_data *t, corner *c)
{
    double finite = 0.0;
    for (int k = 0; k < 3; k++) {
        finite += project_one(v->m, t->c[k].pos, c[k].c);
        for (int j = 0; j < 3; j++)
            c[k].beta[j] = j == k ? 1.0 : 0.0;
    }
    return finite == 0.0;
}

static double clampd(double x, double lo, double hi)
{
    return x > lo ? (x < hi ? x : hi) : lo; /* NaN -> lo */
}

/* floor(x) for |x| < 2^62, without libm (x86-64 has no SSE2 rounding instruction). */
static int64_t ifloor(double x)
{
    int64_t i = (int64_t)x;
    return i - (x < (double)i);
}

static int64_t round_clamped(double x, double lim)
{
    return ifloor(clampd(x, -lim, lim) + 0.5);
}

/* A corner in window space: snapped position and depth in [0, 1]. */
typedef struct wcorner {
    int64_t x, y;
    double z, invw;
    const double *beta;
} wcorner;

static int to_window(const wk_cpu_view *v, const corner *c, wcorner *out)
{
    if (!(c->c[3] > 0.0))
        return 0;
    double inv = 1.0 / c->c[3];
    double xw = (c->c[0] * inv * 0.5 + 0.5) * v->width;
    double yw = (c->c[1] * inv * 0.5 + 0.5) * v->height;
    out->x = round_clamped(xw * WK_CPU_SUBPIXEL, COORD_LIM);
    out->y = round_clamped(yw * WK_CPU_SUBPIXEL, COORD_LIM);
    out->z = clampd(c->c[2] * inv * 0.5 + 0.5, 0.0, 1.0);
    out->invw = inv;
    out->beta = c->beta;
    return 1;
}

static int64_t floor_div(int64_t a, int64_t b) /* b > 0 */
{
    int64_t q = a / b;
    return q - (a % b != 0 && a < 0);
}

static int clampi(int64_t x, int lo, int hi)
{
    return x < lo ? lo : x > hi ? hi : (int)x;
}

/* Pixel box of the centres within the corners' box, clamped to the view; 0 if empty. */
static int pixel_box(const wk_cpu_view *v, const wcorner *w, wk_cpu_sub *s)
{
    int64_t lo[2] = {w[0].x, w[0].y}, hi[2] = {w[0].x, w[0].y};
    for (int k = 1; k < 3; k++) {
        lo[0] = w[k].x < lo[0] ? w[k].x : lo[0];
        hi[0] = w[k].x > hi[0] ? w[k].x : hi[0];
        lo[1] = w[k].y < lo[1] ? w[k].y : lo[1];
        hi[1] = w[k].y > hi[1] ? w[k].y : hi[1];
    }
    const int64_t half = WK_CPU_SUBPIXEL / 2;
    s->x0 = clampi(-floor_div(-(lo[0] - half), WK_CPU_SUBPIXEL), 0, v->width);
    s->y0 = clampi(-floor_div(-(lo[1] - half), WK_CPU_SUBPIXEL), 0, v->height);
    s->x1 = clampi(floor_div(hi[0] - half, WK_CPU_SUBPIXEL) + 1, 0, v->width);
    s->y1 = clampi(floor_div(hi[1] - half, WK_CPU_SUBPIXEL) + 1, 0, v->height);
    return s->x0 < s->x1 && s->y0 < s->y1;
}

static void setup_edges(const wcorner *w, wk_cpu_sub *s)
{
    int64_t px = (int64_t)s->x0 * WK_CPU_SUBPIXEL + WK_CPU_SUBPIXEL / 2;
    int64_t py = (int64_t)s->y0 * WK_CPU_SUBPIXEL + WK_CPU_SUBPIXEL / 2;
    for (int k = 0; k < 3; k++) {
        const wcorner *a = &w[(k + 1) % 3], *b = &w[(k + 2) % 3];
        int64_t dx = b->x - a->x, dy = b->y - a->y;
        int top_left = dy < 0 || (dy == 0 && dx < 0);
        s->bias[k] = (uint8_t)!top_left;
        s->e[k] = dx * (py - a->y) - dy * (px - a->x) - s->bias[k];
        s->a[k] = -dy * WK_CPU_SUBPIXEL;
        s->b[k] = dx * WK_CPU_SUBPIXEL;
    }
}

static uint64_t depth_key(int64_t z)
{
    if (z <= 0)
        return 0;
    if (z >= ((int64_t)1 << 48))
        return 0xFFFFFFFF00000000ull;
    return ((uint64_t)z << 16) & 0xFFFFFFFF00000000ull;
}

/* The depth plane through the snapped corners, in 2^-48 units per pixel. */
static void setup_depth(const wcorner *w, int64_t area2, wk_cpu_sub *s)
{
    double dx1 = (double)(w[1].x - w[0].x), dy1 = (double)(w[1].y - w[0].y);
    double dx2 = (double)(w[2].x - w[0].x), dy2 = (double)(w[2].y - w[0].y);
    double dz1 = w[1].z - w[0].z, dz2 = w[2].z - w[0].z, area = (double)area2;
    double dzdx = (dz1 * dy2 - dz2 * dy1) / area, dzdy = (dz2 * dx1 - dz1 * dx2) / area;
    double px = (double)((int64_t)s->x0 * WK_CPU_SUBPIXEL + WK_CPU_SUBPIXEL / 2 - w[0].x);
    double py = (double)((int64_t)s->y0 * WK_CPU_SUBPIXEL + WK_CPU_SUBPIXEL / 2 - w[0].y);
    double zref = w[0].z + dzdx * px + dzdy * py;
    double ga = dzdx * WK_CPU_SUBPIXEL * DEPTH_ONE, gb = dzdy * WK_CPU_SUBPIXEL * DEPTH_ONE;
    s->z = round_clamped(zref * DEPTH_ONE, DEPTH_LIM_Z);
    s->za = round_clamped(ga, DEPTH_LIM_STEP);
    s->zb = round_clamped(gb, DEPTH_LIM_STEP);
    double zmin = w[0].z < w[1].z ? w[0].z : w[1].z;
    zmin = w[2].z < zmin ? w[2].z : zmin;
    int steep = !(fabs(ga) < DEPTH_LIM_STEP) || !(fabs(gb) < DEPTH_LIM_STEP) ||
                !(fabs(zref * DEPTH_ONE) < DEPTH_LIM_Z);
    s->zmin_key = steep ? 0 : wk_cpu_depth_bound(zmin);
}

/* One sub from three clipped corners; 0 if it covers no pixel centre of the view. */
static int setup_sub(const wk_cpu_view *v, const corner *c0, const corner *c1, const corner *c2,
                     uint32_t tag, wk_cpu_sub *s)
{
    wcorner w[3];
    if (!to_window(v, c0, &w[0]) || !to_window(v, c1, &w[1]) || !to_window(v, c2, &w[2]))
        return 0;
    int64_t area2 = (w[1].x - w[0].x) * (w[2].y - w[0].y) - (w[1].y - w[0].y) * (w[2].x - w[0].x);
    if (area2 == 0)
        return 0;
    if (area2 < 0) {
        wcorner t = w[1];
        w[1] = w[2];
        w[2] = t;
        area2 = -area2;
    }
    if (!pixel_box(v, w, s))
        return 0;
    setup_edges(w, s);
    setup_depth(w, area2, s);
    s->tag = tag;
    for (int k = 0; k < 3; k++) {
        s->invw[k] = w[k].invw;
        memcpy(s->beta[k], w[k].beta, sizeof s->beta[k]);
    }
    return 1;
}

int wk_cpu_tri_setup(const wk_cpu_view *v, const lm_tri_data *t, wk_cpu_sub *out)
{
    corner poly[2][MAX_CORNERS];
    if (!project_corners(v, t, poly[0]))
        return 0;
    int codes[3] = {outcode(&poly[0][0]), outcode(&poly[0][1]), outcode(&poly[0][2])};
    if (codes[0] & codes[1] & codes[2])
        return 0; /* wholly outside one plane */
    int n = 3, cur = 0;
    for (int p = 0; p < N_PLANES && n >= 3; p++)
        if ((codes[0] | codes[1] | codes[2]) & (1 << p)) {
            n = clip_plane(poly[cur], n, p, poly[cur ^ 1]);
            cur ^= 1;
        }
    int k = 0;
    uint32_t base = t->id << 3;
    for (int i = 1; i + 1 < n; i++)
        k += setup_sub(v, &poly[cur][0], &poly[cur][i], &poly[cur][i + 1], base | (uint32_t)(i - 1),
                       &out[k]);
    return k;
}

void wk_cpu_vcorner_make(const wk_cpu_view *v, const float pos[3], wk_cpu_vcorner *out)
{
    corner c;
    wcorner w;
    out->inside = project_one(v->m, pos, c.c) == 0.0 && outcode(&c) == 0 && to_window(v, &c, &w);
    out->x = out->inside ? w.x : 0;
    out->y = out->inside ? w.y : 0;
}

int wk_cpu_tri_covers_none(const wk_cpu_view *v, const wk_cpu_vcorner *c0, const wk_cpu_vcorner *c1,
                           const wk_cpu_vcorner *c2)
{
    if (!c0->inside || !c1->inside || !c2->inside)
        return 0; /* clipped, outside or not finite: the full setup decides */
    wcorner w[3] = {{.x = c0->x, .y = c0->y}, {.x = c1->x, .y = c1->y}, {.x = c2->x, .y = c2->y}};
    int64_t area2 = (w[1].x - w[0].x) * (w[2].y - w[0].y) - (w[1].y - w[0].y) * (w[2].x - w[0].x);
    wk_cpu_sub box;
    return area2 == 0 || !pixel_box(v, w, &box);
}

uint64_t wk_cpu_depth_bound(double z)
{
    return depth_key(ifloor(clampd(z, 0.0, 1.0) * DEPTH_ONE) - ZMIN_MARGIN);
}

int wk_cpu_sub_key_at(const wk_cpu_sub *s, int x, int y, uint64_t *key)
{
    if (x < s->x0 || x >= s->x1 || y < s->y0 || y >= s->y1)
        return 0;
    for (int k = 0; k < 3; k++)
        if (s->e[k] + s->a[k] * (x - s->x0) + s->b[k] * (y - s->y0) < 0)
            return 0;
    *key = depth_key(s->z + s->za * (x - s->x0) + s->zb * (y - s->y0)) | s->tag;
    return 1;
}

/* ---- kernels ------------------------------------------------------------------------------ */

/* The part of sub s's box within r; 0 if empty. */
static int box_in(const wk_cpu_sub *s, const wk_rect *r, wk_rect *out)
{
    out->x0 = s->x0 > r->x0 ? s->x0 : r->x0;
    out->y0 = s->y0 > r->y0 ? s->y0 : r->y0;
    out->x1 = s->x1 < r->x1 ? s->x1 : r->x1;
    out->y1 = s->y1 < r->y1 ? s->y1 : r->y1;
    return out->x0 < out->x1 && out->y0 < out->y1;
}

/* Rows of a sub within a box, walked with each edge's bound on the columns kept exactly as
 * floor(f / |a|) plus a remainder, f being the edge function at the sub's column x0 (no division
 * after the first row): row y's covered pixels are exactly those with every edge function >= 0.
 * An edge with a > 0 bounds the columns from below (dx >= ceil(-f / a) = -floor(f / a)), one with
 * a < 0 from above (dx <= floor(f / -a)); an edge along the rows (a = 0) keeps or drops a row:
 * it walks as |a| = 1 (q = f) and drops the row when f < 0. Straight-line code per row. */
typedef struct span_walk {
    int64_t q[3], rem[3], m[3], bq[3], br[3];
    int kind[3];    /* 1 lower, -1 upper, 0 along the rows */
    int64_t lo, hi; /* the box's columns relative to the sub's x0 */
} span_walk;

static void span_begin(const wk_cpu_sub *s, const wk_rect *r, span_walk *w)
{
    w->lo = r->x0 - s->x0;
    w->hi = r->x1 - 1 - s->x0;
    for (int k = 0; k < 3; k++) {
        int64_t f = s->e[k] + s->b[k] * (r->y0 - s->y0), a = s->a[k];
        int64_t m = a > 0 ? a : a < 0 ? -a : 1;
        w->kind[k] = a > 0 ? 1 : a < 0 ? -1 : 0;
        w->m[k] = m;
        w->q[k] = floor_div(f, m);
        w->rem[k] = f - w->q[k] * m;
        w->bq[k] = floor_div(s->b[k], m);
        w->br[k] = s->b[k] - w->bq[k] * m;
    }
}

/* The covered columns [*x0, *x1) of the current row (relative to the sub's x0), then a step to
 * the next row. */
static inline void span_row(span_walk *w, int *x0, int *x1)
{
    int64_t lo = w->lo, hi = w->hi;
    for (int k = 0; k < 3; k++) {
        int64_t q = w->q[k];
        int64_t l = w->kind[k] > 0 ? -q : lo;
        int64_t u = w->kind[k] < 0 ? q : w->kind[k] == 0 && q < 0 ? lo - 1 : hi;
        lo = l > lo ? l : lo;
        hi = u < hi ? u : hi;
        int64_t rem = w->rem[k] + w->br[k];
        int carry = rem >= w->m[k];
        w->q[k] = q + w->bq[k] + carry;
        w->rem[k] = carry ? rem - w->m[k] : rem;
    }
    *x0 = (int)lo;
    *x1 = hi >= lo ? (int)hi + 1 : (int)lo;
}

/* How the tiles of box r stand to the sub: -1 all masked out or in front of it (nothing to
 * draw), 1 none is (no tile test needed), 0 some are. */
static int box_tiles(const wk_cpu_sub *s, const wk_cpu_keys *k, const wk_cpu_clip *clip,
                     const wk_rect *r)
{
    if (!k->tmax && !clip->tile_mask)
        return 1;
    const int T = WK_CPU_TILE;
    int open = 0, shut = 0;
    for (int ty = r->y0 / T; ty * T < r->y1; ty++)
        for (int tx = r->x0 / T; tx * T < r->x1; tx++) {
            int t = ty * k->tiles_w + tx;
            int is_open =
                (!clip->tile_mask || clip->tile_mask[t]) && (!k->tmax || s->zmin_key <= k->tmax[t]);
            open += is_open;
            shut += !is_open;
        }
    return !open ? -1 : !shut ? 1 : 0;
}

/* Min-update of columns [x0, x1) of one tile's row (key row `row`, absolute columns); changed
 * pixels logged (first touch) when log is not NULL. Fields are copied to locals: the key stores
 * could alias them otherwise. */
static inline __attribute__((always_inline)) size_t draw_run(const wk_cpu_sub *s, uint64_t *row,
                                                             int x0, int x1, int64_t z,
                                                             wk_cpu_log *log, uint32_t p0,
                                                             uint32_t y16, uint8_t flag)
{
    const int64_t za = s->za;
    const uint64_t tag = s->tag;
    size_t changed = 0;
    if (!log) {
        for (int x = x0; x < x1; x++, z += za) {
            uint64_t key = depth_key(z) | tag;
            if (key < row[x]) {
                row[x] = key;
                changed++;
            }
        }
        return changed;
    }
    uint32_t *stamp = log->stamp, now = log->now;
    size_t n = log->n;
    for (int x = x0; x < x1; x++, z += za) {
        uint64_t key = depth_key(z) | tag;
        if (key >= row[x])
            continue;
        uint32_t p = p0 + (uint32_t)x;
        if (stamp[p] != now) {
            stamp[p] = now;
            log->idx[n] = p;
            log->xy[n] = y16 | (uint32_t)x;
            log->old[n] = row[x];
            log->flag[n++] = flag;
        }
        row[x] = key;
        changed++;
    }
    log->n = n;
    return changed;
}

/* Min-update of columns [x0, x1) of row y (absolute), tile by tile. */
static size_t draw_span(const wk_cpu_sub *s, wk_cpu_keys *k, const wk_cpu_clip *clip,
                        wk_cpu_log *log, uint8_t flag, int y, int x0, int x1, int64_t zrow)
{
    size_t changed = 0;
    const int T = WK_CPU_TILE;
    const uint8_t *mask = clip->tile_mask ? clip->tile_mask + (y / T) * k->tiles_w : NULL;
    const uint64_t *tmax = k->tmax ? k->tmax + (y / T) * k->tiles_w : NULL;
    uint64_t *row = k->key + (size_t)y * k->width;
    const uint32_t p0 = (uint32_t)y * (uint32_t)k->width, y16 = WK_CPU_XY(0, y);
    for (int x = x0; x < x1;) {
        int end = (x / T + 1) * T < x1 ? (x / T + 1) * T : x1, t = x / T;
        if ((mask && !mask[t]) || (tmax && s->zmin_key > tmax[t])) {
            x = end;
            continue;
        }
        changed += draw_run(s, row, x, end, zrow + s->za * (x - s->x0), log, p0, y16, flag);
        x = end;
    }
    return changed;
}

/* Columns [x0, x1) of row y keeping the second least key as well. */
static size_t draw_span_second(const wk_cpu_sub *s, wk_cpu_keys *k, int y, int x0, int x1,
                               int64_t zrow)
{
    size_t changed = 0;
    uint64_t *row = k->key + (size_t)y * k->width;
    uint32_t *second = k->second + (size_t)y * k->width;
    int64_t z = zrow + s->za * (x0 - s->x0);
    for (int x = x0; x < x1; x++, z += s->za) {
        uint64_t key = depth_key(z) | s->tag;
        if (key < row[x]) {
            second[x] = wk_cpu_second_of(row[x]);
            row[x] = key;
            changed++;
        } else if (wk_cpu_second_of(key) < second[x] && key != row[x]) {
            second[x] = wk_cpu_second_of(key);
        }
    }
    return changed;
}

size_t wk_cpu_draw(const wk_cpu_sub *s, wk_cpu_keys *k, const wk_cpu_clip *clip, wk_cpu_log *log,
                   uint8_t flag)
{
    LM_ASSERT(!k->second || (!log && !k->tmax));
    wk_rect r;
    int tiles;
    if (!box_in(s, &clip->rect, &r) || (tiles = box_tiles(s, k, clip, &r)) < 0)
        return 0;
    span_walk w;
    span_begin(s, &r, &w);
    size_t changed = 0;
    int64_t zrow = s->z + s->zb * (r.y0 - s->y0);
    for (int y = r.y0; y < r.y1; y++, zrow += s->zb) {
        int x0, x1;
        span_row(&w, &x0, &x1);
        if (x0 >= x1)
            continue;
        if (k->second)
            changed += draw_span_second(s, k, y, s->x0 + x0, s->x0 + x1, zrow);
        else if (tiles) /* every tile open: the whole span at once */
            changed += draw_run(s, k->key + (size_t)y * k->width, s->x0 + x0, s->x0 + x1,
                                zrow + s->za * x0, log, (uint32_t)y * (uint32_t)k->width,
                                WK_CPU_XY(0, y), flag);
        else
            changed += draw_span(s, k, clip, log, flag, y, s->x0 + x0, s->x0 + x1, zrow);
    }
    return changed;
}

/* The pixels of clip where s is visible, up to `limit`: appended to out (log NULL) or logged as
 * new with flag `flag`, and set to the background when `clear` (log not NULL). The callers pass
 * constants, so each gets its own loop. */
static inline size_t owned_walk(const wk_cpu_sub *s, const wk_cpu_keys *k, const wk_rect *clip,
                                size_t limit, uint32_t *out, wk_cpu_log *log, uint8_t flag,
                                int clear)
{
    wk_rect r; /* a pixel whose key carries the tag is one the sub covers and wins */
    if (!box_in(s, clip, &r))
        return 0;
    span_walk w; /* along the covered columns only: fewer cache lines than the whole box */
    span_begin(s, &r, &w);
    size_t n = 0, n0 = log ? log->n : 0;
    for (int y = r.y0; y < r.y1; y++) {
        int x0, x1;
        span_row(&w, &x0, &x1);
        uint64_t *row = k->key + (size_t)y * k->width + s->x0;
        const uint32_t p0 = (uint32_t)y * (uint32_t)k->width + (uint32_t)s->x0;
        for (int x = x0; x < x1; x++) {
            if ((uint32_t)row[x] != s->tag)
                continue;
            uint32_t xy = WK_CPU_XY(s->x0 + x, y);
            if (log) {
                size_t j = n0 + n;
                log->stamp[p0 + (uint32_t)x] = log->now;
                log->idx[j] = p0 + (uint32_t)x;
                log->xy[j] = xy;
                log->old[j] = row[x];
                log->flag[j] = flag;
                if (clear)
                    row[x] = WK_CPU_KEY_BG;
            } else {
                out[n] = xy;
            }
            if (++n == limit)
                goto done;
        }
    }
done:
    if (log)
        log->n = n0 + n;
    return n;
}

size_t wk_cpu_owned(const wk_cpu_sub *s, const wk_cpu_keys *k, const wk_rect *clip, uint32_t *out,
                    size_t limit)
{
    return owned_walk(s, k, clip, limit, out, NULL, 0, 0);
}

size_t wk_cpu_log_owned(const wk_cpu_sub *s, wk_cpu_keys *k, wk_cpu_log *log, uint8_t flag,
                        int clear, size_t limit)
{
    const wk_rect all = {0, 0, k->width, k->height};
    return clear ? owned_walk(s, k, &all, limit, NULL, log, flag, 1)
                 : owned_walk(s, k, &all, limit, NULL, log, flag, 0);
}

void wk_cpu_keys_update_tiles(wk_cpu_keys *k, const wk_rect *r)
{
    const int T = WK_CPU_TILE;
    for (int ty = r->y0 / T; ty * T < r->y1; ty++) {
        int y1 = (ty + 1) * T < k->height ? (ty + 1) * T : k->height;
        for (int tx = r->x0 / T; tx * T < r->x1; tx++) {
            int x1 = (tx + 1) * T < k->width ? (tx + 1) * T : k->width;
            uint64_t m = 0;
            for (int y = ty * T; y < y1; y++) {
                const uint64_t *row = k->key + (size_t)y * k->width;
                for (int x = tx * T; x < x1; x++)
                    m = row[x] > m ? row[x] : m;
            }
            k->tmax[ty * k->tiles_w + tx] = m;
        }
    }
}
