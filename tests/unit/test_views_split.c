/* tests/unit/test_views_split.c — the split backend is bit-identical to a single backend: for
 * k = 1..4 children over the 20 views of the coarse bunny and the coarse textured spider, every
 * energy (total and per view), every ΔE of a batch of vertex moves, the oracle's potentials and
 * every image agree exactly with one local backend over all views, before and after commits and a
 * change of materials; on llvmpipe (host) and on lumesh's CPU rasteriser (cpu). Also: the one
 * constructor refuses bad descriptions with a message. */
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "common/patch.h"
#include "coordinator/cli/bench_moves.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/views/views.h"
#include "test_support.h"

#define N_VIEWS 20
#define SIZE 64
#define N_PATCHES 48

typedef struct pair {
    lm_mesh *orig, *coarse;
    lm_view_set vs;
    lm_views *one, *split;
} pair;

static void load_pair(pair *p, const char *path)
{
    memset(p, 0, sizeof *p);
    assert_int_equal(lm_mesh_load(path, NULL, &p->orig), LM_OK);
    uint32_t target = p->orig->live_verts / 100 > 60 ? p->orig->live_verts / 100 : 60;
    lm_status st = co_simplify(p->orig, CO_SIMPLIFY_QEM, target, &p->coarse);
    assert_true(st == LM_OK || (st == LM_E_RANGE && p->coarse));
    assert_int_equal(lm_mesh_build_adjacency(p->coarse), LM_OK);
    float c[3], r;
    lm_mesh_bounding_sphere(p->orig, c, &r);
    assert_int_equal(lm_view_set_make(&p->vs, N_VIEWS, SIZE, c, r), LM_OK);
}

static void make_views(pair *p, uint32_t k, const char *device)
{
    co_views_desc d = {.original = p->orig,
                       .views = &p->vs,
                       .materials = p->coarse->materials,
                       .n_materials = p->coarse->n_materials,
                       .mesh = p->coarse,
                       .device = device};
    assert_int_equal(co_views_create(&d, &p->one), LM_OK);
    d.kind = CO_VIEWS_SPLIT;
    d.split = k;
    assert_int_equal(co_views_create(&d, &p->split), LM_OK);
}

static void same_energies(pair *p)
{
    int64_t e1, e2, v1[N_VIEWS], v2[N_VIEWS];
    assert_int_equal(p->one->ops->energy(p->one, &e1, v1), LM_OK);
    assert_int_equal(p->split->ops->energy(p->split, &e2, v2), LM_OK);
    assert_true(e1 > 0);
    assert_true(e1 == e2);
    assert_memory_equal(v1, v2, sizeof v1);
}

static void same_deltas(pair *p, const lm_patch *patches, uint32_t n)
{
    int64_t d1[N_PATCHES], d2[N_PATCHES];
    assert_int_equal(p->one->ops->evaluate(p->one, patches, n, d1), LM_OK);
    assert_int_equal(p->split->ops->evaluate(p->split, patches, n, d2), LM_OK);
    int nonzero = 0;
    for (uint32_t i = 0; i < n; i++) {
        assert_true(d1[i] == d2[i]);
        nonzero += d1[i] != 0;
    }
    assert_true(nonzero > (int)n / 2); /* the moves are seen */
}

static void same_images(pair *p)
{
    uint8_t a[SIZE * SIZE * 4], b[SIZE * SIZE * 4];
    lm_image_kind kinds[] = {LM_IMAGE_TARGET_LUMA, LM_IMAGE_CURRENT_LUMA, LM_IMAGE_RGBA};
    for (uint32_t h = 0; h < N_VIEWS; h++)
        for (int k = 0; k < 3; k++) {
            size_t bytes = SIZE * SIZE * lm_image_kind_bpp(kinds[k]);
            assert_int_equal(p->one->ops->read_image(p->one, kinds[k], h, a), LM_OK);
            assert_int_equal(p->split->ops->read_image(p->split, kinds[k], h, b), LM_OK);
            assert_memory_equal(a, b, bytes);
        }
    assert_int_equal(p->split->ops->read_image(p->split, LM_IMAGE_RGBA, N_VIEWS, a), LM_E_RANGE);
}

static void same_potentials(pair *p)
{
    float pts[64][3];
    int64_t o1[64], o2[64];
    for (int i = 0; i < 64; i++)
        memcpy(pts[i], p->coarse->pos[(uint32_t)i * 7 % p->coarse->n_verts], sizeof pts[i]);
    assert_int_equal(p->one->ops->potentials(p->one, (const float(*)[3])pts, 64, o1), LM_OK);
    assert_int_equal(p->split->ops->potentials(p->split, (const float(*)[3])pts, 64, o2), LM_OK);
    assert_memory_equal(o1, o2, sizeof o1);
}

static void same_info(pair *p, uint64_t seq)
{
    lm_views_info i1, i2;
    p->one->ops->info(p->one, &i1);
    p->split->ops->info(p->split, &i2);
    assert_int_equal(i2.n_views, N_VIEWS);
    assert_int_equal(i1.width, i2.width);
    assert_string_equal(i1.renderer, i2.renderer);
    assert_true(i1.seq == seq && i2.seq == seq);
}

static void check_split(const char *path, uint32_t k, const char *device)
{
    pair p;
    load_pair(&p, path);
    make_views(&p, k, device);
    same_info(&p, 2); /* materials, mesh */
    same_energies(&p);
    same_images(&p);
    lm_patch patches[N_PATCHES];
    for (int i = 0; i < N_PATCHES; i++)
        lm_patch_init(&patches[i]);
    assert_int_equal(co_bench_vertex_moves(p.coarse, 7 + k, patches, N_PATCHES), LM_OK);
    same_deltas(&p, patches, N_PATCHES);
    same_potentials(&p);
    /* after commits (each patch moves a different random vertex: apply a few far-apart ones) */
    for (int i = 0; i < 4; i++) {
        assert_int_equal(p.one->ops->commit(p.one, &patches[i * 11]), LM_OK);
        assert_int_equal(p.split->ops->commit(p.split, &patches[i * 11]), LM_OK);
    }
    same_info(&p, 6);
    same_energies(&p);
    same_images(&p);
    same_deltas(&p, patches + 1, 10);
    /* a change of materials re-renders both alike */
    assert_int_equal(p.one->ops->set_materials(p.one, p.orig->materials, p.orig->n_materials),
                     LM_OK);
    assert_int_equal(p.split->ops->set_materials(p.split, p.orig->materials, p.orig->n_materials),
                     LM_OK);
    same_energies(&p);
    for (int i = 0; i < N_PATCHES; i++)
        lm_patch_free(&patches[i]);
    lm_views_destroy(p.one);
    lm_views_destroy(p.split);
    lm_mesh_destroy(p.orig);
    lm_mesh_destroy(p.coarse);
}

static void test_split_bunny(void **state)
{
    (void)state;
    const char *bunny = lmt_bunny_path();
    if (!bunny)
        skip();
    for (uint32_t k = 1; k <= 4; k++)
        check_split(bunny, k, "host");
}

static void test_split_spider(void **state)
{
    (void)state;
    const char *spider = lmt_spider_path();
    if (!spider)
        skip();
    for (uint32_t k = 1; k <= 4; k++)
        check_split(spider, k, "host");
}

static void test_split_cpu(void **state)
{
    (void)state;
    const char *bunny = lmt_bunny_path(), *spider = lmt_spider_path();
    if (!bunny || !spider)
        skip();
    check_split(bunny, 2, "cpu");
    check_split(spider, 3, "cpu");
}

static void test_desc_refused(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2);
    lm_view_set vs;
    float c[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(&vs, 4, 32, c, 1.0f), LM_OK);
    lm_views *v = (lm_views *)&vs; /* must come back NULL */
    co_views_desc none = {.views = &vs};
    assert_int_equal(co_views_create(&none, &v), LM_E_INVALID);
    assert_null(v);
    assert_true(strstr(lm_last_error(), "original") != NULL);
    co_views_desc range = {.original = m, .views = &vs, .first = 2, .count = 3, .device = "host"};
    assert_int_equal(co_views_create(&range, &v), LM_E_RANGE);
    assert_true(strstr(lm_last_error(), "outside the 4 views") != NULL);
    co_views_desc ok = {.original = m, .views = &vs, .first = 1, .device = "host"};
    assert_int_equal(co_views_create(&ok, &v), LM_OK);
    lm_views_info info;
    v->ops->info(v, &info);
    assert_int_equal(info.n_views, 3);
    lm_views_destroy(v);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_split_bunny),
        cmocka_unit_test(test_split_spider),
        cmocka_unit_test(test_split_cpu),
        cmocka_unit_test(test_desc_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
