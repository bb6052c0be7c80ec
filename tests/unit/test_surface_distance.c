/* tests/unit/test_surface_distance.c — the report's geometric error: point-to-triangle distances
 * in each Voronoi region, the hierarchy's closest point equal to a scan of every triangle, exact
 * answers where they are known (a sheet and its copy moved along its normal; a mesh against
 * itself), samples that follow area, and the same numbers on every run. */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "common/mesh_topology.h"
#include "coordinator/frog/frog.h"
#include "coordinator/quality/surface_distance.h"
#include "coordinator/simplify/simplify.h"

static void test_point_triangle(void **state)
{
    (void)state;
    const double a[3] = {0, 0, 0}, b[3] = {2, 0, 0}, c[3] = {0, 2, 0};
    const struct {
        double p[3], want;
    } cases[] = {
        {{0.5, 0.5, 3}, 9},        /* above the face */
        {{-1, -1, 0}, 2},          /* corner a */
        {{3, -1, 0}, 2},           /* corner b */
        {{-1, 4, 0}, 1 + 4},       /* corner c */
        {{1, -2, 0}, 4},           /* edge ab */
        {{-3, 1, 0}, 9},           /* edge ac */
        {{2, 2, 0}, 2},            /* edge bc: (1, 1) is the closest point */
        {{0.25, 0.25, -0.5}, 0.25} /* below the face */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        assert_float_equal(lm_point_triangle_sq(cases[i].p, a, b, c), cases[i].want, 1e-12);
    const double d[3] = {1, 1, 1}; /* a degenerate triangle (all corners at d) */
    const double p[3] = {1, 1, 3};
    assert_float_equal(lm_point_triangle_sq(p, d, d, d), 4, 1e-12);
}

static double brute_sq(const lm_mesh *m, const double p[3])
{
    double best = INFINITY;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        double v[3][3];
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                v[k][j] = m->pos[lm_tri_vertex(m, t, k)][j];
        double d = lm_point_triangle_sq(p, v[0], v[1], v[2]);
        best = d < best ? d : best;
    }
    return best;
}

/* The hierarchy prunes only what cannot be closer: the same minimum as a scan of every
 * triangle, for points inside, near and far from the frog. */
static void test_bvh_equals_scan(void **state)
{
    (void)state;
    lm_mesh *m = NULL;
    assert_int_equal(co_frog_generate(4000, 5, &m), LM_OK);
    lm_bvh *b = NULL;
    assert_int_equal(lm_bvh_create(m, &b), LM_OK);
    uint64_t rng = 42;
    for (int i = 0; i < 1500; i++) {
        double p[3];
        for (int k = 0; k < 3; k++)
            p[k] = (lmt_urand(&rng) - 0.5) * (i < 1000 ? 3.0 : 30.0);
        assert_true(lm_bvh_closest_sq(b, p) == brute_sq(m, p));
    }
    lm_bvh_destroy(b);
    lm_mesh_destroy(m);
}

/* A flat sheet and its copy 0.05 above it: every sample is exactly 0.05 from the other sheet. */
static void test_moved_sheet(void **state)
{
    (void)state;
    lm_mesh *a = lmt_make_grid(9), *b = NULL;
    assert_int_equal(lm_mesh_clone(a, &b), LM_OK);
    for (uint32_t v = 0; v < b->n_verts; v++)
        b->pos[v][2] += 0.05f;
    co_surface_distance d;
    assert_int_equal(co_surface_distance_measure(a, b, 4000, &d), LM_OK);
    assert_float_equal(d.mean, 0.05, 1e-6);
    assert_float_equal(d.rms, 0.05, 1e-6);
    assert_float_equal(d.max, 0.05, 1e-6);
    assert_int_equal(d.samples, 4000);
    /* against itself: zero */
    assert_int_equal(co_surface_distance_measure(a, a, 4000, &d), LM_OK);
    assert_true(d.max < 1e-6);
    lm_mesh_destroy(a);
    lm_mesh_destroy(b);
}

/* The two sides apart: a sheet half the size of the original, lying on it, has its own points on
 * the original (0 to it) while most of the original's points are off it; their mean is the mean. */
static void test_sides(void **state)
{
    (void)state;
    lm_mesh *a = lmt_make_grid(9), *b = NULL;
    assert_int_equal(lm_mesh_clone(a, &b), LM_OK);
    for (uint32_t v = 0; v < b->n_verts; v++)
        for (int k = 0; k < 2; k++)
            b->pos[v][k] *= 0.5f;
    co_surface_distance d;
    assert_int_equal(co_surface_distance_measure(a, b, 4000, &d), LM_OK);
    assert_true(d.mean_to_original < 1e-6);
    assert_true(d.mean_from_original > 0.01);
    assert_float_equal(d.mean, 0.5 * (d.mean_to_original + d.mean_from_original), 1e-12);
    lm_mesh_destroy(a);
    lm_mesh_destroy(b);
}

/* Samples follow area: on two triangles of areas 1 and 3, a quarter of the points lie on the
 * small one (stratified, so within a point or two). */
static void test_samples_follow_area(void **state)
{
    (void)state;
    lm_mesh *m = NULL;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    static const float p[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {5, 0, 0}, {8, 0, 0}, {5, 2, 0}};
    for (int i = 0; i < 6; i++) {
        lm_wedge w = {.vertex = (uint32_t)i, .color = {1, 1, 1, 1}};
        assert_int_equal(lm_mesh_add_vertex(m, p[i], NULL), LM_OK);
        assert_int_equal(lm_mesh_add_wedge(m, &w, NULL), LM_OK);
    }
    assert_int_equal(lm_mesh_add_tri(m, (uint32_t[3]){0, 1, 2}, 0, NULL), LM_OK);
    assert_int_equal(lm_mesh_add_tri(m, (uint32_t[3]){3, 4, 5}, 0, NULL), LM_OK);
    double *pts = NULL;
    assert_int_equal(co_surface_sample(m, 1000, 7, &pts), LM_OK);
    int small = 0;
    for (int i = 0; i < 1000; i++) {
        small += pts[3 * i] < 2;
        assert_float_equal(pts[3 * i + 2], 0, 0);
    }
    assert_in_range(small, 249, 251);
    free(pts);
    lm_mesh_destroy(m);
}

/* A coarse frog against the frog: a positive error, ordered mean <= rms <= max, and the very
 * same numbers on a second run. */
static void test_deterministic(void **state)
{
    (void)state;
    lm_mesh *frog = NULL, *coarse = NULL;
    assert_int_equal(co_frog_generate(6000, 1, &frog), LM_OK);
    assert_int_equal(co_simplify(frog, CO_SIMPLIFY_QEM, 300, &coarse), LM_OK);
    co_surface_distance d1, d2;
    assert_int_equal(co_surface_distance_measure(frog, coarse, 0, &d1), LM_OK);
    assert_int_equal(co_surface_distance_measure(frog, coarse, 0, &d2), LM_OK);
    assert_memory_equal(&d1, &d2, sizeof d1);
    assert_true(d1.mean > 0 && d1.mean <= d1.rms && d1.rms <= d1.max);
    assert_true(d1.max < 0.1 * d1.diagonal);
    assert_int_equal(d1.samples, CO_DISTANCE_SAMPLES);
    print_message("frog vs QEM 300: mean %.5f rms %.5f max %.5f of diagonal %.3f\n", d1.mean,
                  d1.rms, d1.max, d1.diagonal);
    lm_mesh_destroy(frog);
    lm_mesh_destroy(coarse);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_point_triangle), cmocka_unit_test(test_bvh_equals_scan),
        cmocka_unit_test(test_moved_sheet),    cmocka_unit_test(test_samples_follow_area),
        cmocka_unit_test(test_deterministic),  cmocka_unit_test(test_sides),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
