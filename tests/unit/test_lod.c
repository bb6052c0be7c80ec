/* tests/unit/test_lod.c — level-of-detail chains: the levels nest (without optimisation each
 * level is exactly the image-driven simplification of the level before it, against the
 * original's images; with it, vertex counts fall level by level and every level keeps every part
 * by name), and the one-file GLB holds them all under MSFT_lod with LOD0 what readers load.
 * LUMESH_TEST_LIGHT=1 (the sanitizer stage; the release stage runs it whole): 4 views of 32
 * pixels instead of 6 of 48, levels 85%,75%,65% instead of 70%,55%,45%, 500 evaluations of
 * optimisation per level instead of 1500; every assertion the same. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "coordinator/quality/view_setup.h"
#include "coordinator/simplify/isimp.h"
#include "coordinator/simplify/lod.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/simplify/work.h"
#include "test_support.h"

static int light; /* LUMESH_TEST_LIGHT=1 */
static uint32_t n_views = 6;
static int size = 48;
static uint64_t evals = 1500;
static const char *levels = "70%,55%,45%";
static double fraction[3] = {0.7, 0.55, 0.45};
static char *dir, input[600]; /* the spider cut by QEM to 250 vertices, as a GLB (textures kept) */

static int make_input(void **state)
{
    (void)state;
    dir = lmt_mkdtemp();
    snprintf(input, sizeof input, "%s/spider250.glb", dir);
    lm_mesh *orig, *m;
    assert_int_equal(lm_mesh_load(lmt_spider_path(), NULL, &orig), LM_OK);
    lm_status st = co_simplify(orig, CO_SIMPLIFY_QEM, 250, &m);
    assert_true(st == LM_OK || (st == LM_E_RANGE && m));
    lm_clear_error();
    assert_int_equal(lm_mesh_save(input, m), LM_OK);
    lm_mesh_destroy(m);
    lm_mesh_destroy(orig);
    return 0;
}

static int remove_input(void **state)
{
    (void)state;
    lmt_rmdir(dir);
    return 0;
}

static void options(co_lod_options *o, int optimize)
{
    memset(o, 0, sizeof *o);
    o->input_path = input;
    assert_int_equal(co_lod_parse_levels(levels, o), LM_OK);
    o->views.count = n_views;
    o->size = size;
    o->device = "host";
    o->no_optimize = !optimize;
    o->evals = evals;
}

static uint64_t hash_of(const lm_mesh *m)
{
    lm_mesh *c;
    assert_int_equal(co_simplify_output_copy(m, &c), LM_OK);
    uint64_t h = lm_mesh_hash(c);
    lm_mesh_destroy(c);
    return h;
}

/* prev simplified to target by image-driven collapses against orig's images. */
static uint64_t simplified_hash(const lm_mesh *orig, const lm_mesh *prev, uint32_t target)
{
    lm_mesh *m;
    lm_view_set *vs;
    lm_views *v;
    int derived;
    assert_int_equal(lm_mesh_clone(prev, &m), LM_OK);
    assert_int_equal(co_simplify_prepare(m, &derived), LM_OK);
    assert_int_equal(co_view_set_around(orig, n_views, size, 0, &vs), LM_OK);
    assert_int_equal(co_simplify_make_views(CO_PRICE_IMAGE, orig, m, vs, "host", NULL, &v), LM_OK);
    co_isimp_config cfg = {.target_verts = target, .views = vs, .derived_normals = derived};
    co_isimp_stats s;
    assert_int_equal(co_isimp_run(m, v, &cfg, &s), LM_OK);
    uint64_t h = hash_of(m);
    lm_views_destroy(v);
    free(vs);
    lm_mesh_destroy(m);
    return h;
}

static void levels_nest(void **state)
{
    (void)state;
    co_lod_options o;
    options(&o, 0);
    co_lod_summary sum;
    lm_mesh *lv[LM_MESH_MAX_LODS];
    assert_int_equal(co_lod_build(&o, &sum, lv), LM_OK);
    lm_mesh *orig;
    assert_int_equal(lm_mesh_load(o.input_path, NULL, &orig), LM_OK);
    uint32_t want[3] = {(uint32_t)(fraction[0] * orig->live_verts + 0.5),
                        (uint32_t)(fraction[1] * orig->live_verts + 0.5),
                        (uint32_t)(fraction[2] * orig->live_verts + 0.5)};
    for (uint32_t k = 0; k < 3; k++) {
        assert_int_equal(lv[k]->live_verts, want[k]);
        assert_true(hash_of(lv[k]) == simplified_hash(orig, k ? lv[k - 1] : orig, want[k]));
    }
    for (uint32_t k = 0; k < 3; k++)
        lm_mesh_destroy(lv[k]);
    lm_mesh_destroy(orig);
}

/* Every part of the original, by name, in every level. */
static void same_parts(const lm_mesh *orig, const lm_mesh *m)
{
    assert_int_equal(lm_mesh_count_parts(m), lm_mesh_count_parts(orig));
    for (uint32_t t = 0; t < orig->n_tris; t++)
        if (orig->tri_alive[t])
            assert_int_not_equal(lm_mesh_find_part(m, lm_mesh_part_name(orig, t)), LM_NONE);
}

static void optimised_chain_and_glb(void **state)
{
    (void)state;
    co_lod_options o;
    options(&o, 1);
    co_lod_summary sum;
    lm_mesh *lv[LM_MESH_MAX_LODS];
    assert_int_equal(co_lod_build(&o, &sum, lv), LM_OK);
    lm_mesh *orig, *back;
    assert_int_equal(lm_mesh_load(o.input_path, NULL, &orig), LM_OK);
    for (uint32_t k = 0; k < 3; k++) {
        assert_true(lv[k]->live_verts <= sum.level[k].target);
        assert_true(k == 0 || lv[k]->live_verts < lv[k - 1]->live_verts);
        assert_true(sum.level[k].optimize_evals >= evals);
        assert_true(sum.level[k].energy_optimized <= sum.level[k].energy_simplified);
        same_parts(orig, lv[k]);
    }
    char path[700];
    snprintf(path, sizeof path, "%s/chain.glb", dir);
    float cov[3] = {0.5f, 0.25f, 0.125f};
    assert_int_equal(lm_mesh_save_glb_lods(path, (const lm_mesh *const *)lv, 3, cov), LM_OK);
    assert_int_equal(lm_mesh_load(path, NULL, &back), LM_OK);
    assert_int_equal(back->live_verts, lv[0]->live_verts);
    assert_int_equal(back->live_tris, lv[0]->live_tris);
    same_parts(orig, back);
    lm_mesh_destroy(back);
    for (uint32_t k = 0; k < 3; k++)
        lm_mesh_destroy(lv[k]);
    lm_mesh_destroy(orig);
}

static void level_lists(void **state)
{
    (void)state;
    co_lod_options o = {0};
    assert_int_equal(co_lod_parse_levels("50%,25%,100", &o), LM_OK);
    assert_int_equal(o.n_levels, 3);
    assert_true(o.levels[0].fraction == 0.5 && o.levels[2].verts == 100);
    const char *bad[] = {"", "50%,,10%", "0%", "101%", "3", "x", "50%x", "2.5"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
        assert_int_equal(co_lod_parse_levels(bad[i], &o), LM_E_INVALID);
    char buf[64];
    co_lod_level_path("out/frog.glb", 2, buf, sizeof buf);
    assert_string_equal(buf, "out/frog.lod2.glb");
    co_lod_level_path("a.b/frog", 0, buf, sizeof buf);
    assert_string_equal(buf, "a.b/frog.lod0");
    lm_clear_error();
}

int main(void)
{
    if (!lmt_spider_path()) {
        fprintf(stderr, "test_lod: spider.obj missing (scripts/install-deps.sh)\n");
        return 77;
    }
    const char *l = getenv("LUMESH_TEST_LIGHT");
    light = l && !strcmp(l, "1");
    if (light) {
        n_views = 4;
        size = 32;
        evals = 500;
        levels = "85%,75%,65%";
        fraction[0] = 0.85;
        fraction[1] = 0.75;
        fraction[2] = 0.65;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(level_lists),
        cmocka_unit_test(levels_nest),
        cmocka_unit_test(optimised_chain_and_glb),
    };
    return cmocka_run_group_tests(tests, make_input, remove_input);
}
