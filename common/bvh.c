/* common/bvh.c — closest-point queries over a triangle mesh: build (median split of
 * the centroids on the box's longest axis), point-to-triangle distance by Voronoi regions, and a
 * depth-first query that visits the nearer child first and skips boxes farther than the best.
 * Boxes are floats, rounded outwards where a corner is not a float (the model's positions are, so
 * the boxes are exact). The build makes a binary tree of 32-byte nodes (a left child right after
 * its parent), then lays it out for queries (common/bvh_internal.h): an inner node holds both
 * children's boxes in one cache line, tested two-wide (child_box_sq: the same bits as the scalar
 * box_sq). That layout keeps every box, every box distance and the order of the visits, so it
 * changes which lines are read, never which triangles are tested or in what order: the same
 * distance bits, the same triangle at a tie (the first strict least in the nearer-first order,
 * left at equal box distances) and the same barycentrics as the 32-byte layout before it
 * (tests/unit/test_bvh.c checks against a scan and an unpruned walk). A box only ever decides
 * what is skipped, never a distance, so the result is the least distance over all triangles
 * whatever the boxes. */
#include "common/bvh.h"
#include "common/bvh_internal.h"

#include <float.h>
#include <math.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

/* A node of the build: a box, and a leaf's triangles or (count 0) the right child's index (the
 * left child is the next node). */
typedef struct flat_node {
    bvh_box box;
    uint32_t first, count;
} flat_node;

typedef struct build_ctx {
    lm_bvh *b;
    flat_node *flat;
    uint32_t n_flat;
    double (*centre)[3];
    uint32_t *order; /* triangle of each slot */
    double (*src)[3][3];
} build_ctx;

/* The box of slots [first, first + count) (lo, hi in double). */
static void slot_bounds(const build_ctx *c, uint32_t first, uint32_t count, double lo[3],
                        double hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = DBL_MAX;
        hi[k] = -DBL_MAX;
    }
    for (uint32_t i = first; i < first + count; i++)
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++) {
                double x = c->src[c->order[i]][v][k];
                lo[k] = x < lo[k] ? x : lo[k];
                hi[k] = x > hi[k] ? x : hi[k];
            }
}

/* The box in floats that holds [lo, hi]. */
static void node_box(bvh_box *nd, const double lo[3], const double hi[3])
{
    for (int k = 0; k < 3; k++) {
        float l = (float)lo[k], h = (float)hi[k];
        nd->lo[k] = (double)l > lo[k] ? nextafterf(l, -INFINITY) : l;
        nd->hi[k] = (double)h < hi[k] ? nextafterf(h, INFINITY) : h;
    }
}

/* Partition slots [first, first + count) around their median centroid on `axis` (quickselect). */
static void median_split(build_ctx *c, uint32_t first, uint32_t count, int axis)
{
    uint32_t lo = first, hi = first + count - 1, want = first + count / 2;
    while (lo < hi) {
        double pivot = c->centre[c->order[(lo + hi) / 2]][axis];
        uint32_t i = lo, j = hi;
        while (i <= j) {
            while (c->centre[c->order[i]][axis] < pivot)
                i++;
            while (c->centre[c->order[j]][axis] > pivot)
                j--;
            if (i <= j) {
                uint32_t t = c->order[i];
                c->order[i++] = c->order[j];
                c->order[j] = t;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (want <= j)
            hi = j;
        else if (want >= i)
            lo = i;
        else
            break;
    }
}

/* Build the subtree of slots [first, first + count); returns its node index. Depth is about
 * log2(n) (median splits), so recursion is bounded. */
static uint32_t build(build_ctx *c, uint32_t first, uint32_t count)
{
    uint32_t id = c->n_flat++;
    flat_node *nd = &c->flat[id];
    double lo[3], hi[3];
    slot_bounds(c, first, count, lo, hi);
    node_box(&nd->box, lo, hi);
    nd->first = first;
    nd->count = count;
    if (count <= LM_BVH_LEAF)
        return id;
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (hi[k] - lo[k] > hi[axis] - lo[axis])
            axis = k;
    median_split(c, first, count, axis);
    uint32_t half = count / 2;
    uint32_t left = build(c, first, half);
    uint32_t right = build(c, first + half, count - half);
    LM_ASSERT(left == id + 1);
    nd = &c->flat[id]; /* (no reallocation happens, but keep the pointer fresh) */
    nd->count = 0;
    nd->first = right;
    return id;
}

/* Lay flat node `id`'s subtree out in b->nodes (depth first, a left child right after its parent,
 * as in the build); *box gets its box. Returns the subtree's reference. */
static bvh_ref lay_out(lm_bvh *b, const flat_node *flat, uint32_t id, bvh_box *box)
{
    const flat_node *f = &flat[id];
    *box = f->box;
    if (f->count)
        return (bvh_ref){f->first, f->count};
    uint32_t me = b->n_nodes++;
    bvh_box box2[2];
    bvh_ref left = lay_out(b, flat, id + 1, &box2[0]);
    bvh_ref right = lay_out(b, flat, f->first, &box2[1]);
    bvh_node *nd = &b->nodes[me];
    nd->child[0] = left, nd->child[1] = right;
    for (int c = 0; c < 2; c++)
        for (int k = 0; k < 3; k++)
            nd->lo[k][c] = box2[c].lo[k], nd->hi[k][c] = box2[c].hi[k];
    return (bvh_ref){me, 0};
}

static lm_status gather(const lm_mesh *m, build_ctx *c, uint32_t n)
{
    c->src = malloc((size_t)n * sizeof *c->src);
    c->centre = malloc((size_t)n * sizeof *c->centre);
    c->order = malloc((size_t)n * sizeof *c->order);
    c->b->id = malloc((size_t)n * sizeof *c->b->id);
    if (!c->src || !c->centre || !c->order || !c->b->id)
        return lm_fail(LM_E_NOMEM, "out of memory for the distance hierarchy");
    uint32_t i = 0;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        for (int v = 0; v < 3; v++) {
            const float *p = m->pos[lm_tri_vertex(m, t, v)];
            for (int k = 0; k < 3; k++)
                c->src[i][v][k] = p[k];
        }
        for (int k = 0; k < 3; k++)
            c->centre[i][k] = (c->src[i][0][k] + c->src[i][1][k] + c->src[i][2][k]) / 3.0;
        c->order[i] = i;
        c->b->id[i] = t;
        i++;
    }
    return LM_OK;
}

lm_status lm_bvh_create(const lm_mesh *m, lm_bvh **out)
{
    *out = NULL;
    uint32_t n = m->live_tris;
    if (n == 0)
        return lm_fail(LM_E_INVALID, "a distance hierarchy needs at least one triangle");
    lm_bvh *b = calloc(1, sizeof *b);
    build_ctx c = {.b = b};
    lm_status s = b ? gather(m, &c, n) : lm_fail(LM_E_NOMEM, "out of memory");
    if (!s) {
        b->n = n;
        c.flat = malloc(2 * (size_t)n * sizeof *c.flat);
        b->nodes = aligned_alloc(64, (size_t)n * sizeof *b->nodes); /* n - 1 inner nodes */
        b->tri = malloc((size_t)n * sizeof *b->tri);
        if (!c.flat || !b->nodes || !b->tri)
            s = lm_fail(LM_E_NOMEM, "out of memory for the distance hierarchy");
    }
    if (!s) {
        build(&c, 0, n);
        b->root = lay_out(b, c.flat, 0, &b->root_box);
        LM_ASSERT(b->n_nodes < n || n == 1);
        for (uint32_t i = 0; i < n; i++)
            for (int v = 0; v < 3; v++)
                for (int k = 0; k < 3; k++)
                    b->tri[i][v][k] = (float)c.src[c.order[i]][v][k]; /* exact: floats */
        for (uint32_t i = 0; i < n; i++) /* slot -> mesh id, in leaf order like tri */
            c.centre[i][0] = b->id[c.order[i]];
        for (uint32_t i = 0; i < n; i++)
            b->id[i] = (uint32_t)c.centre[i][0];
    }
    free(c.flat);
    free(c.src);
    free(c.centre);
    free(c.order);
    if (s) {
        lm_bvh_destroy(b);
        return s;
    }
    *out = b;
    return LM_OK;
}

void lm_bvh_destroy(lm_bvh *b)
{
    if (!b)
        return;
    free(b->tri);
    free(b->id);
    free(b->nodes);
    free(b);
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double dist_sq(const double p[3], const double q[3])
{
    double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    return dot3(d, d);
}

/* q = a + s*ab + t*ac */
static double at(const double p[3], const double a[3], const double ab[3], const double ac[3],
                 double s, double t)
{
    double q[3];
    for (int k = 0; k < 3; k++)
        q[k] = a[k] + s * ab[k] + t * ac[k];
    return dist_sq(p, q);
}

/* Where the closest point of triangle (a, b, c) to p lies: a corner (PT_A, PT_B, PT_C), or
 * a + s*ab + t*ac (PT_ST), or the triangle is degenerate (PT_FLAT: the nearest corner). */
enum { PT_A, PT_B, PT_C, PT_ST, PT_FLAT };

static int closest_region(const double p[3], const double a[3], const double b[3],
                          const double c[3], double ab[3], double ac[3], double *s, double *t)
{
    double ap[3], bp[3], cp[3];
    for (int k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k], ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k], bp[k] = p[k] - b[k], cp[k] = p[k] - c[k];
    }
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return PT_A;
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return PT_B;
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
        return *s = d1 / (d1 - d3), *t = 0, PT_ST;
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return PT_C;
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
        return *s = 0, *t = d2 / (d2 - d6), PT_ST;
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return *s = 1 - w, *t = w, PT_ST;
    }
    double sum = va + vb + vc;
    if (!(sum > 0)) /* degenerate triangle: nearest of its corners */
        return PT_FLAT;
    return *s = vb / sum, *t = vc / sum, PT_ST;
}

double lm_point_triangle_sq(const double p[3], const double a[3], const double b[3],
                            const double c[3])
{
    double ab[3], ac[3], s = 0, t = 0;
    switch (closest_region(p, a, b, c, ab, ac, &s, &t)) {
    case PT_A:
        return dist_sq(p, a);
    case PT_B:
        return dist_sq(p, b);
    case PT_C:
        return dist_sq(p, c);
    case PT_ST:
        return at(p, a, ab, ac, s, t);
    default:
        return fmin(dist_sq(p, a), fmin(dist_sq(p, b), dist_sq(p, c)));
    }
}

double lm_point_triangle_bary(const double p[3], const double a[3], const double b[3],
                              const double c[3], double bary[3])
{
    double ab[3], ac[3], s = 0, t = 0;
    int r = closest_region(p, a, b, c, ab, ac, &s, &t);
    if (r == PT_FLAT) {
        double da = dist_sq(p, a), db = dist_sq(p, b), dc = dist_sq(p, c);
        r = da <= db && da <= dc ? PT_A : db <= dc ? PT_B : PT_C;
    }
    bary[0] = r == PT_A, bary[1] = r == PT_B, bary[2] = r == PT_C;
    if (r == PT_ST)
        bary[0] = 1 - s - t, bary[1] = s, bary[2] = t;
    return r == PT_ST ? at(p, a, ab, ac, s, t) : dist_sq(p, r == PT_A ? a : r == PT_B ? b : c);
}

/* How far p is outside [lo, hi] along one axis (0 inside): lo - p below, p - hi above, computed
 * without branches (lo <= hi: at most one of them is positive). */
static inline double axis_gap(double p, double lo, double hi)
{
    double below = lo - p, above = p - hi;
    double e = below > above ? below : above;
    return e > 0 ? e : 0;
}

/* The squared distance from p to the box (the same sum, in the same order, as a loop over k). */
static inline double box_sq(const bvh_box *nd, const double p[3])
{
    double e0 = axis_gap(p[0], nd->lo[0], nd->hi[0]);
    double e1 = axis_gap(p[1], nd->lo[1], nd->hi[1]);
    double e2 = axis_gap(p[2], nd->lo[2], nd->hi[2]);
    return (e0 * e0 + e1 * e1) + e2 * e2;
}

/* Both children's box distances: d[c] = box_sq(child c's box, p), bit for bit (the same
 * operations in the same order, two lanes at once where SSE2 is there). */
static inline void child_box_sq(const bvh_node *nd, const double p[3], double d[2])
{
#ifdef __SSE2__
    __m128d sum = _mm_setzero_pd();
    for (int k = 0; k < 3; k++) {
        __m128d pk = _mm_set1_pd(p[k]);
        __m128d lo = _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)nd->lo[k])));
        __m128d hi = _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)nd->hi[k])));
        __m128d below = _mm_sub_pd(lo, pk), above = _mm_sub_pd(pk, hi);
        /* max_pd(a, b) = a > b ? a : b, as axis_gap */
        __m128d e = _mm_max_pd(_mm_max_pd(below, above), _mm_setzero_pd());
        __m128d e2 = _mm_mul_pd(e, e);
        sum = k == 0 ? e2 : _mm_add_pd(sum, e2);
    }
    _mm_storeu_pd(d, sum);
#else
    for (int c = 0; c < 2; c++) {
        bvh_box bx = bvh_child_box(nd, c);
        d[c] = box_sq(&bx, p);
    }
#endif
}

/* Leaf ref's triangles: the least distance below *best (kept in *best); with tri (not NULL) also
 * the first such triangle's id and p's barycentrics on it (strictly less: at a tie the earlier
 * slot stays). */
static inline void leaf_closest(const lm_bvh *b, bvh_ref ref, const double p[3], double *best,
                                uint32_t *tri, double bary[3])
{
    double w[3];
    for (uint32_t i = ref.first; i < ref.first + ref.count; i++) {
        double t[3][3];
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++)
                t[v][k] = b->tri[i][v][k];
        if (!tri) {
            double d = lm_point_triangle_sq(p, t[0], t[1], t[2]);
            *best = d < *best ? d : *best;
            continue;
        }
        double d = lm_point_triangle_bary(p, t[0], t[1], t[2], w);
        if (d < *best) {
            *best = d;
            *tri = b->id[i];
            memcpy(bary, w, sizeof w);
        }
    }
}

/* The closest triangle's squared distance; with tri (not NULL) also its id and p's barycentrics
 * on it. Inlined into both queries, so the distance-only one pays nothing for them. */
static inline double closest(const lm_bvh *b, const double p[3], uint32_t *tri, double bary[3])
{
    double best = DBL_MAX;
    if (tri)
        *tri = LM_NONE;
    struct {
        bvh_ref ref;
        double d; /* its box's squared distance, a lower bound of its triangles' */
    } stack[LM_BVH_STACK];
    int top = 0;
    bvh_ref ref = b->root;
    double d = box_sq(&b->root_box, p);
    for (;;) {
        if (d < best && ref.count) {
            leaf_closest(b, ref, p, &best, tri, bary);
        } else if (d < best) {
            const bvh_node *nd = &b->nodes[ref.first];
            int near = 0;
            double dd[2];
            child_box_sq(nd, p, dd);
            double dn = dd[0], df = dd[1];
            if (df < dn) {
                double td = dn;
                near = 1;
                dn = df, df = td;
            }
            LM_ASSERT(top + 1 <= LM_BVH_STACK);
            if (df < best) {
                stack[top].ref = nd->child[1 - near];
                stack[top++].d = df;
            }
            if (dn < best) { /* the nearer child next, as if pushed last and popped */
                ref = nd->child[near], d = dn;
                continue;
            }
        }
        if (top == 0)
            break;
        --top;
        ref = stack[top].ref, d = stack[top].d;
    }
    return best;
}

/* 1 when a triangle of leaf ref is within squared distance r2 of p. */
static int leaf_within(const lm_bvh *b, bvh_ref ref, const double p[3], double r2)
{
    for (uint32_t i = ref.first; i < ref.first + ref.count; i++) {
        double t[3][3];
        for (int v = 0; v < 3; v++)
            for (int k = 0; k < 3; k++)
                t[v][k] = b->tri[i][v][k];
        if (lm_point_triangle_sq(p, t[0], t[1], t[2]) <= r2)
            return 1;
    }
    return 0;
}

int lm_bvh_within(const lm_bvh *b, const double p[3], double r2)
{
    bvh_ref stack[LM_BVH_STACK];
    int top = 0;
    if (box_sq(&b->root_box, p) > r2)
        return 0;
    stack[top++] = b->root;
    while (top > 0) {
        bvh_ref ref = stack[--top];
        if (ref.count) {
            if (leaf_within(b, ref, p, r2))
                return 1;
            continue;
        }
        const bvh_node *nd = &b->nodes[ref.first];
        double dd[2];
        child_box_sq(nd, p, dd);
        double dn = dd[0], df = dd[1];
        LM_ASSERT(top + 2 <= LM_BVH_STACK);
        if (df <= r2 && df >= dn)
            stack[top++] = nd->child[1];
        if (dn <= r2)
            stack[top++] = nd->child[0];
        if (df <= r2 && df < dn)
            stack[top++] = nd->child[1];
    }
    return 0;
}

double lm_bvh_closest_sq(const lm_bvh *b, const double p[3])
{
    return closest(b, p, NULL, NULL);
}

double lm_bvh_closest_tri(const lm_bvh *b, const double p[3], uint32_t *tri, double bary[3])
{
    return closest(b, p, tri, bary);
}
