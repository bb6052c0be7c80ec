/* tests/unit/test_views_remote.c — views served by real lumesh-worker processes (spawned by the
 * pool over a private ipc socket) are bit-identical to one in-process backend: energies, ΔE of a
 * batch of moves, potentials, images, before and after commits and a change of materials, for
 * 1..3 workers over 20 views and for 3 workers over 2 views (replicas dividing the batch). The
 * geometric term priced by the workers (each group of views its share of the triangles) gives
 * the bits the coordinator's own pricing gives, also after commits and a change of weight. A job
 * pins its renderer: a worker of another renderer is refused with the reason. */
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "common/optimizer/surface_term.h"
#include "common/patch.h"
#include "coordinator/cli/bench_moves.h"
#include "coordinator/pool/pool.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/views/views.h"
#include "test_support.h"

#define SIZE 64
#define N_PATCHES 24

typedef struct rig {
    lm_mesh *orig, *coarse;
    lm_view_set vs;
    co_pool *pool;
    lm_views *one, *remote;
} rig;

static void rig_init(rig *r, const char *path, uint32_t views, uint32_t workers)
{
    memset(r, 0, sizeof *r);
    assert_int_equal(lm_mesh_load(path, NULL, &r->orig), LM_OK);
    uint32_t target = r->orig->live_verts / 100 > 60 ? r->orig->live_verts / 100 : 60;
    lm_status st = co_simplify(r->orig, CO_SIMPLIFY_QEM, target, &r->coarse);
    assert_true(st == LM_OK || (st == LM_E_RANGE && r->coarse));
    assert_int_equal(lm_mesh_build_adjacency(r->coarse), LM_OK);
    float c[3], rad;
    lm_mesh_bounding_sphere(r->orig, c, &rad);
    assert_int_equal(lm_view_set_make(&r->vs, views, SIZE, c, rad), LM_OK);
    co_pool_options po = {.local_workers = workers, .device = "host", .quiet = 1};
    assert_int_equal(co_pool_create(&po, &r->pool), LM_OK);
    assert_int_equal(co_pool_wait(r->pool, workers, 60), LM_OK);
    co_views_desc d = {.original = r->orig,
                       .views = &r->vs,
                       .materials = r->coarse->materials,
                       .n_materials = r->coarse->n_materials,
                       .mesh = r->coarse,
                       .device = "host"};
    assert_int_equal(co_views_create(&d, &r->one), LM_OK);
    d.kind = CO_VIEWS_REMOTE;
    d.pool = r->pool;
    assert_int_equal(co_views_create(&d, &r->remote), LM_OK);
}

static void rig_free(rig *r)
{
    lm_views_destroy(r->one);
    lm_views_destroy(r->remote);
    co_pool_destroy(r->pool);
    lm_mesh_destroy(r->orig);
    lm_mesh_destroy(r->coarse);
}

static void same_energies(rig *r)
{
    int64_t e1, e2, v1[LM_MAX_VIEWS], v2[LM_MAX_VIEWS];
    assert_int_equal(r->one->ops->energy(r->one, &e1, v1), LM_OK);
    assert_int_equal(r->remote->ops->energy(r->remote, &e2, v2), LM_OK);
    assert_true(e1 > 0 && e1 == e2);
    assert_memory_equal(v1, v2, r->vs.count * sizeof *v1);
}

static void same_deltas(rig *r, const lm_patch *p, uint32_t n)
{
    int64_t d1[N_PATCHES], d2[N_PATCHES];
    assert_int_equal(r->one->ops->evaluate(r->one, p, n, d1), LM_OK);
    assert_int_equal(r->remote->ops->evaluate(r->remote, p, n, d2), LM_OK);
    int seen = 0;
    for (uint32_t i = 0; i < n; i++) {
        assert_true(d1[i] == d2[i]);
        seen += d1[i] != 0;
    }
    assert_true(seen > 0);
}

static void same_images(rig *r)
{
    static uint8_t a[SIZE * SIZE * 4], b[SIZE * SIZE * 4];
    lm_image_kind kinds[] = {LM_IMAGE_TARGET_LUMA, LM_IMAGE_CURRENT_LUMA, LM_IMAGE_RGBA};
    for (uint32_t h = 0; h < r->vs.count; h += 3)
        for (int k = 0; k < 3; k++) {
            assert_int_equal(r->one->ops->read_image(r->one, kinds[k], h, a), LM_OK);
            assert_int_equal(r->remote->ops->read_image(r->remote, kinds[k], h, b), LM_OK);
            assert_memory_equal(a, b, SIZE * SIZE * lm_image_kind_bpp(kinds[k]));
        }
}

static void same_potentials(rig *r)
{
    float pts[32][3];
    int64_t o1[32], o2[32];
    for (int i = 0; i < 32; i++)
        memcpy(pts[i], r->coarse->pos[(uint32_t)i * 5 % r->coarse->n_verts], sizeof pts[i]);
    assert_int_equal(r->one->ops->potentials(r->one, (const float(*)[3])pts, 32, o1), LM_OK);
    assert_int_equal(r->remote->ops->potentials(r->remote, (const float(*)[3])pts, 32, o2), LM_OK);
    assert_memory_equal(o1, o2, sizeof o1);
}

static void check_remote(const char *path, uint32_t views, uint32_t workers)
{
    rig r;
    rig_init(&r, path, views, workers);
    lm_views_info info;
    r.remote->ops->info(r.remote, &info);
    assert_int_equal(info.n_views, views);
    assert_true(info.seq == 2);
    same_energies(&r);
    same_images(&r);
    lm_patch p[N_PATCHES];
    for (int i = 0; i < N_PATCHES; i++)
        lm_patch_init(&p[i]);
    assert_int_equal(co_bench_vertex_moves(r.coarse, 3 + workers, p, N_PATCHES), LM_OK);
    same_deltas(&r, p, N_PATCHES);
    same_potentials(&r);
    for (int i = 0; i < 3; i++) {
        assert_int_equal(r.one->ops->commit(r.one, &p[i * 7]), LM_OK);
        assert_int_equal(r.remote->ops->commit(r.remote, &p[i * 7]), LM_OK);
    }
    same_energies(&r);
    same_images(&r);
    same_deltas(&r, p + 1, 5);
    assert_int_equal(r.one->ops->set_materials(r.one, r.orig->materials, r.orig->n_materials),
                     LM_OK);
    assert_int_equal(r.remote->ops->set_materials(r.remote, r.orig->materials, r.orig->n_materials),
                     LM_OK);
    same_energies(&r);
    for (int i = 0; i < N_PATCHES; i++)
        lm_patch_free(&p[i]);
    rig_free(&r);
}

/* The geometric term over both: priced here over the in-process views, by the workers over the
 * remote ones; the same ΔE for every patch, before and after commits and a new weight. */
static void check_surface(const char *path, uint32_t views, uint32_t workers)
{
    rig r;
    rig_init(&r, path, views, workers);
    lm_views *g1 = NULL, *g2 = NULL;
    assert_int_equal(lm_surface_views_create(r.one, r.orig, 3.0, &g1), LM_OK);
    assert_int_equal(lm_surface_views_create(r.remote, r.orig, 3.0, &g2), LM_OK);
    assert_false(lm_surface_views_offloaded(g1));
    assert_true(lm_surface_views_offloaded(g2));
    assert_int_equal(lm_views_set_mesh_from(g1, r.coarse), LM_OK);
    assert_int_equal(lm_views_set_mesh_from(g2, r.coarse), LM_OK);
    lm_patch p[N_PATCHES];
    for (int i = 0; i < N_PATCHES; i++)
        lm_patch_init(&p[i]);
    assert_int_equal(co_bench_vertex_moves(r.coarse, 11 + workers, p, N_PATCHES), LM_OK);
    int64_t d1[N_PATCHES], d2[N_PATCHES], d3[N_PATCHES], img[N_PATCHES];
    for (int round = 0; round < 3; round++) {
        assert_int_equal(g1->ops->evaluate(g1, p, N_PATCHES, d1), LM_OK);
        lm_surface_views_set_pricing(g2, LM_SURFACE_WORKERS);
        assert_int_equal(g2->ops->evaluate(g2, p, N_PATCHES, d2), LM_OK);
        lm_surface_views_set_pricing(g2, LM_SURFACE_HERE);
        assert_int_equal(g2->ops->evaluate(g2, p, N_PATCHES, d3), LM_OK);
        assert_memory_equal(d2, d3, sizeof d2);
        assert_int_equal(r.one->ops->evaluate(r.one, p, N_PATCHES, img), LM_OK);
        int geo = 0;
        for (int i = 0; i < N_PATCHES; i++) {
            assert_true(d1[i] == d2[i]);
            geo += d1[i] != img[i]; /* the term took part */
        }
        assert_true(geo > N_PATCHES / 2);
        int64_t e1, e2;
        assert_int_equal(g1->ops->energy(g1, &e1, NULL), LM_OK);
        assert_int_equal(g2->ops->energy(g2, &e2, NULL), LM_OK);
        assert_true(e1 == e2 && lm_surface_views_energy(g1) == lm_surface_views_energy(g2));
        if (round == 0) { /* commits: both tables follow */
            for (int i = 0; i < 3; i++) {
                assert_int_equal(g1->ops->commit(g1, &p[i * 5]), LM_OK);
                assert_int_equal(g2->ops->commit(g2, &p[i * 5]), LM_OK);
            }
        } else if (round == 1) { /* a new weight reaches the workers */
            assert_int_equal(lm_surface_views_set_weight(g1, 40.0), LM_OK);
            assert_int_equal(lm_surface_views_set_weight(g2, 40.0), LM_OK);
        }
    }
    assert_true(lm_surface_views_worker_share(g2) == 0.5);
    for (int i = 0; i < N_PATCHES; i++)
        lm_patch_free(&p[i]);
    lm_views_destroy(g1);
    lm_views_destroy(g2);
    rig_free(&r);
}

static void test_remote_surface_term(void **state)
{
    (void)state;
    const char *bunny = lmt_bunny_path();
    if (!bunny)
        skip();
    for (uint32_t w = 1; w <= 3; w++)
        check_surface(bunny, 20, w);
    check_surface(bunny, 2, 3); /* replicas: each range's share priced once */
}

static void test_remote_bunny(void **state)
{
    (void)state;
    const char *bunny = lmt_bunny_path();
    if (!bunny)
        skip();
    for (uint32_t w = 1; w <= 3; w++)
        check_remote(bunny, 20, w);
    check_remote(bunny, 2, 3); /* more workers than views: replicas */
}

static void test_remote_spider(void **state)
{
    (void)state;
    const char *spider = lmt_spider_path();
    if (!spider)
        skip();
    check_remote(spider, 20, 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_remote_bunny),
        cmocka_unit_test(test_remote_spider),
        cmocka_unit_test(test_remote_surface_term),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
