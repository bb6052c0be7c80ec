/* tests/unit/test_isimp.c — the image-driven simplifier (coordinator/simplify): a collapse's
 * price is exactly E(full render after) - E(full render before) for every placement; the lazy
 * queue never collapses at a stale price (verify mode re-prices every entry it takes as exact after
 * each collapse — and, with the footprint test switched off, it does catch stale prices); the
 * result is the same mesh for one backend, a split and two worker processes; a shard's price is
 * the difference of the shard rendered alone before and after.
 * LUMESH_TEST_LIGHT=1 (the sanitizer stage; the release stage runs it whole): 6 views of 48
 * pixels instead of 8 of 64, 12 edges checked against full renders instead of 24, 6 verified
 * collapses instead of 12, the same-result runs from about 160 vertices to 140 instead of 200 to
 * 120; every assertion the same. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "coordinator/pool/pool.h"
#include "coordinator/simplify/candidates.h"
#include "coordinator/simplify/collapse_op.h"
#include "coordinator/simplify/isimp.h"
#include "coordinator/simplify/pricer.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/simplify/work.h"
#include "coordinator/views/views.h"
#include "test_support.h"

static int light; /* LUMESH_TEST_LIGHT=1 */
static int size = 64;
static uint32_t n_views = 8;

typedef struct rig {
    lm_mesh *orig, *work;
    lm_view_set vs;
    int derived;
} rig;

/* The spider (textured, 19 parts) cut by QEM to about `verts` vertices, made ready. */
static void rig_init(rig *r, uint32_t verts)
{
    memset(r, 0, sizeof *r);
    assert_int_equal(lm_mesh_load(lmt_spider_path(), NULL, &r->orig), LM_OK);
    lm_status st = co_simplify(r->orig, CO_SIMPLIFY_QEM, verts, &r->work);
    assert_true(st == LM_OK || (st == LM_E_RANGE && r->work));
    lm_clear_error();
    assert_int_equal(co_simplify_prepare(r->work, &r->derived), LM_OK);
    float c[3], rad;
    lm_mesh_bounding_sphere(r->orig, c, &rad);
    assert_int_equal(lm_view_set_make(&r->vs, n_views, size, c, rad), LM_OK);
}

static void rig_free(rig *r)
{
    lm_mesh_destroy(r->orig);
    lm_mesh_destroy(r->work);
}

static int64_t full_energy(const lm_mesh *orig, const lm_mesh *m, const lm_view_set *vs)
{
    lm_views *v;
    assert_int_equal(co_simplify_make_views(CO_PRICE_IMAGE, orig, m, vs, "host", NULL, &v), LM_OK);
    int64_t e;
    assert_int_equal(v->ops->energy(v, &e, NULL), LM_OK);
    lm_views_destroy(v);
    return e;
}

/* Candidates of the first `n` edges priced by the views, checked against full renders. */
static void collapse_costs_equal_full_renders(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 120);
    lm_views *v;
    assert_int_equal(
        co_simplify_make_views(CO_PRICE_IMAGE, r.orig, r.work, &r.vs, "host", NULL, &v), LM_OK);
    co_eq *q;
    assert_int_equal(co_eq_create(r.vs.count, &q), LM_OK);
    uint32_t(*edges)[2];
    size_t n_edges;
    assert_int_equal(lm_mesh_list_edges(r.work, &edges, &n_edges), LM_OK);
    uint32_t idx[24], n = light ? 12 : 24;
    for (uint32_t i = 0; i < n; i++)
        assert_int_equal(co_eq_insert(q, edges[i * 7][0], edges[i * 7][1], 0, &idx[i]), LM_OK);
    free(edges);
    co_cands c;
    co_pricer *p;
    assert_int_equal(co_cands_init(&c), LM_OK);
    assert_int_equal(co_pricer_create(CO_PRICE_IMAGE, v, &r.vs, 16, &p), LM_OK);
    assert_int_equal(co_cands_build(&c, r.work, q, &r.vs, r.derived, idx, n), LM_OK);
    assert_int_equal(co_pricer_price(p, &c, q), LM_OK);
    int64_t e0 = full_energy(r.orig, r.work, &r.vs);
    uint32_t checked = 0, nonzero = 0;
    lm_journal *j;
    assert_int_equal(lm_journal_create(&j), LM_OK);
    for (uint32_t i = 0; i < c.n_edges; i++) {
        const co_eq_entry *e = co_eq_at(q, c.edges[i].entry);
        co_place pl[CO_PLACE_KINDS];
        co_place_all(r.work, e->a, e->b, pl);
        for (uint32_t k = 0; k < c.edges[i].n; k++) {
            size_t mark = lm_journal_mark(j);
            assert_int_equal(co_collapse_apply(r.work, &pl[c.edges[i].kind[k]], r.derived, j),
                             LM_OK);
            int64_t e1 = full_energy(r.orig, r.work, &r.vs);
            lm_journal_rollback(r.work, j, mark);
            assert_true(c.delta[c.edges[i].patch0 + k] == e1 - e0);
            checked++;
            nonzero += e1 != e0;
        }
    }
    assert_true(checked >= 2 * n && nonzero >= checked / 2);
    lm_journal_destroy(j);
    co_pricer_destroy(p);
    co_cands_free(&c);
    co_eq_destroy(q);
    lm_views_destroy(v);
    rig_free(&r);
}

/* The shard after placement k: the shard's triangles the patch leaves, then those it adds. */
static size_t shard_after(const co_cands *c, const co_cand_edge *e, const lm_patch *p,
                          lm_tri_data *out)
{
    size_t n = 0;
    for (uint32_t i = 0; i < e->n_shard; i++) {
        const lm_tri_data *t = &c->shard[e->shard0 + i];
        int gone = 0;
        for (uint32_t r = 0; r < p->n_removed; r++)
            gone |= p->removed[r] == t->id;
        if (!gone)
            out[n++] = *t;
    }
    for (uint32_t a = 0; a < p->n_added; a++)
        out[n++] = p->added[a];
    return n;
}

/* Shard prices (edges grouped, rendered together) against each shard rendered by itself: the
 * render before as the target, a full render after as the current images. */
static void shard_prices_are_shards_alone(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 150);
    lm_views *v, *alone;
    assert_int_equal(
        co_simplify_make_views(CO_PRICE_SHARD, r.orig, r.work, &r.vs, "host", NULL, &v), LM_OK);
    assert_int_equal(
        co_simplify_make_views(CO_PRICE_SHARD, r.orig, r.work, &r.vs, "host", NULL, &alone), LM_OK);
    co_eq *q;
    assert_int_equal(co_eq_create(r.vs.count, &q), LM_OK);
    uint32_t(*edges)[2];
    size_t n_edges;
    assert_int_equal(lm_mesh_list_edges(r.work, &edges, &n_edges), LM_OK);
    uint32_t idx[40], n = 40;
    for (uint32_t i = 0; i < n; i++)
        assert_int_equal(co_eq_insert(q, edges[i * 5][0], edges[i * 5][1], 0, &idx[i]), LM_OK);
    free(edges);
    co_cands c;
    co_pricer *p;
    assert_int_equal(co_cands_init(&c), LM_OK);
    assert_int_equal(co_pricer_create(CO_PRICE_SHARD, v, &r.vs, 16, &p), LM_OK);
    assert_int_equal(co_cands_build(&c, r.work, q, &r.vs, r.derived, idx, n), LM_OK);
    assert_int_equal(co_pricer_price(p, &c, q), LM_OK);
    co_pricer_stats ps;
    co_pricer_stats_get(p, &ps);
    assert_true(ps.renders > 1 && ps.renders < n); /* grouped, and more than one group */
    lm_tri_data *after = malloc((c.n_shard + 64) * sizeof *after);
    assert_non_null(after);
    uint32_t positive = 0;
    for (uint32_t i = 0; i < c.n_edges; i++) {
        const co_cand_edge *e = &c.edges[i];
        for (uint32_t k = 0; k < e->n; k++) {
            const lm_patch *pt = &c.patches[e->patch0 + k];
            assert_int_equal(alone->ops->set_mesh(alone, c.shard + e->shard0, e->n_shard), LM_OK);
            assert_int_equal(lm_views_retarget(alone), LM_OK);
            assert_int_equal(alone->ops->set_mesh(alone, after, shard_after(&c, e, pt, after)),
                             LM_OK);
            int64_t energy;
            assert_int_equal(alone->ops->energy(alone, &energy, NULL), LM_OK);
            assert_true(c.delta[e->patch0 + k] == energy);
            positive += energy > 0;
        }
    }
    assert_true(positive > c.n_patches / 2);
    free(after);
    co_pricer_destroy(p);
    co_cands_free(&c);
    co_eq_destroy(q);
    lm_views_destroy(v);
    lm_views_destroy(alone);
    rig_free(&r);
}

static lm_status count_steps(void *ctx, const lm_mesh *m, co_isimp_step *s)
{
    (void)m;
    uint32_t *n = ctx;
    assert_int_equal(s->index, *n);
    (*n)++;
    return LM_OK;
}

static lm_status run_simplifier(rig *r, co_price_method method, lm_views *v, uint32_t target,
                                int verify, int no_footprints, co_isimp_stats *stats)
{
    uint32_t steps = 0;
    co_isimp_config cfg = {.method = method,
                           .target_verts = target,
                           .views = &r->vs,
                           .derived_normals = r->derived,
                           .max_batch = 32,
                           .verify = verify,
                           .unsafe_no_footprints = no_footprints,
                           .on_step = count_steps,
                           .ctx = &steps};
    lm_status st = co_isimp_run(r->work, v, &cfg, stats);
    if (st == LM_OK)
        assert_int_equal(steps, stats->collapses);
    return st;
}

/* verify mode: every entry the queue takes as exact is priced again after every collapse. */
static void lazy_queue_never_uses_a_stale_cost(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 90);
    uint32_t start = r.work->live_verts;
    lm_views *v;
    assert_int_equal(
        co_simplify_make_views(CO_PRICE_IMAGE, r.orig, r.work, &r.vs, "host", NULL, &v), LM_OK);
    co_isimp_stats st;
    uint32_t n = light ? 6 : 12;
    lm_status s = run_simplifier(&r, CO_PRICE_IMAGE, v, start - n, 1, 0, &st);
    if (s)
        fprintf(stderr, "%s\n", lm_last_error());
    assert_int_equal(s, LM_OK);
    assert_int_equal(r.work->live_verts, start - n);
    assert_int_equal(st.collapses, n);
    assert_true(st.marked_stale > 0 && st.stale_pops > 0);
    /* the views followed every collapse exactly */
    int64_t e;
    assert_int_equal(v->ops->energy(v, &e, NULL), LM_OK);
    assert_true(e == full_energy(r.orig, r.work, &r.vs));
    lm_views_destroy(v);
    rig_free(&r);
}

/* Without the footprint test the verifier finds an entry whose price went stale. */
static void verify_catches_missing_footprints(void **state)
{
    (void)state;
    rig r;
    rig_init(&r, 90);
    lm_views *v;
    assert_int_equal(
        co_simplify_make_views(CO_PRICE_IMAGE, r.orig, r.work, &r.vs, "host", NULL, &v), LM_OK);
    co_isimp_stats st;
    lm_status s = run_simplifier(&r, CO_PRICE_IMAGE, v, r.work->live_verts - 30, 1, 1, &st);
    assert_int_equal(s, LM_E_INTERNAL);
    assert_non_null(strstr(lm_last_error(), "kept as exact"));
    lm_clear_error();
    lm_views_destroy(v);
    rig_free(&r);
}

static uint64_t simplified_hash(co_views_kind kind, co_pool *pool, uint32_t target)
{
    rig r;
    rig_init(&r, light ? 160 : 200);
    co_views_desc d = {.kind = kind,
                       .original = r.orig,
                       .views = &r.vs,
                       .materials = r.work->materials,
                       .n_materials = r.work->n_materials,
                       .mesh = r.work,
                       .device = "host",
                       .split = 3,
                       .pool = pool};
    lm_views *v;
    assert_int_equal(co_views_create(&d, &v), LM_OK);
    co_isimp_stats st;
    assert_int_equal(run_simplifier(&r, CO_PRICE_IMAGE, v, target, 0, 0, &st), LM_OK);
    assert_int_equal(r.work->live_verts, target);
    uint64_t h = lm_mesh_hash(r.work);
    lm_views_destroy(v);
    rig_free(&r);
    return h;
}

/* The same collapses in process, split over 3 backends and through 2 worker processes. */
static void same_result_for_any_views(void **state)
{
    (void)state;
    uint32_t target = light ? 140 : 120;
    uint64_t one = simplified_hash(CO_VIEWS_LOCAL, NULL, target);
    assert_true(one == simplified_hash(CO_VIEWS_SPLIT, NULL, target));
    co_pool *pool;
    co_simplify_workers w = {.local = 2};
    assert_int_equal(co_simplify_pool_start(&w, "host", &pool), LM_OK);
    assert_true(one == simplified_hash(CO_VIEWS_REMOTE, pool, target));
    co_pool_destroy(pool);
}

int main(void)
{
    if (!lmt_spider_path()) {
        fprintf(stderr, "test_isimp: spider.obj missing (scripts/install-deps.sh)\n");
        return 77;
    }
    const char *l = getenv("LUMESH_TEST_LIGHT");
    light = l && !strcmp(l, "1");
    if (light) {
        size = 48;
        n_views = 6;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(collapse_costs_equal_full_renders),
        cmocka_unit_test(lazy_queue_never_uses_a_stale_cost),
        cmocka_unit_test(verify_catches_missing_footprints),
        cmocka_unit_test(same_result_for_any_views),
        cmocka_unit_test(shard_prices_are_shards_alone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
