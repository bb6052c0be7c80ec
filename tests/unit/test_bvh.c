/* tests/unit/test_bvh.c — the hierarchy's queries (common/bvh.c) against references that test
 * every triangle: the least distance equal to a scan's, bit for bit; lm_bvh_within equal to
 * "scan <= r2"; and lm_bvh_closest_tri's triangle and barycentrics at ties equal to those of a
 * walk without pruning in the hierarchy's order (nearer child first, left at equal distances:
 * the first triangle at the least distance). Points are drawn where ties and rounding live: on and
 * near vertices and edges, on a flat grid (every triangle around a vertex at the same distance),
 * and far away. */
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "common/bvh_internal.h"
#include "coordinator/frog/frog.h"

static void corners(const lm_mesh *m, uint32_t t, double v[3][3])
{
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            v[k][j] = m->pos[lm_tri_vertex(m, t, k)][j];
}

static double scan_sq(const lm_mesh *m, const double p[3])
{
    double best = INFINITY;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        double v[3][3];
        corners(m, t, v);
        double d = lm_point_triangle_sq(p, v[0], v[1], v[2]);
        best = d < best ? d : best;
    }
    return best;
}

static double box_dist(const bvh_box *bx, const double p[3])
{
    double d = 0;
    for (int k = 0; k < 3; k++) {
        double lo = bx->lo[k], hi = bx->hi[k];
        double e = p[k] < lo ? lo - p[k] : p[k] > hi ? p[k] - hi : 0;
        d += e * e;
    }
    return d;
}

typedef struct walk {
    double best, bary[3];
    uint32_t tri;
} walk;

/* Every triangle, in the hierarchy's order for p, without pruning; the first strict least. */
static void walk_all(const lm_bvh *b, bvh_ref ref, const double p[3], walk *w)
{
    if (ref.count) {
        for (uint32_t i = ref.first; i < ref.first + ref.count; i++) {
            double t[3][3], bary[3];
            for (int v = 0; v < 3; v++)
                for (int k = 0; k < 3; k++)
                    t[v][k] = b->tri[i][v][k];
            double d = lm_point_triangle_bary(p, t[0], t[1], t[2], bary);
            if (d < w->best) {
                w->best = d, w->tri = b->id[i];
                memcpy(w->bary, bary, sizeof bary);
            }
        }
        return;
    }
    const bvh_node *nd = &b->nodes[ref.first];
    bvh_box left = bvh_child_box(nd, 0), right = bvh_child_box(nd, 1);
    int near = box_dist(&right, p) < box_dist(&left, p);
    walk_all(b, nd->child[near], p, w);
    walk_all(b, nd->child[1 - near], p, w);
}

/* All three queries at p against the references. */
static void check_point(const lm_mesh *m, const lm_bvh *b, const double p[3])
{
    double want = scan_sq(m, p);
    assert_true(lm_bvh_closest_sq(b, p) == want);
    walk w = {.best = DBL_MAX, .tri = LM_NONE};
    walk_all(b, b->root, p, &w);
    assert_true(w.best == want);
    uint32_t tri = 0;
    double bary[3];
    assert_true(lm_bvh_closest_tri(b, p, &tri, bary) == want);
    assert_int_equal(tri, w.tri);
    assert_memory_equal(bary, w.bary, sizeof bary);
    assert_true(lm_bvh_within(b, p, want));
    assert_true(!lm_bvh_within(b, p, nextafter(want, -INFINITY)) || want == 0);
}

/* Points at, and a little off, every vertex and edge midpoint of m (offsets from 1e-9 to 1e-2 of
 * the model's size, along random directions), and random points in and far outside its box. */
static void check_mesh(const lm_mesh *m, uint32_t stride)
{
    lm_bvh *b = NULL;
    assert_int_equal(lm_bvh_create(m, &b), LM_OK);
    uint64_t rng = 7;
    for (uint32_t t = 0; t < m->n_tris; t += stride) {
        if (!m->tri_alive[t])
            continue;
        double v[3][3];
        corners(m, t, v);
        for (int e = 0; e < 6; e++) {
            double base[3], p[3];
            for (int k = 0; k < 3; k++)
                base[k] = e < 3 ? v[e][k] : 0.5 * (v[e - 3][k] + v[(e - 2) % 3][k]);
            check_point(m, b, base);
            for (int s = 0; s < 4; s++) {
                double off = pow(10.0, -9 + 2.3 * s);
                for (int k = 0; k < 3; k++)
                    p[k] = base[k] + off * (lmt_urand(&rng) - 0.5);
                check_point(m, b, p);
            }
        }
    }
    for (int i = 0; i < 300; i++) {
        double p[3];
        for (int k = 0; k < 3; k++)
            p[k] = (lmt_urand(&rng) - 0.5) * (i < 200 ? 3.0 : 300.0);
        check_point(m, b, p);
    }
    lm_bvh_destroy(b);
}

static void test_frog(void **state)
{
    (void)state;
    lm_mesh *m = NULL;
    assert_int_equal(co_frog_generate(3000, 5, &m), LM_OK);
    check_mesh(m, 7);
    lm_mesh_destroy(m);
}

/* A flat grid: a point above a vertex is equally far from every triangle around it. */
static void test_grid_ties(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_grid(12);
    check_mesh(m, 1);
    lm_bvh *b = NULL;
    assert_int_equal(lm_bvh_create(m, &b), LM_OK);
    for (uint32_t v = 0; v < m->n_verts; v++) {
        double p[3] = {m->pos[v][0], m->pos[v][1], 0.25};
        check_point(m, b, p);
        p[2] = 0;
        check_point(m, b, p);
    }
    lm_bvh_destroy(b);
    lm_mesh_destroy(m);
}

/* One live triangle: the root is a leaf. */
static void test_one_triangle(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_grid(2);
    for (uint32_t t = 1; t < m->n_tris; t++)
        m->tri_alive[t] = 0;
    m->live_tris = 1;
    check_mesh(m, 1);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frog),
        cmocka_unit_test(test_grid_ties),
        cmocka_unit_test(test_one_triangle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
