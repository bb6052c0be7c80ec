/* tests/unit/test_geometric.c — Hoppe et al. 1993 mesh optimization (coordinator/geometric/): each
 * energy term on a known configuration (E_dist, E_spring, E_rep), the least-squares step (exact on
 * a tiny case, never raising E_dist + E_spring for fixed projections), the legality of every move
 * kept (manifold, Euler characteristic, no face turned over), E never rising on an accepted move
 * over the outer loops, the sample's determinism and the improvements' list. */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh_topology.h"
#include "coordinator/geometric/geo_internal.h"

/* The unit square in z = 0 as two triangles (0,1,2), (0,2,3). */
static lm_mesh *square(void)
{
    static const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    static const uint32_t t[2][3] = {{0, 1, 2}, {0, 2, 3}};
    lm_mesh *m;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "m", NULL, NULL, NULL, NULL), LM_OK);
    for (uint32_t i = 0; i < 4; i++) {
        uint32_t v, w;
        assert_int_equal(lm_mesh_add_vertex(m, p[i], &v), LM_OK);
        lm_wedge x = {.vertex = v, .normal = {0, 0, 1}, .color = {1, 1, 1, 1}};
        assert_int_equal(lm_mesh_add_wedge(m, &x, &w), LM_OK);
    }
    for (uint32_t i = 0; i < 2; i++)
        assert_int_equal(lm_mesh_add_tri(m, t[i], 0, NULL), LM_OK);
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    return m;
}

/* A state over m with the given points (weights 1: E_dist = Σ d², E_spring = κ Σ |e|²). */
static co_geo_state *state(lm_mesh *m, const double (*x)[3], uint32_t n, double kappa)
{
    co_geo_state *g = calloc(1, sizeof *g);
    g->m = m;
    g->n_pts = n;
    g->pt = calloc(n, sizeof *g->pt);
    for (uint32_t i = 0; i < n; i++)
        memcpy(g->pt[i].x, x[i], sizeof x[i]);
    g->w_dist = g->w_len = 1;
    g->kappa = kappa;
    assert_int_equal(lm_journal_create(&g->j), LM_OK);
    return g;
}

static void state_free(co_geo_state *g)
{
    lm_journal_destroy(g->j);
    free(g->pt);
    free(g->head);
    free(g->pidx);
    free(g->ptmp);
    lm_mesh_destroy(g->m);
    free(g);
}

static void test_e_dist_known(void **st)
{
    (void)st;
    /* heights 0.5 and -0.25 above the square, one point 2 to its right (closest: edge x = 1) */
    static const double x[3][3] = {{0.25, 0.5, 0.5}, {0.7, 0.2, -0.25}, {3, 0.5, 0}};
    co_geo_state *g = state(square(), x, 3, 0);
    assert_int_equal(co_geo_project_all(g), LM_OK);
    co_geo_retotal(g);
    assert_true(fabs(g->e_dist - (0.25 + 0.0625 + 4)) < 1e-12);
    /* the projection's barycentrics give back the closest point */
    const co_geo_point *p = &g->pt[1];
    double q[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++)
            q[c] += p->bary[k] * g->m->pos[lm_tri_vertex(g->m, p->tri, k)][c];
    assert_true(fabs(q[0] - 0.7) < 1e-12 && fabs(q[1] - 0.2) < 1e-12 && fabs(q[2]) < 1e-12);
    state_free(g);
}

static void test_e_spring_and_rep(void **st)
{
    (void)st;
    static const double x[1][3] = {{0.5, 0.5, 0}};
    co_geo_state *g = state(square(), x, 1, 0.5);
    assert_int_equal(co_geo_project_all(g), LM_OK);
    co_geo_retotal(g);
    /* four sides of length 1 and the diagonal of length √2: Σ |e|² = 6 */
    assert_true(fabs(co_geo_spring_sum(g->m) - 6) < 1e-12);
    assert_true(fabs(g->e_spring - 3) < 1e-12);
    assert_true(fabs(g->e_dist) < 1e-15);
    g->c_rep = 0.125;
    assert_true(fabs(co_geo_total(g) - (3 + 0.125 * 4)) < 1e-12);
    assert_true(fabs(co_geo_energy_now(g) - co_geo_total(g)) < 1e-12);
    state_free(g);
}

/* With κ = 0 and points at fixed barycentrics of a target square, one step lands on it. */
static void test_least_squares_exact(void **st)
{
    (void)st;
    static const double target[4][3] = {{0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}};
    static const uint32_t tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
    static const double bary[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.2, 0.3, 0.5}};
    double x[8][3];
    co_geo_state *g = state(square(), x, 8, 0);
    for (uint32_t i = 0; i < 8; i++) {
        co_geo_point *p = &g->pt[i];
        p->tri = i / 4;
        memcpy(p->bary, bary[i % 4], sizeof p->bary);
        for (int c = 0; c < 3; c++) {
            p->x[c] = 0;
            for (int k = 0; k < 3; k++)
                p->x[c] += p->bary[k] * target[tri[p->tri][k]][c];
        }
    }
    assert_int_equal(co_geo_solve_positions(g), LM_OK);
    for (uint32_t v = 0; v < 4; v++)
        for (int c = 0; c < 3; c++)
            assert_true(fabs(g->m->pos[v][c] - target[v][c]) < 1e-5);
    state_free(g);
}

/* E_dist + E_spring for the recorded projections (barycentrics fixed), as the solve sees it. */
static double fixed_energy(const co_geo_state *g)
{
    double e = 0;
    for (uint32_t i = 0; i < g->n_pts; i++) {
        const co_geo_point *p = &g->pt[i];
        double q[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++)
                q[c] += p->bary[k] * g->m->pos[lm_tri_vertex(g->m, p->tri, k)][c];
        for (int c = 0; c < 3; c++)
            e += (q[c] - p->x[c]) * (q[c] - p->x[c]);
    }
    return g->w_dist * e + g->kappa * g->w_len * co_geo_spring_sum(g->m);
}

static void test_least_squares_lowers(void **st)
{
    (void)st;
    lm_mesh *sphere = lmt_make_sphere(2);
    uint64_t r = 7;
    double x[400][3];
    for (int i = 0; i < 400; i++) { /* a bumpy sphere of radius about 1.2 */
        double z = 2 * lmt_urand(&r) - 1, a = 6.283185307 * lmt_urand(&r), s = sqrt(1 - z * z),
               rad = 1.2 + 0.1 * lmt_urand(&r);
        x[i][0] = rad * s * cos(a), x[i][1] = rad * s * sin(a), x[i][2] = rad * z;
    }
    for (int round = 0; round < 3; round++) {
        lm_mesh *m;
        assert_int_equal(lm_mesh_clone(sphere, &m), LM_OK);
        assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
        co_geo_state *g = state(m, x, 400, round == 0 ? 1e-3 : round == 1 ? 1e-1 : 0);
        assert_int_equal(co_geo_project_all(g), LM_OK);
        double before = fixed_energy(g);
        assert_int_equal(co_geo_solve_positions(g), LM_OK);
        double after = fixed_energy(g);
        assert_true(after <= before + 1e-9 * before);
        assert_true(after < before);
        state_free(g);
    }
    lm_mesh_destroy(sphere);
}

typedef struct watch {
    double kappa, c_rep, last;
    long euler;
    uint32_t comps, accepted;
    int rose, illegal;
} watch;

/* After every accepted move: a manifold mesh of the same topological type, and E (from scratch,
 * the recorded projections) not above its value after the previous move at the same κ, c_rep. */
static void on_accept(void *ctx, const co_geo_state *g)
{
    watch *w = ctx;
    double e = co_geo_energy_now(g);
    if (g->kappa == w->kappa && g->c_rep == w->c_rep && e > w->last + 1e-9 * fabs(w->last))
        w->rose++;
    if (fabs(e - co_geo_energy_tracked(g)) > 1e-6 * fabs(e) + 1e-12)
        w->rose++;
    w->kappa = g->kappa, w->c_rep = g->c_rep, w->last = e;
    w->accepted++;
    const lm_mesh *m = g->m;
    if (lm_mesh_euler_characteristic(m) != w->euler || lm_mesh_count_components(m) != w->comps)
        w->illegal++;
    uint32_t(*edges)[2];
    size_t n;
    assert_int_equal(lm_mesh_list_edges(m, &edges, &n), LM_OK);
    for (size_t i = 0; i < n; i++) {
        uint32_t t[4];
        if (lm_mesh_edge_tris(m, edges[i][0], edges[i][1], t, 4) != 2) /* closed: two each */
            w->illegal++;
    }
    free(edges);
    for (uint32_t t = 0; t < m->n_tris; t++) { /* the sphere's faces all face outwards */
        if (!m->tri_alive[t])
            continue;
        double nrm[3], c[3] = {0, 0, 0};
        lm_mesh_face_normal(m, t, nrm);
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++)
                c[a] += m->pos[lm_tri_vertex(m, t, k)][a];
        if (nrm[0] * c[0] + nrm[1] * c[1] + nrm[2] * c[2] <= 0)
            w->illegal++;
    }
}

static void run_outer(uint32_t improvements, uint32_t target)
{
    lm_mesh *orig = lmt_make_sphere(4), *start = lmt_make_sphere(3);
    assert_int_equal(lm_mesh_build_adjacency(start), LM_OK);
    watch w = {.kappa = -1,
               .euler = lm_mesh_euler_characteristic(start),
               .comps = lm_mesh_count_components(start)};
    co_geo_options o = {.target_verts = target,
                        .c_rep = 1e-5,
                        .improvements = improvements,
                        .seed = 3,
                        .points = 4000,
                        .on_accept = on_accept,
                        .ctx = &w};
    co_geo_summary s;
    assert_int_equal(co_geo_optimize(orig, start, &o, &s), LM_OK);
    assert_true(w.accepted > 10);
    assert_int_equal(w.rose, 0);
    assert_int_equal(w.illegal, 0);
    assert_int_equal(start->live_verts, target);
    assert_int_equal(s.verts, target);
    if (improvements & CO_GEO_COLLAPSE_ONLY)
        assert_true(s.swaps == 0 && s.splits == 0);
    lm_mesh_destroy(orig);
    lm_mesh_destroy(start);
}

static void test_outer_all_moves(void **st)
{
    (void)st;
    run_outer(0, 60);
}

static void test_outer_improved(void **st)
{
    (void)st;
    run_outer(CO_GEO_ALL, 40);
}

/* The same seed gives the same mesh; another seed another one. */
static void test_deterministic(void **st)
{
    (void)st;
    uint64_t h[3];
    for (int i = 0; i < 3; i++) {
        lm_mesh *orig = lmt_make_sphere(3), *start = lmt_make_sphere(3);
        assert_int_equal(lm_mesh_build_adjacency(start), LM_OK);
        co_geo_options o = {.target_verts = 50,
                            .c_rep = 1e-5,
                            .seed = i == 2 ? 9 : 4,
                            .improvements = CO_GEO_ALL,
                            .points = 3000};
        co_geo_summary s;
        assert_int_equal(co_geo_optimize(orig, start, &o, &s), LM_OK);
        h[i] = lm_mesh_hash(start);
        lm_mesh_destroy(orig);
        lm_mesh_destroy(start);
    }
    assert_true(h[0] == h[1]);
    assert_true(h[0] != h[2]);
}

static void test_improvements_list(void **st)
{
    (void)st;
    uint32_t b;
    assert_int_equal(co_geo_parse_improvements("all", &b), LM_OK);
    assert_int_equal(b, CO_GEO_ALL);
    assert_int_equal(co_geo_parse_improvements("none", &b), LM_OK);
    assert_int_equal(b, 0);
    assert_int_equal(co_geo_parse_improvements("stored,collapse-only", &b), LM_OK);
    assert_int_equal(b, CO_GEO_STORED | CO_GEO_COLLAPSE_ONLY);
    assert_int_not_equal(co_geo_parse_improvements("stored,fast", &b), LM_OK);
    lm_clear_error();
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_e_dist_known),        cmocka_unit_test(test_e_spring_and_rep),
        cmocka_unit_test(test_least_squares_exact), cmocka_unit_test(test_least_squares_lowers),
        cmocka_unit_test(test_outer_all_moves),     cmocka_unit_test(test_outer_improved),
        cmocka_unit_test(test_deterministic),       cmocka_unit_test(test_improvements_list),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
