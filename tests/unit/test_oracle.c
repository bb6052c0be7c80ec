/* tests/unit/test_oracle.c — the oracle: an edge under a planted error ranks first and edges far
 * from it rank last; iteration plans take the requested share of best edges, skip stale ones,
 * fill up with distinct random edges, interleave the two, and are deterministic for a seed; the
 * balance moves the share towards the source that made more progress, within its bounds.
 * The views are a test double whose potentials come from a planted function of the point. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh_topology.h"
#include "common/optimizer/oracle.h"
#include "test_support.h"

typedef struct fake_views {
    lm_views base;
    float centre[3];
    float width;
    int calls;
} fake_views;

static lm_status fv_potentials(lm_views *v, const float (*pts)[3], size_t n, int64_t *out)
{
    fake_views *f = (fake_views *)v;
    f->calls++;
    for (size_t i = 0; i < n; i++) {
        double d2 = 0;
        for (int k = 0; k < 3; k++)
            d2 += (pts[i][k] - f->centre[k]) * (double)(pts[i][k] - f->centre[k]);
        out[i] = (int64_t)(1e6 * exp(-d2 / (f->width * f->width)));
    }
    return LM_OK;
}

static lm_status fv_set_mesh(lm_views *v, const lm_tri_data *t, size_t n)
{
    (void)v, (void)t, (void)n;
    return LM_E_UNSUPPORTED;
}
static lm_status fv_evaluate(lm_views *v, const lm_patch *p, uint32_t n, int64_t *d)
{
    (void)v, (void)p, (void)n, (void)d;
    return LM_E_UNSUPPORTED;
}
static lm_status fv_commit(lm_views *v, const lm_patch *p)
{
    (void)v, (void)p;
    return LM_E_UNSUPPORTED;
}
static lm_status fv_energy(lm_views *v, int64_t *t, int64_t *pv)
{
    (void)v, (void)t, (void)pv;
    return LM_E_UNSUPPORTED;
}
static void fv_info(lm_views *v, lm_views_info *out)
{
    (void)v;
    memset(out, 0, sizeof *out);
}
static void fv_destroy(lm_views *v)
{
    (void)v;
}

static const lm_views_ops fake_ops = {.set_mesh = fv_set_mesh,
                                      .evaluate = fv_evaluate,
                                      .commit = fv_commit,
                                      .energy = fv_energy,
                                      .potentials = fv_potentials,
                                      .info = fv_info,
                                      .destroy = fv_destroy};

typedef struct fixture {
    lm_mesh *m;
    uint32_t (*edges)[2];
    size_t n;
    fake_views fv;
} fixture;

static void setup_fixture(fixture *f, size_t planted)
{
    f->m = lmt_make_sphere(2);
    assert_non_null(f->m);
    assert_int_equal(lm_mesh_build_adjacency(f->m), LM_OK);
    assert_int_equal(lm_mesh_list_edges(f->m, &f->edges, &f->n), LM_OK);
    assert_true(f->n > 100);
    memset(&f->fv, 0, sizeof f->fv);
    f->fv.base.ops = &fake_ops;
    const float *a = f->m->pos[f->edges[planted][0]], *b = f->m->pos[f->edges[planted][1]];
    for (int k = 0; k < 3; k++)
        f->fv.centre[k] = 0.5f * (a[k] + b[k]);
    f->fv.width = 0.15f;
}

static void teardown_fixture(fixture *f)
{
    free(f->edges);
    lm_mesh_destroy(f->m);
}

static double edge_distance(const fixture *f, const lm_ranked_edge *e)
{
    double d = 0;
    for (int k = 0; k < 3; k++) {
        double mid = 0.5 * (f->m->pos[e->a][k] + f->m->pos[e->b][k]);
        d += (mid - f->fv.centre[k]) * (mid - f->fv.centre[k]);
    }
    return sqrt(d);
}

static void test_planted_error_ranks_first(void **state)
{
    (void)state;
    const size_t planted[] = {0, 17, 101};
    for (int p = 0; p < 3; p++) {
        fixture f;
        setup_fixture(&f, planted[p]);
        lm_ranked_edge *r;
        assert_int_equal(lm_oracle_rank(&f.fv.base, f.m, (const uint32_t(*)[2])f.edges, f.n, &r),
                         LM_OK);
        assert_int_equal(f.fv.calls, 1); /* one potentials call for all points */
        assert_int_equal(r[0].a, f.edges[planted[p]][0]);
        assert_int_equal(r[0].b, f.edges[planted[p]][1]);
        for (size_t i = 1; i < f.n; i++)
            assert_true(r[i - 1].potential >= r[i].potential);
        /* the lower half lies far from the planted error */
        for (size_t i = f.n / 2; i < f.n; i++)
            assert_true(edge_distance(&f, &r[i]) > 0.3);
        free(r);
        teardown_fixture(&f);
    }
}

static void test_plan(void **state)
{
    (void)state;
    fixture f;
    setup_fixture(&f, 5);
    lm_ranked_edge *r;
    assert_int_equal(lm_oracle_rank(&f.fv.base, f.m, (const uint32_t(*)[2])f.edges, f.n, &r),
                     LM_OK);
    lm_oracle o;
    lm_oracle_init(&o);
    lm_rng rng, rng2;
    lm_rng_seed(&rng, 7);
    lm_rng_seed(&rng2, 7);
    lm_planned_edge p[64], q[64];
    uint32_t n, n2;
    assert_int_equal(lm_oracle_plan(&o, r, f.n, &rng, 64, p, &n), LM_OK);
    assert_int_equal(lm_oracle_plan(&o, r, f.n, &rng2, 64, q, &n2), LM_OK);
    assert_int_equal(n, 64);
    assert_int_equal(n2, 64);
    assert_memory_equal(p, q, sizeof p); /* deterministic */
    uint32_t from_oracle = 0;
    for (uint32_t i = 0; i < n; i++) {
        from_oracle += p[i].from_oracle;
        for (uint32_t j = 0; j < i; j++)
            assert_false(p[i].a == p[j].a && p[i].b == p[j].b);
    }
    assert_int_equal(from_oracle, 32);
    assert_true(p[0].from_oracle && p[0].a == r[0].a && p[0].b == r[0].b);
    assert_false(p[1].from_oracle); /* interleaved */
    /* the next oracle edge is the best one not sharing a vertex with the first */
    size_t second = 1;
    while (r[second].a == r[0].a || r[second].a == r[0].b || r[second].b == r[0].a ||
           r[second].b == r[0].b)
        second++;
    assert_true(second > 1); /* the planted error covers neighbouring edges too */
    assert_true(p[2].from_oracle && p[2].a == r[second].a && p[2].b == r[second].b);
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = 0; j < i; j++)
            if (p[i].from_oracle && p[j].from_oracle)
                assert_false(p[i].a == p[j].a || p[i].a == p[j].b || p[i].b == p[j].a ||
                             p[i].b == p[j].b);
    /* the best edge made no progress: it is skipped next time; oracle did better than random */
    uint64_t stale = lm_edge_key(r[0].a, r[0].b);
    lm_oracle_balance(&o, 1000, 32, 10, 32);
    assert_int_equal(lm_oracle_update_stale(&o, 0, &stale, 1, NULL, NULL), LM_OK);
    assert_true(o.share > 0.5 && o.share <= o.max_share);
    assert_int_equal(lm_oracle_plan(&o, r, f.n, &rng, 64, p, &n), LM_OK);
    from_oracle = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (p[i].from_oracle)
            assert_false(p[i].a == r[0].a && p[i].b == r[0].b);
        from_oracle += p[i].from_oracle;
    }
    assert_int_equal(from_oracle, (uint32_t)lround(o.share * 64));
    assert_true(p[0].a == r[1].a && p[0].b == r[1].b);
    /* random edges doing better push the share down, never below its minimum */
    for (int i = 0; i < 20; i++)
        lm_oracle_balance(&o, 0, 32, 500, 32);
    assert_true(fabs(o.share - o.min_share) < 1e-12);
    lm_oracle_free(&o);
    free(r);
    teardown_fixture(&f);
}

static void test_small_mesh_plan(void **state)
{
    (void)state;
    fixture f;
    f.m = lmt_make_sphere(0); /* octahedron: 12 edges */
    assert_int_equal(lm_mesh_build_adjacency(f.m), LM_OK);
    assert_int_equal(lm_mesh_list_edges(f.m, &f.edges, &f.n), LM_OK);
    memset(&f.fv, 0, sizeof f.fv);
    f.fv.base.ops = &fake_ops;
    f.fv.width = 1;
    lm_ranked_edge *r;
    assert_int_equal(lm_oracle_rank(&f.fv.base, f.m, (const uint32_t(*)[2])f.edges, f.n, &r),
                     LM_OK);
    lm_oracle o;
    lm_oracle_init(&o);
    lm_rng rng;
    lm_rng_seed(&rng, 1);
    lm_planned_edge p[64];
    uint32_t n;
    assert_int_equal(lm_oracle_plan(&o, r, f.n, &rng, 64, p, &n), LM_OK);
    assert_true(n <= f.n); /* never more than there are edges, each once */
    assert_true(n >= 12 * 3 / 4);
    lm_oracle_free(&o);
    free(r);
    teardown_fixture(&f);
}

static int touches_vertex(const void *ctx, uint32_t v)
{
    return v == *(const uint32_t *)ctx;
}

static void test_stale_edges(void **state)
{
    (void)state;
    lm_oracle o;
    lm_oracle_init(&o);
    o.max_age = 3;
    uint64_t k1 = lm_edge_key(1, 2), k2 = lm_edge_key(5, 3), k3 = lm_edge_key(7, 8);
    uint64_t first[2] = {k2, k1};
    assert_int_equal(lm_oracle_update_stale(&o, 10, first, 2, NULL, NULL), LM_OK);
    assert_int_equal(o.n_stale, 2);
    assert_true(o.stale[0].key == k1 && o.stale[1].key == k2); /* sorted */
    /* a move touched vertex 3: edge (3, 5) is forgotten; (7, 8) joins */
    uint32_t v = 3;
    assert_int_equal(lm_oracle_update_stale(&o, 11, &k3, 1, touches_vertex, &v), LM_OK);
    assert_int_equal(o.n_stale, 2);
    assert_true(o.stale[0].key == k1 && o.stale[1].key == k3);
    /* tried again without progress: its age restarts; too old ones go */
    assert_int_equal(lm_oracle_update_stale(&o, 13, &k3, 1, NULL, NULL), LM_OK);
    assert_int_equal(lm_oracle_update_stale(&o, 14, NULL, 0, NULL, NULL), LM_OK);
    assert_int_equal(o.n_stale, 1);
    assert_true(o.stale[0].key == k3 && o.stale[0].iteration == 13);
    lm_stale_edge e[2] = {{k3, 4}, {k1, 2}};
    assert_int_equal(lm_oracle_set_stale(&o, e, 2), LM_OK);
    assert_true(o.n_stale == 2 && o.stale[0].key == k1);
    lm_oracle_free(&o);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_planted_error_ranks_first),
        cmocka_unit_test(test_plan),
        cmocka_unit_test(test_small_mesh_plan),
        cmocka_unit_test(test_stale_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
