/* tests/unit/test_adaptive.c — the shape-adaptive simplifier (Park, Lee & Lee 2003;
 * coordinator/simplify/adapt_*.c, simplify_adaptive.c): directional curvature on a sphere and a
 * cylinder of known radius, the optimal edge length formula, feature edges and vertex classes on
 * a cube, and the collapses' legality (a valid closed manifold, corners kept, vertices on the
 * original, the tolerance met at the original's vertices), exact targets, determinism, bad input.
 */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "common/mesh_topology.h"
#include "coordinator/simplify/adapt_curvature.h"
#include "coordinator/simplify/adapt_edge_length.h"
#include "coordinator/simplify/adapt_features.h"
#include "coordinator/simplify/adaptive.h"
#include "coordinator/simplify/simplify.h"

/* ---- mesh builders ----------------------------------------------------------------------------
 */

static lm_mesh *new_mesh(void)
{
    lm_mesh *m = NULL;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "default", NULL, NULL, NULL, NULL), LM_OK);
    return m;
}

/* The vertex at p (one wedge a vertex), found by position or added. */
static uint32_t vertex_at(lm_mesh *m, double x, double y, double z)
{
    float p[3] = {(float)x, (float)y, (float)z};
    for (uint32_t v = 0; v < m->n_verts; v++)
        if (fabsf(m->pos[v][0] - p[0]) < 1e-5f && fabsf(m->pos[v][1] - p[1]) < 1e-5f &&
            fabsf(m->pos[v][2] - p[2]) < 1e-5f)
            return v;
    uint32_t id = 0;
    assert_int_equal(lm_mesh_add_vertex(m, p, &id), LM_OK);
    lm_wedge w = {.vertex = id, .color = {1, 1, 1, 1}};
    uint32_t wid = 0;
    assert_int_equal(lm_mesh_add_wedge(m, &w, &wid), LM_OK);
    assert_int_equal(wid, id);
    return id;
}

static void tri(lm_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    uint32_t w[3] = {a, b, c};
    assert_int_equal(lm_mesh_add_tri(m, w, 0, NULL), LM_OK);
}

/* A cube [-1,1]^3, each face an n x n grid of quads (two triangles each), outward. */
static lm_mesh *make_cube(int n)
{
    lm_mesh *m = new_mesh();
    for (int axis = 0; axis < 3; axis++)
        for (int side = -1; side <= 1; side += 2)
            for (int i = 0; i < n; i++)
                for (int j = 0; j < n; j++) {
                    uint32_t q[4];
                    for (int k = 0; k < 4; k++) {
                        double u = -1 + 2.0 * (i + (k == 1 || k == 2)) / n;
                        double v = -1 + 2.0 * (j + (k >= 2)) / n;
                        double p[3];
                        p[axis] = side;
                        p[(axis + 1) % 3] = u;
                        p[(axis + 2) % 3] = v;
                        q[k] = vertex_at(m, p[0], p[1], p[2]);
                    }
                    if (side > 0) {
                        tri(m, q[0], q[1], q[2]);
                        tri(m, q[0], q[2], q[3]);
                    } else {
                        tri(m, q[0], q[2], q[1]);
                        tri(m, q[0], q[3], q[2]);
                    }
                }
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    return m;
}

/* An open tube of radius r along z (around x 0..h): `around` segments, `along` rings - 1. */
static lm_mesh *make_cylinder(double r, double h, int around, int along)
{
    lm_mesh *m = new_mesh();
    for (int j = 0; j < along; j++)
        for (int i = 0; i < around; i++) {
            double a0 = 2 * 3.14159265358979323846 * i / around,
                   a1 = 2 * 3.14159265358979323846 * (i + 1) / around;
            double z0 = h * j / along, z1 = h * (j + 1) / along;
            uint32_t p = vertex_at(m, r * cos(a0), r * sin(a0), z0);
            uint32_t q = vertex_at(m, r * cos(a1), r * sin(a1), z0);
            uint32_t s = vertex_at(m, r * cos(a1), r * sin(a1), z1);
            uint32_t t = vertex_at(m, r * cos(a0), r * sin(a0), z1);
            tri(m, p, q, s);
            tri(m, p, s, t);
        }
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    return m;
}

static void posd(const lm_mesh *m, uint32_t v, double p[3])
{
    for (int k = 0; k < 3; k++)
        p[k] = m->pos[v][k];
}

/* ---- curvature ---------------------------------------------------------------------------------
 */

static void test_curvature_exact_on_a_circle(void **state)
{
    (void)state;
    const double r = 2.5;
    for (int i = 1; i < 8; i++) {
        double t = 0.1 * i, a[3] = {r, 0, 0}, b[3] = {r * cos(t), r * sin(t), 0};
        double na[3] = {1, 0, 0}, nb[3] = {cos(t), sin(t), 0};
        assert_true(fabs(co_adapt_edge_curvature(a, na, b, nb) - 1 / r) < 1e-12);
    }
    double a[3] = {0, 0, 0}, n[3] = {0, 0, 1};
    assert_true(co_adapt_edge_curvature(a, n, a, n) == 0);
}

static void test_curvature_on_a_sphere(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(4); /* unit sphere */
    double(*nrm)[3] = malloc(m->n_verts * sizeof *nrm);
    co_adapt_vertex_normals(m, nrm);
    uint32_t(*e)[2] = NULL;
    size_t ne = 0;
    assert_int_equal(lm_mesh_list_edges(m, &e, &ne), LM_OK);
    double worst = 0, sum = 0;
    for (size_t i = 0; i < ne; i++) {
        double a[3], b[3];
        posd(m, e[i][0], a);
        posd(m, e[i][1], b);
        double k = co_adapt_edge_curvature(a, nrm[e[i][0]], b, nrm[e[i][1]]);
        worst = fmax(worst, fabs(k - 1.0));
        sum += fabs(k - 1.0);
    }
    /* the mesh's normals are estimates (area-weighted): near the octahedron's six valence-4
     * vertices they lean off the radius, elsewhere they are close to it */
    print_message("sphere r=1: |kappa - 1| over %zu edges: mean %.4f, worst %.4f\n", ne,
                  sum / (double)ne, worst);
    assert_true(sum / (double)ne < 0.08);
    assert_true(worst < 0.35);
    free(e);
    free(nrm);
    lm_mesh_destroy(m);
}

static void test_curvature_on_a_cylinder(void **state)
{
    (void)state;
    const double r = 3;
    lm_mesh *m = make_cylinder(r, 6, 48, 12);
    double(*nrm)[3] = malloc(m->n_verts * sizeof *nrm);
    co_adapt_vertex_normals(m, nrm);
    uint32_t(*e)[2] = NULL;
    size_t ne = 0;
    assert_int_equal(lm_mesh_list_edges(m, &e, &ne), LM_OK);
    int along = 0, around = 0;
    for (size_t i = 0; i < ne; i++) {
        double a[3], b[3];
        posd(m, e[i][0], a);
        posd(m, e[i][1], b);
        double k = co_adapt_edge_curvature(a, nrm[e[i][0]], b, nrm[e[i][1]]);
        if (fabs(a[2] - b[2]) < 1e-6) { /* around the axis: 1 / r */
            assert_true(fabs(k - 1 / r) < 0.01 / r);
            around++;
        } else if (fabs(a[0] - b[0]) < 1e-6 && fabs(a[1] - b[1]) < 1e-6) { /* a ruling: 0 */
            assert_true(k < 1e-6);
            along++;
        }
    }
    assert_true(along > 0 && around > 0);
    free(e);
    free(nrm);
    lm_mesh_destroy(m);
}

/* ---- optimal edge length -----------------------------------------------------------------------
 */

static void test_optimal_length(void **state)
{
    (void)state;
    const double r = 1.0, e = 0.01;
    double l = co_adapt_optimal_length(1 / r, e, 100);
    assert_true(fabs(l - 2 * sqrt(2 * e * r - e * e)) < 1e-15);
    /* the chord of that length leaves an arc whose farthest point is exactly e away */
    double sagitta = r - sqrt(r * r - l * l / 4);
    assert_true(fabs(sagitta - e) < 1e-12);
    assert_true(co_adapt_optimal_length(0, e, 7.5) == 7.5);    /* flat: the cap */
    assert_true(co_adapt_optimal_length(1e-9, e, 7.5) == 7.5); /* almost flat: capped */
    assert_true(fabs(co_adapt_optimal_length(1 / (0.1 * e), e, 100) - 2 * e) < 1e-15); /* r < e */
    assert_true(co_adapt_optimal_length(2, e, 100) < co_adapt_optimal_length(1, e, 100));
    assert_true(co_adapt_optimal_length(1, 2 * e, 100) > co_adapt_optimal_length(1, e, 100));
    assert_true(fabs(co_adapt_optimality(0.1, 1, e, 100) - (0.1 - l)) < 1e-15);
}

/* ---- features ----------------------------------------------------------------------------------
 */

static void test_cube_features(void **state)
{
    (void)state;
    lm_mesh *m = make_cube(2); /* 26 vertices: 8 corners, 12 edge midpoints, 6 face centres */
    assert_int_equal(m->live_verts, 26);
    double cos30 = cos(CO_ADAPT_FEATURE_DEG * 3.14159265358979323846 / 180);
    uint32_t(*e)[2] = NULL;
    size_t ne = 0, feat = 0;
    assert_int_equal(lm_mesh_list_edges(m, &e, &ne), LM_OK);
    for (size_t i = 0; i < ne; i++) {
        double a[3], b[3];
        posd(m, e[i][0], a);
        posd(m, e[i][1], b);
        /* on a cube edge: both ends have two coordinates at +-1 in common */
        int shared = 0;
        for (int k = 0; k < 3; k++)
            shared += fabs(a[k]) == 1 && a[k] == b[k];
        int f = co_adapt_is_feature_edge(m, e[i][0], e[i][1], cos30);
        assert_int_equal(f, shared == 2);
        feat += (size_t)f;
    }
    assert_int_equal(feat, 24); /* 12 cube edges, two segments each */
    uint8_t *cls = malloc(m->n_verts);
    assert_int_equal(co_adapt_vertex_classes(m, cos30, cls), LM_OK);
    int count[3] = {0, 0, 0};
    for (uint32_t v = 0; v < m->n_verts; v++) {
        double p[3];
        posd(m, v, p);
        int on = (fabs(p[0]) == 1) + (fabs(p[1]) == 1) + (fabs(p[2]) == 1);
        assert_int_equal(cls[v], on == 3   ? CO_ADAPT_CORNER
                                 : on == 2 ? CO_ADAPT_LINE
                                           : CO_ADAPT_SMOOTH);
        count[cls[v]]++;
    }
    assert_int_equal(count[CO_ADAPT_CORNER], 8);
    assert_int_equal(count[CO_ADAPT_LINE], 12);
    assert_int_equal(count[CO_ADAPT_SMOOTH], 6);
    free(cls);
    free(e);
    lm_mesh_destroy(m);
}

/* ---- the simplifier ----------------------------------------------------------------------------
 */

static double diag_of(const lm_mesh *m)
{
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
    for (uint32_t v = 0; v < m->n_verts; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->pos[v][k]);
            hi[k] = fmax(hi[k], m->pos[v][k]);
        }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/* Every vertex of out is a vertex of in; every vertex of in within tol of out's surface. */
static void check_on_original(const lm_mesh *in, const lm_mesh *out, double tol)
{
    for (uint32_t v = 0; v < out->n_verts; v++) {
        int found = 0;
        for (uint32_t u = 0; u < in->n_verts && !found; u++)
            found = !memcmp(in->pos[u], out->pos[v], sizeof in->pos[u]);
        assert_true(found);
    }
    lm_bvh *b = NULL;
    assert_int_equal(lm_bvh_create(out, &b), LM_OK);
    for (uint32_t v = 0; v < in->n_verts; v++) {
        double p[3];
        posd(in, v, p);
        assert_true(sqrt(lm_bvh_closest_sq(b, p)) <= tol);
    }
    lm_bvh_destroy(b);
}

static void check_closed_manifold(const lm_mesh *m)
{
    assert_int_equal(lm_mesh_validate(m), LM_OK);
    assert_int_equal(lm_mesh_euler_characteristic(m), 2);
    uint32_t(*e)[2] = NULL;
    size_t ne = 0;
    assert_int_equal(lm_mesh_list_edges(m, &e, &ne), LM_OK);
    for (size_t i = 0; i < ne; i++) {
        uint32_t t[3];
        assert_int_equal(lm_mesh_edge_tris(m, e[i][0], e[i][1], t, 3), 2);
    }
    free(e);
}

static void test_cube_keeps_its_corners_and_faces(void **state)
{
    (void)state;
    lm_mesh *m = make_cube(6), *out = NULL;
    co_adapt_stats st;
    assert_int_equal(co_simplify_adaptive(m, 0.001, 0, &st, &out), LM_OK);
    print_message("cube 6x6: %u -> %u vertices, %u collapses, %u refused\n", m->live_verts,
                  out->live_verts, st.collapses, st.refused);
    check_closed_manifold(out);
    check_on_original(m, out, 1e-6); /* flat faces: nothing moves off them */
    assert_true(out->live_verts < m->live_verts / 4);
    int corners = 0;
    for (uint32_t v = 0; v < out->n_verts; v++)
        corners +=
            fabsf(out->pos[v][0]) == 1 && fabsf(out->pos[v][1]) == 1 && fabsf(out->pos[v][2]) == 1;
    assert_int_equal(corners, 8);
    lm_mesh_destroy(out);
    lm_mesh_destroy(m);
}

static void test_sphere_tolerance_and_determinism(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(4), *a = NULL, *b = NULL;
    double tol = 0.01;
    assert_int_equal(co_simplify_adaptive(m, tol, 0, NULL, &a), LM_OK);
    assert_int_equal(co_simplify_adaptive(m, tol, 0, NULL, &b), LM_OK);
    print_message("sphere: %u -> %u vertices at tolerance %.3g\n", m->live_verts, a->live_verts,
                  tol);
    check_closed_manifold(a);
    check_on_original(m, a, tol * diag_of(m));
    assert_true(a->live_verts < m->live_verts / 3);
    assert_int_equal(a->n_verts, b->n_verts);
    assert_int_equal(a->n_tris, b->n_tris);
    assert_memory_equal(a->pos, b->pos, a->n_verts * sizeof *a->pos);
    assert_memory_equal(a->tris, b->tris, a->n_tris * sizeof *a->tris);
    /* a tighter tolerance keeps more */
    lm_mesh *c = NULL;
    assert_int_equal(co_simplify_adaptive(m, tol / 4, 0, NULL, &c), LM_OK);
    assert_true(c->live_verts > a->live_verts);
    lm_mesh_destroy(a);
    lm_mesh_destroy(b);
    lm_mesh_destroy(c);
    lm_mesh_destroy(m);
}

static void test_exact_target(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(4), *out = NULL;
    co_adapt_stats st;
    assert_int_equal(co_simplify_adaptive(m, 0, 300, &st, &out), LM_OK);
    assert_int_equal(out->live_verts, 300);
    assert_true(st.runs > 1 && st.tolerance > 0);
    check_closed_manifold(out);
    lm_mesh_destroy(out);
    assert_int_equal(co_simplify(m, CO_SIMPLIFY_ADAPTIVE, 120, &out), LM_OK);
    assert_int_equal(out->live_verts, 120);
    lm_mesh_destroy(out);
    lm_mesh_destroy(m);
}

static void test_bad_input(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2), *out = (lm_mesh *)1;
    assert_int_equal(co_simplify_adaptive(m, -0.1, 0, NULL, &out), LM_E_INVALID);
    assert_null(out);
    assert_int_equal(co_simplify_adaptive(m, NAN, 0, NULL, &out), LM_E_INVALID);
    assert_int_equal(co_simplify_adaptive(m, 0, 0, NULL, &out), LM_E_INVALID);
    assert_int_equal(co_simplify_adaptive(m, 0, 3, NULL, &out), LM_E_INVALID);
    assert_null(out);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_curvature_exact_on_a_circle),
        cmocka_unit_test(test_curvature_on_a_sphere),
        cmocka_unit_test(test_curvature_on_a_cylinder),
        cmocka_unit_test(test_optimal_length),
        cmocka_unit_test(test_cube_features),
        cmocka_unit_test(test_cube_keeps_its_corners_and_faces),
        cmocka_unit_test(test_sphere_tolerance_and_determinism),
        cmocka_unit_test(test_exact_target),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
