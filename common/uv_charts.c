/* common/uv_charts.c — charts of adjacent near-planar triangles, flattened by projection (see
 * uv_charts.h): edge adjacency by sorting, breadth-first growth with the normal, flip and overlap
 * tests, then each chart turned to its smallest bounding rectangle. */
#include "common/uv_charts.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

typedef struct edge {
    uint32_t a, b; /* vertices, a < b */
    uint32_t tri;  /* live index */
    int k;         /* the edge runs from corner k to k + 1 */
    int fwd;       /* 1 when the triangle runs a -> b */
} edge;

static int edge_cmp(const void *pa, const void *pb)
{
    const edge *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return x->tri < y->tri ? -1 : x->tri > y->tri;
}

/* Work state of one segmentation. */
typedef struct seg {
    const lm_mesh *m;
    lm_charts *c;
    double (*n)[3];    /* unit face normals */
    uint8_t *flat;     /* 1: no area (degenerate) */
    uint32_t (*nb)[3]; /* neighbour across edge k (k -> k+1), LM_NONE if none */
    uint32_t *order;   /* live indices grouped by chart, in growth order */
    uint32_t *start;   /* [n_charts + 1] each chart's first entry in order */
    double (*bb)[4];   /* 2-D bounds per live triangle: x0, y0, x1, y1 */
    uint32_t *stamp;   /* last chart a triangle was rejected from + 1 */
} seg;

static void seg_free(seg *s)
{
    free(s->n);
    free(s->flat);
    free(s->nb);
    free(s->order);
    free(s->start);
    free(s->bb);
    free(s->stamp);
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void face_normals(seg *s)
{
    for (uint32_t i = 0; i < s->c->n_tris; i++) {
        double *n = s->n[i];
        lm_mesh_face_normal(s->m, s->c->tri[i], n);
        double len = sqrt(dot3(n, n));
        s->flat[i] = !(len > 1e-20) || !isfinite(len);
        for (int k = 0; k < 3; k++)
            n[k] = s->flat[i] ? 0.0 : n[k] / len;
    }
}

/* Two triangles may share a chart across an edge: same material and part. */
static int joinable(const lm_mesh *m, uint32_t t, uint32_t u)
{
    return m->tris[t].material == m->tris[u].material && m->tris[t].part == m->tris[u].part;
}

/* Neighbours across manifold, consistently oriented edges. */
static lm_status adjacency(seg *s)
{
    uint32_t n = s->c->n_tris;
    edge *e = malloc((3 * (size_t)n + 1) * sizeof *e);
    if (!e)
        return LM_E_NOMEM;
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t p = lm_tri_vertex(s->m, s->c->tri[i], k),
                     q = lm_tri_vertex(s->m, s->c->tri[i], (k + 1) % 3);
            edge *x = &e[3 * (size_t)i + k];
            x->a = p < q ? p : q, x->b = p < q ? q : p, x->tri = i, x->k = k, x->fwd = p < q;
            s->nb[i][k] = LM_NONE;
        }
    qsort(e, 3 * (size_t)n, sizeof *e, edge_cmp);
    for (size_t j = 0; j < 3 * (size_t)n;) {
        size_t end = j + 1;
        while (end < 3 * (size_t)n && e[end].a == e[j].a && e[end].b == e[j].b)
            end++;
        if (end - j == 2 && e[j].fwd != e[j + 1].fwd && e[j].a != e[j].b &&
            joinable(s->m, s->c->tri[e[j].tri], s->c->tri[e[j + 1].tri])) {
            s->nb[e[j].tri][e[j].k] = e[j + 1].tri;
            s->nb[e[j + 1].tri][e[j + 1].k] = e[j].tri;
        }
        j = end;
    }
    free(e);
    return LM_OK;
}

/* A fixed orthonormal pair ax, ay with ax × ay = n (unit). */
static void plane_axes(const double n[3], double ax[3], double ay[3])
{
    int a = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0
            : fabs(n[1]) <= fabs(n[2])                           ? 1
                                                                 : 2;
    double e[3] = {0, 0, 0};
    e[a] = 1.0;
    for (int k = 0; k < 3; k++)
        ax[k] = e[k] - n[k] * n[a];
    double len = sqrt(dot3(ax, ax));
    for (int k = 0; k < 3; k++)
        ax[k] /= len;
    ay[0] = n[1] * ax[2] - n[2] * ax[1];
    ay[1] = n[2] * ax[0] - n[0] * ax[2];
    ay[2] = n[0] * ax[1] - n[1] * ax[0];
}

/* Live triangle i projected on the plane (ax, ay) into s->c->xy[i] and its bounds. */
static void project(seg *s, uint32_t i, const double ax[3], const double ay[3])
{
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int k = 0; k < 3; k++) {
        const float *p = s->m->pos[lm_tri_vertex(s->m, s->c->tri[i], k)];
        double q[3] = {p[0], p[1], p[2]};
        double x = dot3(q, ax), y = dot3(q, ay);
        s->c->xy[i][k][0] = x, s->c->xy[i][k][1] = y;
        x0 = x < x0 ? x : x0, y0 = y < y0 ? y : y0, x1 = x > x1 ? x : x1, y1 = y > y1 ? y : y1;
    }
    s->bb[i][0] = x0, s->bb[i][1] = y0, s->bb[i][2] = x1, s->bb[i][3] = y1;
}

static double area2(const double t[3][2])
{
    return (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]);
}

/* The span of t on axis (x, y); *lo, *hi. */
static void span(const double t[3][2], double x, double y, double *lo, double *hi)
{
    *lo = *hi = t[0][0] * x + t[0][1] * y;
    for (int k = 1; k < 3; k++) {
        double d = t[k][0] * x + t[k][1] * y;
        *lo = d < *lo ? d : *lo, *hi = d > *hi ? d : *hi;
    }
}

static double longest_edge(const double t[3][2])
{
    double best = 0.0;
    for (int k = 0; k < 3; k++) {
        double dx = t[(k + 1) % 3][0] - t[k][0], dy = t[(k + 1) % 3][1] - t[k][1];
        double len = sqrt(dx * dx + dy * dy);
        best = len > best ? len : best;
    }
    return best;
}

/* 1 when one of a's edge normals separates a and b (within tol). */
static int separated_by(const double a[3][2], const double b[3][2], double tol)
{
    for (int k = 0; k < 3; k++) {
        double x = -(a[(k + 1) % 3][1] - a[k][1]), y = a[(k + 1) % 3][0] - a[k][0];
        double len = sqrt(x * x + y * y);
        if (!(len > 0.0))
            continue;
        x /= len, y /= len;
        double alo, ahi, blo, bhi;
        span(a, x, y, &alo, &ahi);
        span(b, x, y, &blo, &bhi);
        if (ahi <= blo + tol || bhi <= alo + tol)
            return 1;
    }
    return 0;
}

int lm_tri2_overlap(const double a[3][2], const double b[3][2])
{
    if (area2(a) == 0.0 || area2(b) == 0.0)
        return 0;
    double la = longest_edge(a), lb = longest_edge(b);
    double tol = 1e-7 * (la > lb ? la : lb);
    return !separated_by(a, b, tol) && !separated_by(b, a, tol);
}

/* 1 when live triangle i (projected) overlaps one of order[from..to). */
static int overlaps_chart(const seg *s, uint32_t i, uint32_t from, uint32_t to)
{
    const double *bi = s->bb[i];
    for (uint32_t j = from; j < to; j++) {
        uint32_t o = s->order[j];
        const double *bo = s->bb[o];
        if (bo[0] >= bi[2] || bi[0] >= bo[2] || bo[1] >= bi[3] || bi[1] >= bo[3])
            continue;
        if (lm_tri2_overlap((const double(*)[2])s->c->xy[i], (const double(*)[2])s->c->xy[o]))
            return 1;
    }
    return 0;
}

/* Whether live triangle i joins the chart order[from..to) of seed normal n on axes ax, ay
 * (projected into xy when it does). */
static int accepts(seg *s, uint32_t i, const double n[3], const double ax[3], const double ay[3],
                   uint32_t from, uint32_t to)
{
    double cosmax = cos(LM_CHART_MAX_ANGLE * PI / 180.0);
    if (!s->flat[i] && dot3(s->n[i], n) < cosmax)
        return 0;
    project(s, i, ax, ay);
    if (s->flat[i])
        return 1;
    return area2((const double(*)[2])s->c->xy[i]) > 0.0 && !overlaps_chart(s, i, from, to);
}

/* Grows chart c from seed live triangle `seed` (order[*len] on); *len advanced. */
static void grow(seg *s, uint32_t seed, uint32_t c, uint32_t *len)
{
    uint32_t from = *len;
    double ax[3], ay[3];
    const double *n = s->n[seed];
    plane_axes(s->flat[seed] ? (const double[3]){0, 0, 1} : n, ax, ay);
    project(s, seed, ax, ay);
    s->c->chart[seed] = c;
    s->order[(*len)++] = seed;
    for (uint32_t q = from; q < *len && !s->flat[seed]; q++) {
        uint32_t t = s->order[q];
        for (int k = 0; k < 3; k++) {
            uint32_t u = s->nb[t][k];
            if (u == LM_NONE || s->c->chart[u] != LM_NONE || s->stamp[u] == c + 1 ||
                *len - from >= LM_CHART_MAX_TRIS)
                continue;
            if (!accepts(s, u, n, ax, ay, from, *len)) {
                s->stamp[u] = c + 1;
                continue;
            }
            s->c->chart[u] = c;
            s->order[(*len)++] = u;
        }
    }
}

typedef struct pt2 {
    double x, y;
} pt2;

static int pt_cmp(const void *pa, const void *pb)
{
    const pt2 *p = pa, *q = pb;
    if (p->x != q->x)
        return p->x < q->x ? -1 : 1;
    return p->y < q->y ? -1 : p->y > q->y;
}

static double cross(pt2 o, pt2 a, pt2 b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/* Convex hull of p[0..n) (sorted in place) into h (room for 2n), counter-clockwise; its size. */
static uint32_t hull(pt2 *p, uint32_t n, pt2 *h)
{
    qsort(p, n, sizeof *p, pt_cmp);
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++) {
        while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0.0)
            k--;
        h[k++] = p[i];
    }
    for (uint32_t i = n - 1, lo = k + 1; i-- > 0;) {
        while (k >= lo && cross(h[k - 2], h[k - 1], p[i]) <= 0.0)
            k--;
        h[k++] = p[i];
    }
    return k > 1 ? k - 1 : k;
}

/* The direction (c, s) of h's edge whose aligned bounding rectangle is smallest. */
static void best_direction(const pt2 *h, uint32_t nh, double *cs, double *sn)
{
    double best = INFINITY;
    *cs = 1.0, *sn = 0.0;
    for (uint32_t e = 0; e < nh; e++) {
        double dx = h[(e + 1) % nh].x - h[e].x, dy = h[(e + 1) % nh].y - h[e].y;
        double len = sqrt(dx * dx + dy * dy);
        if (!(len > 0.0))
            continue;
        double c = dx / len, s = dy / len, x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY,
               y1 = -INFINITY;
        for (uint32_t i = 0; i < nh; i++) {
            double x = c * h[i].x + s * h[i].y, y = -s * h[i].x + c * h[i].y;
            x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1, y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
        }
        double area = (x1 - x0) * (y1 - y0);
        if (area < best)
            best = area, *cs = c, *sn = s;
    }
}

/* Turns chart c's corners (rotation only: orientation kept) to its smallest rectangle, longer
 * side along x, from the origin; its extent. pts, h: room for 3 and 6 points a triangle. */
static void settle(seg *s, uint32_t c, pt2 *pts, pt2 *h)
{
    uint32_t from = s->start[c], to = s->start[c + 1], n = 0;
    for (uint32_t j = from; j < to; j++)
        for (int k = 0; k < 3; k++)
            pts[n++] = (pt2){s->c->xy[s->order[j]][k][0], s->c->xy[s->order[j]][k][1]};
    uint32_t nh = hull(pts, n, h);
    double cs, sn, x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    best_direction(h, nh, &cs, &sn);
    for (uint32_t j = from; j < to; j++)
        for (int k = 0; k < 3; k++) {
            double *p = s->c->xy[s->order[j]][k];
            double x = cs * p[0] + sn * p[1], y = -sn * p[0] + cs * p[1];
            p[0] = x, p[1] = y;
            x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1, y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
        }
    int turn = y1 - y0 > x1 - x0; /* a quarter turn: (x, y) -> (-y, x) */
    for (uint32_t j = from; j < to; j++) {
        uint32_t i = s->order[j];
        for (int k = 0; k < 3; k++) {
            double *p = s->c->xy[i][k];
            double x = turn ? y1 - p[1] : p[0] - x0, y = turn ? p[0] - x0 : p[1] - y0;
            p[0] = x, p[1] = y;
        }
        s->c->area += 0.5 * fabs(area2((const double(*)[2])s->c->xy[i]));
    }
    s->c->extent[c][0] = turn ? y1 - y0 : x1 - x0;
    s->c->extent[c][1] = turn ? x1 - x0 : y1 - y0;
}

static lm_status segment(seg *s)
{
    uint32_t n = s->c->n_tris, len = 0, charts = 0;
    for (uint32_t i = 0; i < n; i++)
        s->c->chart[i] = LM_NONE, s->stamp[i] = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (s->c->chart[i] != LM_NONE)
            continue;
        s->start[charts] = len;
        grow(s, i, charts++, &len);
    }
    s->start[charts] = len;
    s->c->n_charts = charts;
    s->c->extent = malloc(((size_t)charts + 1) * sizeof *s->c->extent);
    uint32_t most = 0;
    for (uint32_t c = 0; c < charts; c++)
        most = s->start[c + 1] - s->start[c] > most ? s->start[c + 1] - s->start[c] : most;
    pt2 *pts = malloc((3 * (size_t)most + 1) * sizeof *pts),
        *h = malloc((6 * (size_t)most + 2) * sizeof *h);
    if (!s->c->extent || !pts || !h) {
        free(pts);
        free(h);
        return LM_E_NOMEM;
    }
    for (uint32_t c = 0; c < charts; c++)
        settle(s, c, pts, h);
    free(pts);
    free(h);
    return LM_OK;
}

static lm_status alloc_all(seg *s, uint32_t n)
{
    size_t m = (size_t)n + 1;
    lm_charts *c = s->c;
    c->tri = malloc(m * sizeof *c->tri);
    c->chart = malloc(m * sizeof *c->chart);
    c->xy = malloc(m * sizeof *c->xy);
    s->n = malloc(m * sizeof *s->n);
    s->flat = malloc(m);
    s->nb = malloc(m * sizeof *s->nb);
    s->order = malloc(m * sizeof *s->order);
    s->start = malloc((m + 1) * sizeof *s->start);
    s->bb = malloc(m * sizeof *s->bb);
    s->stamp = malloc(m * sizeof *s->stamp);
    return c->tri && c->chart && c->xy && s->n && s->flat && s->nb && s->order && s->start &&
                   s->bb && s->stamp
               ? LM_OK
               : LM_E_NOMEM;
}

lm_status lm_charts_make(const lm_mesh *m, lm_charts *c)
{
    memset(c, 0, sizeof *c);
    seg s;
    memset(&s, 0, sizeof s);
    s.m = m, s.c = c;
    lm_status st = alloc_all(&s, m->live_tris);
    for (uint32_t t = 0; st == LM_OK && t < m->n_tris; t++)
        if (m->tri_alive[t])
            c->tri[c->n_tris++] = t;
    if (st == LM_OK) {
        face_normals(&s);
        st = adjacency(&s);
    }
    if (st == LM_OK)
        st = segment(&s);
    seg_free(&s);
    if (st != LM_OK) {
        lm_charts_free(c);
        return lm_fail(LM_E_NOMEM, "out of memory for the charts of %u triangles", m->live_tris);
    }
    return LM_OK;
}

void lm_charts_free(lm_charts *c)
{
    free(c->tri);
    free(c->chart);
    free(c->xy);
    free(c->extent);
    memset(c, 0, sizeof *c);
}
