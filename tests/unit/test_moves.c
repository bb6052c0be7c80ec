/* tests/unit/test_moves.c — one operation at a time against the real in-process views (Mesa's
 * software device, 12 views of 64x64): the vertex sets of Table 1; for no-op, swap, split and
 * collapse an accept path (ΔE < 0, committed, energy falls by exactly ΔE and equals a fresh full
 * render) and a reject path (mesh and images untouched, byte for byte); illegal moves; optimised
 * colours; and the vertex teleport (vertex count unchanged) with its rejection. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh_topology.h"
#include "common/optimizer/moves.h"
#include "common/optimizer/teleport.h"
#include "common/view.h"
#include "test_support.h"
#include "worker/render/views_local.h"

#define N_VIEWS 12
#define SIZE 64

typedef struct rig {
    lm_mesh *orig, *m;
    lm_views *v;
    lm_moves *mv;
    lm_view_set *vs;
} rig;

static void derive(lm_mesh *m, uint32_t attrs)
{
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    if (!(attrs & LM_ATTR_NORMAL)) {
        lm_mesh_merge_wedges(m, LM_ATTR_UV | LM_ATTR_COLOR);
        lm_mesh_compute_normals(m);
    }
}

static void send_mesh(lm_views *v, const lm_mesh *m)
{
    lm_tri_data *t;
    size_t n;
    assert_int_equal(lm_mesh_export_tris(m, &t, &n), LM_OK);
    assert_int_equal(v->ops->set_mesh(v, t, n), LM_OK);
    free(t);
}

/* Takes both meshes. */
static void rig_init(rig *r, lm_mesh *orig, lm_mesh *coarse, uint32_t attrs)
{
    memset(r, 0, sizeof *r);
    r->orig = orig;
    r->m = coarse;
    derive(orig, 0);
    derive(coarse, attrs);
    float c[3], rad;
    lm_mesh_bounding_sphere(orig, c, &rad);
    r->vs = malloc(sizeof *r->vs);
    assert_int_equal(lm_view_set_make(r->vs, N_VIEWS, SIZE, c, rad), LM_OK);
    assert_int_equal(wk_views_local_create(orig, r->vs, 0, 0, "host", &r->v), LM_OK);
    send_mesh(r->v, coarse);
    /* a finer simplex tolerance than the optimizer's default (0.25): these tests check how far a
     * single move gets */
    lm_moves_config cfg = {.attrs = attrs, .bound_radius = 4 * rad, .size_tol = 1.0 / 16};
    memcpy(cfg.centre, c, sizeof c);
    assert_int_equal(lm_moves_create(coarse, r->v, &cfg, &r->mv), LM_OK);
}

static void rig_free(rig *r)
{
    lm_moves_destroy(r->mv);
    lm_views_destroy(r->v);
    lm_mesh_destroy(r->orig);
    lm_mesh_destroy(r->m);
    free(r->vs);
}

static int64_t energy(lm_views *v)
{
    int64_t e;
    assert_int_equal(v->ops->energy(v, &e, NULL), LM_OK);
    return e;
}

/* The views' incrementally kept energy equals a fresh full render of the mesh. */
static void check_fresh(const rig *r)
{
    lm_views *f;
    assert_int_equal(wk_views_local_create(r->orig, r->vs, 0, 0, "host", &f), LM_OK);
    send_mesh(f, r->m);
    assert_true(energy(f) == energy(r->v));
    lm_views_destroy(f);
    assert_int_equal(lm_mesh_validate(r->m), LM_OK);
}

static lm_mesh *sphere_with(int sub, uint32_t vertex, float scale)
{
    lm_mesh *m = lmt_make_sphere(sub);
    for (int k = 0; k < 3; k++)
        m->pos[vertex][k] *= scale;
    return m;
}

static double norm3(const float *p)
{
    return sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
}

static uint32_t first_neighbor(const lm_mesh *m, uint32_t v)
{
    uint32_t nb[64];
    assert_true(lm_mesh_vertex_neighbors(m, v, nb, 64) > 0);
    return nb[0];
}

static void accept_checks(rig *r, const lm_move_result *res, int64_t e0)
{
    assert_true(res->legal);
    assert_true(res->accepted);
    assert_true(res->delta < 0);
    assert_true(res->evals > 0);
    assert_true(energy(r->v) == e0 + res->delta);
    check_fresh(r);
}

static void test_noop_accept(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, lmt_make_sphere(3), sphere_with(2, 0, 0.7f), 0);
    int64_t e0 = energy(r.v);
    uint32_t b = first_neighbor(r.m, 0);
    lm_move_result res;
    assert_int_equal(lm_moves_try(r.mv, LM_MOVE_NOOP, 1, 0, b, 0, &res), LM_OK);
    accept_checks(&r, &res, e0);
    assert_int_equal(res.set_size, 2);
    assert_true(norm3(r.m->pos[0]) > 0.75); /* pushed back out towards the sphere */
    rig_free(&r);
}

static void test_color_accept(void **state)
{
    (void)state;
    lm_mesh *coarse = lmt_make_sphere(2);
    coarse->attrs |= LM_ATTR_COLOR;
    for (int k = 0; k < 3; k++)
        coarse->wedges[0].color[k] = 0.3f;
    rig r;
    rig_init(&r, lmt_make_sphere(3), coarse, LM_ATTR_COLOR);
    int64_t e0 = energy(r.v);
    lm_move_result res;
    assert_int_equal(lm_moves_try(r.mv, LM_MOVE_NOOP, 1, 0, first_neighbor(r.m, 0), 0, &res),
                     LM_OK);
    accept_checks(&r, &res, e0);
    assert_true(r.m->wedges[0].color[0] > 0.35f);
    rig_free(&r);
}

/* A ridge: four vertices, the original's diagonal on the crest, the coarse one across it. */
static lm_mesh *ridge(int crest)
{
    lm_mesh *m;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "default", NULL, NULL, NULL, NULL), LM_OK);
    const float p[4][3] = {{0, -1, 0}, {0, 1, 0}, {-1, 0, -0.6f}, {1, 0, -0.6f}};
    for (uint32_t i = 0; i < 4; i++) {
        assert_int_equal(lm_mesh_add_vertex(m, p[i], NULL), LM_OK);
        lm_wedge w = {.vertex = i, .normal = {0, 0, 1}, .color = {1, 1, 1, 1}};
        assert_int_equal(lm_mesh_add_wedge(m, &w, NULL), LM_OK);
    }
    const uint32_t a[2][3] = {{0, 3, 1}, {0, 1, 2}}, b[2][3] = {{2, 0, 3}, {2, 3, 1}};
    for (int i = 0; i < 2; i++)
        assert_int_equal(lm_mesh_add_tri(m, crest ? a[i] : b[i], 0, NULL), LM_OK);
    return m;
}

static void test_swap_accept(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, ridge(1), ridge(0), 0);
    int64_t e0 = energy(r.v);
    assert_true(e0 > 0);
    lm_move_result res;
    assert_int_equal(lm_moves_try(r.mv, LM_MOVE_SWAP, 0, 2, 3, 0, &res), LM_OK);
    accept_checks(&r, &res, e0);
    assert_int_equal(res.evals, 1); /* level 0: no optimisation */
    assert_true(lm_mesh_edge_exists(r.m, 0, 1));
    assert_false(lm_mesh_edge_exists(r.m, 2, 3));
    assert_true(energy(r.v) < e0 / 4); /* the crest is back */
    rig_free(&r);
}

static void test_split_accept(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, lmt_make_sphere(3), lmt_make_sphere(0), 0);
    int64_t e0 = energy(r.v);
    lm_move_result res;
    assert_int_equal(lm_moves_try(r.mv, LM_MOVE_SPLIT, 1, 0, 2, 0, &res), LM_OK);
    accept_checks(&r, &res, e0);
    assert_int_equal(r.m->live_verts, 7);
    assert_true(res.site.v != LM_NONE);
    assert_true(norm3(r.m->pos[res.site.v]) > 0.75); /* the midpoint is at 0.707 */
    rig_free(&r);
}

static void test_collapse_accept(void **state)
{
    (void)state;
    lm_mesh *coarse = lmt_make_sphere(1);
    assert_int_equal(lm_mesh_build_adjacency(coarse), LM_OK);
    uint32_t a = 0, b = first_neighbor(coarse, 0), v;
    assert_int_equal(lm_mesh_split_edge(coarse, a, b, &v, NULL), LM_OK);
    for (int k = 0; k < 3; k++)
        coarse->pos[v][k] *= 0.6f; /* a dent */
    rig r;
    rig_init(&r, lmt_make_sphere(1), coarse, 0);
    uint32_t verts = r.m->live_verts;
    int64_t e0 = energy(r.v);
    lm_move_result res;
    assert_int_equal(lm_moves_try(r.mv, LM_MOVE_COLLAPSE, 1, b, v, 0, &res), LM_OK);
    accept_checks(&r, &res, e0);
    assert_int_equal(r.m->live_verts, verts - 1);
    assert_false(r.m->vert_alive[v]);
    assert_true(energy(r.v) < e0 / 4);
    rig_free(&r);
}

static void test_reject_restores(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, lmt_make_sphere(3), sphere_with(2, 0, 0.8f), 0);
    uint32_t b = first_neighbor(r.m, 0);
    const lm_move_kind kinds[4] = {LM_MOVE_NOOP, LM_MOVE_SWAP, LM_MOVE_SPLIT, LM_MOVE_COLLAPSE};
    for (int k = 0; k < 4; k++)
        for (int level = k == 0 ? 1 : 0; level < 4; level++) {
            uint64_t h = lm_mesh_hash(r.m);
            uint32_t nv = r.m->n_verts, nt = r.m->n_tris;
            int64_t e0 = energy(r.v);
            lm_move_result res;
            assert_int_equal(lm_moves_try(r.mv, kinds[k], level, 0, b, INT64_MIN, &res), LM_OK);
            assert_true(res.legal);
            assert_false(res.accepted);
            assert_true(res.evals > 0);
            assert_true(res.delta != INT64_MAX);
            assert_true(lm_mesh_hash(r.m) == h);
            assert_int_equal(r.m->n_verts, nv);
            assert_int_equal(r.m->n_tris, nt);
            assert_true(energy(r.v) == e0);
        }
    check_fresh(&r);
    rig_free(&r);
}

static void test_illegal(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, lmt_make_grid(4), lmt_make_grid(4), 0);
    uint64_t h = lm_mesh_hash(r.m);
    lm_move_result res;
    /* (0, 1) is a boundary edge: no swap */
    assert_int_equal(lm_moves_try(r.mv, LM_MOVE_SWAP, 1, 0, 1, 0, &res), LM_OK);
    assert_false(res.legal);
    assert_int_equal(res.evals, 0);
    /* not an edge at all */
    assert_int_equal(lm_moves_try(r.mv, LM_MOVE_NOOP, 1, 0, 15, 0, &res), LM_OK);
    assert_false(res.legal);
    assert_int_equal(lm_moves_try(r.mv, LM_MOVE_COLLAPSE, 1, 0, 99999, 0, &res), LM_OK);
    assert_false(res.legal);
    assert_true(lm_mesh_hash(r.m) == h);
    assert_int_not_equal(lm_moves_try(r.mv, LM_MOVE_NOOP, 0, 0, 1, 0, &res), LM_OK);
    rig_free(&r);
}

static int has(const lm_idset *s, uint32_t v)
{
    return lm_idset_has(s, v);
}

static void test_vertex_sets(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2);
    lm_idset s;
    lm_idset_init(&s);
    uint32_t a = 0, b = first_neighbor(m, 0);
    uint32_t t[2];
    assert_int_equal(lm_mesh_edge_tris(m, a, b, t, 2), 2);
    lm_move_site site = {.kind = LM_MOVE_NOOP, .a = a, .b = b, .v = LM_NONE};
    for (int k = 0; k < 3; k++) {
        uint32_t x = lm_tri_vertex(m, t[0], k), y = lm_tri_vertex(m, t[1], k);
        if (x != a && x != b)
            site.c = x;
        if (y != a && y != b)
            site.d = y;
    }
    assert_int_equal(lm_moves_vertex_set(m, &site, 1, &s), LM_OK);
    assert_int_equal(s.n, 2);
    assert_true(s.ids[0] == a && s.ids[1] == b);
    assert_int_equal(lm_moves_vertex_set(m, &site, 2, &s), LM_OK);
    assert_int_equal(s.n, 4);
    assert_true(has(&s, site.c) && has(&s, site.d));
    assert_int_equal(lm_moves_vertex_set(m, &site, 3, &s), LM_OK);
    uint32_t na[64], nb[64];
    uint32_t ka = lm_mesh_vertex_neighbors(m, a, na, 64),
             kb = lm_mesh_vertex_neighbors(m, b, nb, 64);
    assert_int_equal(s.n, ka + kb - 2); /* a, b, and their rings; c, d and a, b shared */
    assert_true(s.ids[0] == a && s.ids[1] == b);
    site.kind = LM_MOVE_SWAP;
    assert_int_equal(lm_moves_vertex_set(m, &site, 0, &s), LM_OK);
    assert_int_equal(s.n, 0);
    assert_int_equal(lm_moves_vertex_set(m, &site, 1, &s), LM_OK);
    assert_true(s.n == 2 && s.ids[0] == site.c && s.ids[1] == site.d);
    assert_int_equal(lm_moves_vertex_set(m, &site, 2, &s), LM_OK);
    assert_int_equal(s.n, 4);
    site.kind = LM_MOVE_COLLAPSE;
    site.v = a;
    assert_int_equal(lm_moves_vertex_set(m, &site, 1, &s), LM_OK);
    assert_true(s.n == 1 && s.ids[0] == a);
    assert_int_equal(lm_moves_vertex_set(m, &site, 2, &s), LM_OK);
    assert_true(s.n == 3 && s.ids[0] == a && has(&s, site.c) && has(&s, site.d));
    assert_int_equal(lm_moves_vertex_set(m, &site, 3, &s), LM_OK);
    assert_int_equal(s.n, 1 + ka);
    site.kind = LM_MOVE_SPLIT;
    site.v = 5;
    assert_int_equal(lm_moves_vertex_set(m, &site, 3, &s), LM_OK);
    assert_true(s.ids[0] == 5 && has(&s, a) && has(&s, b));
    lm_idset_free(&s);
    lm_mesh_destroy(m);
}

static void test_teleport(void **state)
{
    (void)state;
    /* a wasted vertex: an edge split at its midpoint, flat, on one side of the sphere */
    lm_mesh *coarse = lmt_make_sphere(1);
    assert_int_equal(lm_mesh_build_adjacency(coarse), LM_OK);
    uint32_t w;
    assert_int_equal(lm_mesh_split_edge(coarse, 0, first_neighbor(coarse, 0), &w, NULL), LM_OK);
    rig r;
    rig_init(&r, lmt_make_sphere(3), coarse, 0);
    lm_teleport tp;
    assert_int_equal(lm_teleport_init(&tp, NULL, r.m), LM_OK);
    uint32_t verts = r.m->live_verts;
    int64_t e0 = energy(r.v);
    /* rejection: a huge recent collapse cost makes no split worth it */
    tp.last_collapse = INT64_MAX / 4;
    tp.last_time = lm_moves_evals(r.mv);
    uint64_t h = lm_mesh_hash(r.m);
    lm_teleport_result res;
    assert_int_equal(lm_teleport_try(&tp, r.mv, 1, 1, first_neighbor(r.m, 1), &res), LM_OK);
    assert_true(res.legal);
    assert_false(res.accepted);
    assert_true(lm_mesh_hash(r.m) == h && energy(r.v) == e0);
    /* acceptance: split on the far side, pay with a cheap collapse */
    tp.last_collapse = 0;
    int accepted = 0;
    for (uint32_t v = 1; v < 6 && !accepted; v++) {
        int64_t before = energy(r.v);
        assert_int_equal(lm_teleport_try(&tp, r.mv, 1, v, first_neighbor(r.m, v), &res), LM_OK);
        lm_moves_forget(r.mv);
        assert_int_equal(r.m->live_verts, verts);
        assert_true(energy(r.v) == before + res.delta);
        accepted = res.accepted;
        if (accepted)
            assert_true(res.delta < 0 && res.collapse_attempts > 0);
    }
    assert_true(accepted);
    assert_true(tp.searches > 0);
    check_fresh(&r);
    lm_teleport_free(&tp);
    rig_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vertex_sets),     cmocka_unit_test(test_noop_accept),
        cmocka_unit_test(test_color_accept),    cmocka_unit_test(test_swap_accept),
        cmocka_unit_test(test_split_accept),    cmocka_unit_test(test_collapse_accept),
        cmocka_unit_test(test_reject_restores), cmocka_unit_test(test_illegal),
        cmocka_unit_test(test_teleport),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
