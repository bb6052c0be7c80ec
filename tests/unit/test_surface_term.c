/* tests/unit/test_surface_term.c — the optimizer's geometric term (surface_term.h) over a test
 * double of views whose image energy is a set number (0 unless a test says): a triangle on the
 * surface costs nothing and one lifted off a plane by h costs k · area · h²; evaluate's ΔE is
 * exactly what a commit then changes in energy, and 0 for triangles whose corners did not move; the
 * total does not depend on the order of the triangles; ops are passed on to the wrapped views; a
 * share gives the weight that makes E_geo that share of the image energy; wrapping views of another
 * count and size scales k by their views × pixels, and back again to the same bits. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/surface_term.h"
#include "common/patch.h"
#include "test_support.h"

typedef struct zero_views {
    lm_views base;
    int set_mesh, evaluate, commit, evaluate_surface;
    int64_t image;     /* what energy reports */
    int overlap_costs; /* what info reports */
    int holds;         /* they take the term too, as workers do (pricing 0 of it) */
    uint32_t n_views;  /* what info reports (0: 10) */
    int width;         /* likewise (0: 128) */
} zero_views;

static lm_status zv_set_mesh(lm_views *v, const lm_tri_data *t, size_t n)
{
    (void)t, (void)n;
    ((zero_views *)v)->set_mesh++;
    return LM_OK;
}
static lm_status zv_set_materials(lm_views *v, const lm_material *m, uint32_t n)
{
    (void)v, (void)m, (void)n;
    return LM_OK;
}
static lm_status zv_evaluate(lm_views *v, const lm_patch *p, uint32_t n, int64_t *d)
{
    (void)p;
    ((zero_views *)v)->evaluate++;
    for (uint32_t i = 0; i < n; i++)
        d[i] = 0;
    return LM_OK;
}
static lm_status zv_commit(lm_views *v, const lm_patch *p)
{
    (void)p;
    ((zero_views *)v)->commit++;
    return LM_OK;
}
static lm_status zv_energy(lm_views *v, int64_t *t, int64_t *pv)
{
    (void)pv;
    *t = ((zero_views *)v)->image;
    return LM_OK;
}
static lm_status zv_potentials(lm_views *v, const float (*p)[3], size_t n, int64_t *out)
{
    (void)v, (void)p, (void)n, (void)out;
    return LM_E_UNSUPPORTED;
}
static lm_status zv_read_image(lm_views *v, lm_image_kind k, uint32_t view, uint8_t *out)
{
    (void)v, (void)k, (void)view, (void)out;
    return LM_E_UNSUPPORTED;
}
static void zv_info(lm_views *v, lm_views_info *out)
{
    memset(out, 0, sizeof *out);
    const zero_views *z = (const zero_views *)v;
    out->n_views = z->n_views ? z->n_views : 10;
    out->width = out->height = z->width ? z->width : 128;
    out->overlap_costs = ((zero_views *)v)->overlap_costs;
}
static void zv_destroy(lm_views *v)
{
    (void)v;
}

static lm_status zv_surface_term(lm_views *v, const lm_mesh *surface, double k)
{
    (void)surface, (void)k;
    return ((zero_views *)v)->holds ? LM_OK : lm_fail(LM_E_UNSUPPORTED, "no term here");
}
static lm_status zv_evaluate_surface(lm_views *v, const lm_patch *p, uint32_t n, int64_t *d)
{
    ((zero_views *)v)->evaluate_surface++;
    ((zero_views *)v)->evaluate--; /* counted once, as the one evaluation it is */
    return zv_evaluate(v, p, n, d);
}

static const lm_views_ops zero_ops = {.set_mesh = zv_set_mesh,
                                      .set_materials = zv_set_materials,
                                      .evaluate = zv_evaluate,
                                      .commit = zv_commit,
                                      .energy = zv_energy,
                                      .potentials = zv_potentials,
                                      .read_image = zv_read_image,
                                      .info = zv_info,
                                      .destroy = zv_destroy,
                                      .surface_term = zv_surface_term,
                                      .evaluate_surface = zv_evaluate_surface};

typedef struct fixture {
    zero_views inner;
    lm_mesh *plane; /* the surface: a flat grid in z = 0 */
    lm_views *v;
} fixture;

static void setup(fixture *f)
{
    memset(f, 0, sizeof *f);
    f->inner.base.ops = &zero_ops;
    f->plane = lmt_make_grid(9);
    assert_int_equal(lm_surface_views_create(&f->inner.base, f->plane, 2.0, &f->v), LM_OK);
}

static void teardown(fixture *f)
{
    lm_views_destroy(f->v);
    lm_mesh_destroy(f->plane);
}

static lm_tri_data tri(uint32_t id, float x, float y, float s, float z)
{
    lm_tri_data t;
    memset(&t, 0, sizeof t);
    t.id = id;
    const float c[3][3] = {{x, y, z}, {x + s, y, z}, {x, y + s, z}};
    for (int v = 0; v < 3; v++)
        memcpy(t.c[v].pos, c[v], sizeof c[v]);
    return t;
}

/* e(t) of one triangle's corners. */
static int64_t corner_energy(const lm_views *v, const lm_tri_data *t)
{
    float p[3][3];
    for (int c = 0; c < 3; c++)
        memcpy(p[c], t->c[c].pos, sizeof p[c]);
    return lm_surface_views_tri(v, (const float(*)[3])p);
}

static int64_t energy(lm_views *v)
{
    int64_t e = -1;
    assert_int_equal(v->ops->energy(v, &e, NULL), LM_OK);
    return e;
}

static void test_scale(void **state)
{
    (void)state;
    fixture f;
    setup(&f);
    float on[3][3] = {{0.2f, 0.2f, 0}, {0.5f, 0.2f, 0}, {0.2f, 0.5f, 0}};
    assert_true(lm_surface_views_tri(f.v, (const float(*)[3])on) == 0);
    /* lifted by h everywhere (inside the plane's extent): k · area · h² */
    const float h = 0.01f;
    float up[3][3] = {{0.2f, 0.2f, h}, {0.5f, 0.2f, h}, {0.2f, 0.5f, h}};
    float c[3], r;
    lm_mesh_bounding_sphere(f.plane, c, &r);
    double px = 128.0 / (2.0 * r), px256 = 256.0 / (2.0 * r);
    double k = 2.0 * 10 * px * px * px256 * px256;
    double want = k * 0.5 * 0.3 * 0.3 * (double)h * h;
    int64_t got = lm_surface_views_tri(f.v, (const float(*)[3])up);
    assert_true(want > 100);
    assert_true(fabs((double)got - want) <= 1e-3 * want + 1);
    /* twice as far costs four times as much */
    for (int v = 0; v < 3; v++)
        up[v][2] = 2 * h;
    assert_true(fabs((double)lm_surface_views_tri(f.v, (const float(*)[3])up) - 4 * want) <=
                4e-3 * want + 1);
    teardown(&f);
}

static void test_delta_is_what_commit_changes(void **state)
{
    (void)state;
    fixture f;
    setup(&f);
    lm_tri_data t[3] = {tri(0, 0.1f, 0.1f, 0.2f, 0.02f), tri(1, 0.5f, 0.1f, 0.2f, 0),
                        tri(4, 0.1f, 0.5f, 0.3f, -0.03f)};
    assert_int_equal(f.v->ops->set_mesh(f.v, t, 3), LM_OK);
    assert_int_equal(f.inner.set_mesh, 1);
    int64_t e0 = energy(f.v);
    assert_true(e0 > 0 && e0 == lm_surface_views_energy(f.v));
    lm_patch p[2];
    lm_patch_init(&p[0]);
    lm_patch_init(&p[1]);
    /* 0: triangle 0 put on the plane, triangle 7 added off it, triangle 4 gone */
    lm_tri_data t0 = tri(0, 0.1f, 0.1f, 0.2f, 0), t7 = tri(7, 0.6f, 0.6f, 0.2f, 0.05f);
    assert_int_equal(lm_patch_remove(&p[0], 0), LM_OK);
    assert_int_equal(lm_patch_remove(&p[0], 4), LM_OK);
    assert_int_equal(lm_patch_add(&p[0], &t0), LM_OK);
    assert_int_equal(lm_patch_add(&p[0], &t7), LM_OK);
    /* 1: triangle 1 re-sent unchanged */
    assert_int_equal(lm_patch_remove(&p[1], 1), LM_OK);
    assert_int_equal(lm_patch_add(&p[1], &t[1]), LM_OK);
    int64_t d[2] = {1, 1};
    assert_int_equal(f.v->ops->evaluate(f.v, p, 2, d), LM_OK);
    assert_int_equal(f.inner.evaluate, 1);
    assert_true(d[1] == 0);
    assert_true(d[0] != 0);
    assert_true(energy(f.v) == e0); /* evaluate changes nothing */
    assert_int_equal(f.v->ops->commit(f.v, &p[0]), LM_OK);
    assert_int_equal(f.inner.commit, 1);
    assert_true(energy(f.v) == e0 + d[0]);
    /* what is left: triangle 1 (on the plane) and triangle 7 */
    assert_true(energy(f.v) == corner_energy(f.v, &t7));
    lm_patch_free(&p[0]);
    lm_patch_free(&p[1]);
    teardown(&f);
}

static void test_order_free(void **state)
{
    (void)state;
    fixture a, b;
    setup(&a);
    setup(&b);
    lm_tri_data t[16], r[16];
    uint64_t seed = 7;
    for (int i = 0; i < 16; i++)
        t[i] = tri((uint32_t)i, (float)lmt_urand(&seed) * 0.7f, (float)lmt_urand(&seed) * 0.7f,
                   0.1f + 0.2f * (float)lmt_urand(&seed), 0.1f * (float)lmt_urand(&seed) - 0.05f);
    for (int i = 0; i < 16; i++)
        r[i] = t[15 - i];
    assert_int_equal(a.v->ops->set_mesh(a.v, t, 16), LM_OK);
    assert_int_equal(b.v->ops->set_mesh(b.v, r, 16), LM_OK);
    assert_true(energy(a.v) == energy(b.v) && energy(a.v) > 0);
    /* set_mesh again starts afresh */
    assert_int_equal(a.v->ops->set_mesh(a.v, t, 1), LM_OK);
    assert_true(energy(a.v) == corner_energy(a.v, &t[0]));
    teardown(&a);
    teardown(&b);
}

/* A new weight rescales every e(t) as a fresh term of that weight computes it, and the unit energy
 * is the unrounded E_geo at weight 1. */
static void test_set_weight(void **state)
{
    (void)state;
    fixture a, b;
    setup(&a);
    setup(&b);
    lm_tri_data t[8];
    uint64_t seed = 11;
    for (int i = 0; i < 8; i++)
        t[i] = tri((uint32_t)i, (float)lmt_urand(&seed) * 0.7f, (float)lmt_urand(&seed) * 0.7f,
                   0.1f + 0.2f * (float)lmt_urand(&seed), 0.1f * (float)lmt_urand(&seed) - 0.05f);
    assert_int_equal(a.v->ops->set_mesh(a.v, t, 8), LM_OK);
    double unit = lm_surface_views_unit_energy(a.v);
    assert_true(unit > 0 && fabs(2.0 * unit - (double)energy(a.v)) <= 8);
    lm_views_destroy(b.v);
    assert_int_equal(lm_surface_views_create(&b.inner.base, b.plane, 7.5, &b.v), LM_OK);
    assert_int_equal(b.v->ops->set_mesh(b.v, t, 8), LM_OK);
    lm_surface_views_set_weight(a.v, 7.5);
    assert_true(energy(a.v) == energy(b.v));
    for (int i = 0; i < 8; i++)
        assert_true(corner_energy(a.v, &t[i]) == corner_energy(b.v, &t[i]));
    assert_true(lm_surface_views_unit_energy(a.v) == unit);
    teardown(&a);
    teardown(&b);
}

static void test_share_weight(void **state)
{
    (void)state;
    fixture f;
    setup(&f);
    lm_tri_data t[6];
    uint64_t seed = 5;
    for (int i = 0; i < 6; i++)
        t[i] = tri((uint32_t)i, (float)lmt_urand(&seed) * 0.7f, (float)lmt_urand(&seed) * 0.7f,
                   0.1f + 0.2f * (float)lmt_urand(&seed), 0.1f * (float)lmt_urand(&seed) - 0.05f);
    assert_int_equal(f.v->ops->set_mesh(f.v, t, 6), LM_OK);
    double w = 0;
    assert_int_equal(lm_surface_views_weight_for_share(f.v, 0.1, &w), LM_OK);
    assert_true(w == 1.0); /* no image energy: weight 1 */
    f.inner.image = 40000000;
    assert_int_equal(lm_surface_views_weight_for_share(f.v, 0.1, &w), LM_OK);
    double unit = lm_surface_views_unit_energy(f.v);
    assert_true(w > 0 && fabs(w * unit - 4000000.0) <= 1e-6 * 4000000.0);
    lm_surface_views_set_weight(f.v, w);
    int64_t geo = energy(f.v) - f.inner.image;
    assert_true(geo == lm_surface_views_energy(f.v));
    assert_true(llabs(geo - 4000000) <= 6); /* one rounding per triangle */
    teardown(&f);
}

static void test_refuses_bad_arguments(void **state)
{
    (void)state;
    fixture f;
    setup(&f);
    lm_views *v = NULL;
    assert_int_equal(lm_surface_views_create(&f.inner.base, f.plane, 0, &v), LM_E_INVALID);
    assert_int_equal(lm_surface_views_create(&f.inner.base, f.plane, NAN, &v), LM_E_INVALID);
    assert_int_equal(lm_surface_views_create(&f.inner.base, NULL, 1, &v), LM_E_INVALID);
    assert_null(v);
    teardown(&f);
}
/* set_inner with views of another count and size: k becomes weight · views · px² · px256² of the
 * new ones (k × views × pixels relative to the old), e(t) and E_geo with it, the weight and the
 * term handed to the new views where they take it; back on views like the first, k's bits are the
 * first's. */
static void test_inner_of_other_size(void **state)
{
    (void)state;
    fixture f;
    setup(&f);
    zero_views big = {.base.ops = &zero_ops, .n_views = 23, .width = 160, .holds = 1};
    zero_views same = {.base.ops = &zero_ops};
    lm_tri_data t[2] = {tri(0, 0.1f, 0.1f, 0.3f, 0.02f), tri(1, 0.5f, 0.5f, 0.3f, -0.03f)};
    assert_int_equal(f.v->ops->set_mesh(f.v, t, 2), LM_OK);
    double k0 = lm_surface_views_scale(f.v);
    int64_t e0 = energy(f.v);
    float c[3], r;
    lm_mesh_bounding_sphere(f.plane, c, &r);
    double px = 128.0 / (2.0 * r), px256 = 256.0 / (2.0 * r);
    assert_true(k0 == 2.0 * 10 * px * px * px256 * px256);
    assert_false(lm_surface_views_offloaded(f.v));
    /* 23 views of 160²: k × 2.3 × 1.5625 */
    assert_int_equal(lm_surface_views_set_inner(f.v, &big.base), LM_OK);
    assert_true(lm_surface_views_offloaded(f.v));
    assert_int_equal(f.v->ops->set_mesh(f.v, t, 2), LM_OK);
    double px2 = 160.0 / (2.0 * r), k1 = 2.0 * 23 * px2 * px2 * px256 * px256;
    assert_true(lm_surface_views_scale(f.v) == k1);
    assert_true(fabs(k1 / k0 - 2.3 * 1.5625) <= 1e-12);
    double want = (double)e0 * 2.3 * 1.5625;
    assert_true(e0 > 100 && fabs((double)energy(f.v) - want) <= 1e-3 * want + 2);
    /* a fresh wrapper of the big views at the same weight gives the same bits */
    lm_views *g = NULL;
    assert_int_equal(lm_surface_views_create(&big.base, f.plane, 2.0, &g), LM_OK);
    assert_int_equal(g->ops->set_mesh(g, t, 2), LM_OK);
    assert_true(lm_surface_views_scale(g) == k1 && energy(g) == energy(f.v));
    lm_views_destroy(g);
    /* back on 10 views of 128²: the first k and energy exactly */
    assert_int_equal(lm_surface_views_set_inner(f.v, &same.base), LM_OK);
    assert_int_equal(f.v->ops->set_mesh(f.v, t, 2), LM_OK);
    assert_true(lm_surface_views_scale(f.v) == k0 && energy(f.v) == e0);
    teardown(&f);
}

/* Workers that busy every processor here price the term from the first evaluation on and are
 * never probed (work here would take a processor from one of them); otherwise the first batch
 * is priced here, to measure. */
static void test_pricing_where_the_cores_are_full(void **state)
{
    (void)state;
    for (int full = 0; full <= 1; full++) {
        zero_views inner = {.base.ops = &zero_ops, .overlap_costs = full, .holds = 1};
        lm_mesh *plane = lmt_make_grid(9);
        lm_views *v = NULL;
        assert_int_equal(lm_surface_views_create(&inner.base, plane, 2.0, &v), LM_OK);
        assert_true(lm_surface_views_offloaded(v));
        lm_surface_views_set_pricing(v, LM_SURFACE_AUTO);
        lm_tri_data t[2] = {tri(0, 0.1f, 0.1f, 0.3f, 0.0f), tri(1, 0.5f, 0.5f, 0.3f, 0.0f)};
        assert_int_equal(v->ops->set_mesh(v, t, 2), LM_OK);
        lm_patch p;
        lm_patch_init(&p);
        uint32_t removed = 0;
        lm_tri_data moved = tri(0, 0.1f, 0.1f, 0.3f, 0.02f);
        p.removed = &removed, p.n_removed = 1, p.added = &moved, p.n_added = 1;
        int64_t d = 0;
        assert_int_equal(v->ops->evaluate(v, &p, 1, &d), LM_OK);
        assert_int_equal(inner.evaluate_surface, full);
        assert_int_equal(inner.evaluate, !full);
        /* full: never probed here either (past SV_PROBE_EVERY batches) */
        for (int i = 0; full && i < 40; i++)
            assert_int_equal(v->ops->evaluate(v, &p, 1, &d), LM_OK);
        assert_true(lm_surface_views_worker_share(v) == (full ? 1.0 : 0.0));
        lm_views_destroy(v);
        lm_mesh_destroy(plane);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scale),
        cmocka_unit_test(test_delta_is_what_commit_changes),
        cmocka_unit_test(test_order_free),
        cmocka_unit_test(test_set_weight),
        cmocka_unit_test(test_inner_of_other_size),
        cmocka_unit_test(test_share_weight),
        cmocka_unit_test(test_refuses_bad_arguments),
        cmocka_unit_test(test_pricing_where_the_cores_are_full),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
