/* common/bvh_ray.c — line queries over the hierarchy of common/bvh.c: the hit nearest a point
 * along a line, both ways (a bake's ray from the result's surface to the original's, which may lie
 * on either side). Slab tests against the nodes' boxes, Möller–Trumbore against the triangles, in
 * double precision without contracted multiply-adds (common/CMakeLists.txt). */
#include "common/bvh.h"

#include <float.h>
#include <math.h>

#include "common/bvh_internal.h"

/* The interval [*lo, *hi] of t in [-tmax, tmax] where o + t d is in the node's box; 0 if empty. */
static int box_span(const bvh_box *nd, const double o[3], const double d[3], double tmax,
                    double *lo, double *hi)
{
    double a = -tmax, b = tmax;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0) {
            if (o[k] < nd->lo[k] || o[k] > nd->hi[k])
                return 0;
            continue;
        }
        double t0 = (nd->lo[k] - o[k]) / d[k], t1 = (nd->hi[k] - o[k]) / d[k];
        if (t0 > t1) {
            double s = t0;
            t0 = t1, t1 = s;
        }
        a = t0 > a ? t0 : a;
        b = t1 < b ? t1 : b;
        if (a > b)
            return 0;
    }
    *lo = a, *hi = b;
    return 1;
}

/* The least |t| over [lo, hi]. */
static double span_near(double lo, double hi)
{
    return lo > 0.0 ? lo : hi < 0.0 ? -hi : 0.0;
}

/* Möller–Trumbore: 1 with t and the barycentrics where the line meets triangle tr (with facing,
 * only a triangle whose front, counter-clockwise, faces along d). */
static int tri_hit(const float tr[3][3], const double o[3], const double d[3], int facing,
                   double *t, double bary[3])
{
    double e1[3], e2[3], s[3], p[3], q[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)tr[1][k] - tr[0][k];
        e2[k] = (double)tr[2][k] - tr[0][k];
        s[k] = o[k] - tr[0][k];
    }
    p[0] = d[1] * e2[2] - d[2] * e2[1];
    p[1] = d[2] * e2[0] - d[0] * e2[2];
    p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0.0 || !isfinite(det) || (facing && det > 0.0)) /* det = -d . (e1 x e2) */
        return 0;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    if (u < 0.0 || u > 1.0)
        return 0;
    q[0] = s[1] * e1[2] - s[2] * e1[1];
    q[1] = s[2] * e1[0] - s[0] * e1[2];
    q[2] = s[0] * e1[1] - s[1] * e1[0];
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    if (v < 0.0 || u + v > 1.0)
        return 0;
    *t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    bary[0] = 1.0 - u - v, bary[1] = u, bary[2] = v;
    return 1;
}

int lm_bvh_line_hit(const lm_bvh *b, const double o[3], const double d[3], double tmax, int facing,
                    uint32_t *tri, double *t, double bary[3])
{
    double best = DBL_MAX;
    struct {
        bvh_ref ref;
        bvh_box box;
    } stack[LM_BVH_STACK];
    int top = 0;
    double lo, hi;
    if (box_span(&b->root_box, o, d, tmax, &lo, &hi)) {
        stack[top].ref = b->root;
        stack[top++].box = b->root_box;
    }
    while (top > 0) {
        --top;
        bvh_ref ref = stack[top].ref;
        if (!box_span(&stack[top].box, o, d, tmax, &lo, &hi) || span_near(lo, hi) >= best)
            continue;
        if (!ref.count) {
            const bvh_node *nd = &b->nodes[ref.first];
            LM_ASSERT(top + 2 <= LM_BVH_STACK);
            for (int side = 1; side >= 0; side--) { /* right below left: left is popped first */
                stack[top].ref = nd->child[side];
                stack[top++].box = bvh_child_box(nd, side);
            }
            continue;
        }
        for (uint32_t i = ref.first; i < ref.first + ref.count; i++) {
            double ti, w[3];
            if (!tri_hit(b->tri[i], o, d, facing, &ti, w) || fabs(ti) > tmax || fabs(ti) >= best)
                continue;
            best = fabs(ti);
            *tri = b->id[i], *t = ti;
            bary[0] = w[0], bary[1] = w[1], bary[2] = w[2];
        }
    }
    return best != DBL_MAX;
}
