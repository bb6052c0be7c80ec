/* tests/unit/test_surface_table.c — the geometric term's table (common/surface_table.h) in
 * shares: for 1..5 shares, the tables of shares 0..n-1 together give exactly the ΔE_geo of every
 * patch and the E_geo of one whole table, before and after commits and a new scale; a table
 * holds and prices only its share's ids; a triangle whose corners did not move costs no change;
 * bad shares and scales are refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "common/patch.h"
#include "common/surface_table.h"
#include "test_support.h"

#define MAX_SHARES 5
#define N_PATCHES 40

typedef struct rig {
    lm_mesh *surface, *coarse;
    lm_bvh *bvh;
    lm_tri_data *tris;
    size_t n;
} rig;

static void rig_init(rig *r)
{
    memset(r, 0, sizeof *r);
    r->surface = lmt_make_sphere(4);
    r->coarse = lmt_make_sphere(2);
    for (uint32_t v = 0; v < r->coarse->n_verts; v++) /* off the surface, by 5 to 10% */
        for (int i = 0; i < 3; i++)
            r->coarse->pos[v][i] *= 1.05f + 0.05f * (float)(v % 3) / 2.0f;
    assert_int_equal(lm_bvh_create(r->surface, &r->bvh), LM_OK);
    assert_int_equal(lm_mesh_export_tris(r->coarse, &r->tris, &r->n), LM_OK);
    assert_true(r->n > 100);
}

static void rig_free(rig *r)
{
    free(r->tris);
    lm_bvh_destroy(r->bvh);
    lm_mesh_destroy(r->surface);
    lm_mesh_destroy(r->coarse);
}

/* A random patch: a few triangles removed and added again with moved corners (some with the same
 * corners: no change), and one triangle under a new id. */
static void random_patch(const rig *r, uint64_t *rng, uint32_t new_id, lm_patch *p)
{
    lm_patch_reset(p);
    uint32_t first = (uint32_t)(lmt_urand(rng) * (double)(r->n - 8));
    for (uint32_t k = 0; k < 6; k++) {
        lm_tri_data t = r->tris[first + k];
        assert_int_equal(lm_patch_remove(p, t.id), LM_OK);
        if (k % 3)
            for (int v = 0; v < 3; v++)
                for (int i = 0; i < 3; i++)
                    t.c[v].pos[i] += (float)(0.05 * (lmt_urand(rng) - 0.5));
        assert_int_equal(lm_patch_add(p, &t), LM_OK);
    }
    lm_tri_data extra = r->tris[first];
    extra.id = new_id;
    extra.c[0].pos[0] += 0.1f;
    assert_int_equal(lm_patch_add(p, &extra), LM_OK);
}

static void make_tables(const rig *r, uint32_t shares, double k, lm_surface_table **whole,
                        lm_surface_table **part)
{
    assert_int_equal(lm_surface_table_create(r->bvh, k, 0, 1, whole), LM_OK);
    assert_int_equal(lm_surface_table_set_mesh(*whole, r->tris, r->n), LM_OK);
    for (uint32_t s = 0; s < shares; s++) {
        assert_int_equal(lm_surface_table_create(r->bvh, k, s, shares, &part[s]), LM_OK);
        assert_int_equal(lm_surface_table_set_mesh(part[s], r->tris, r->n), LM_OK);
    }
}

static void same_totals(lm_surface_table *whole, lm_surface_table **part, uint32_t shares)
{
    int64_t sum = 0;
    for (uint32_t s = 0; s < shares; s++) {
        sum += lm_surface_table_total(part[s]);
        if (shares > 1) /* every share holds some of the sphere */
            assert_true(lm_surface_table_total(part[s]) > 0);
    }
    assert_true(sum == lm_surface_table_total(whole) && sum > 0);
}

static void check_shares(uint32_t shares)
{
    rig r;
    rig_init(&r);
    lm_surface_table *whole = NULL, *part[MAX_SHARES] = {NULL};
    make_tables(&r, shares, 1.0e7, &whole, part);
    same_totals(whole, part, shares);
    uint64_t rng = 0x9E3779B97F4A7C15ull + shares;
    lm_patch p;
    lm_patch_init(&p);
    for (int i = 0; i < N_PATCHES; i++) {
        random_patch(&r, &rng, (uint32_t)(r.n + (size_t)i), &p);
        int64_t want = lm_surface_table_delta(whole, &p), got = 0;
        for (uint32_t s = 0; s < shares; s++)
            got += lm_surface_table_delta(part[s], &p);
        assert_true(want == got && want != 0);
        if (i % 4 == 0) { /* commit it everywhere: the totals follow the delta */
            int64_t before = lm_surface_table_total(whole);
            assert_int_equal(lm_surface_table_commit(whole, &p), LM_OK);
            assert_true(lm_surface_table_total(whole) == before + want);
            for (uint32_t s = 0; s < shares; s++)
                assert_int_equal(lm_surface_table_commit(part[s], &p), LM_OK);
            same_totals(whole, part, shares);
        }
        if (i == N_PATCHES / 2) {
            lm_surface_table_set_k(whole, 3.25e6);
            for (uint32_t s = 0; s < shares; s++)
                lm_surface_table_set_k(part[s], 3.25e6);
            same_totals(whole, part, shares);
        }
    }
    lm_patch_free(&p);
    lm_surface_table_destroy(whole);
    for (uint32_t s = 0; s < shares; s++)
        lm_surface_table_destroy(part[s]);
    rig_free(&r);
}

static void test_shares_add_up(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= MAX_SHARES; n++)
        check_shares(n);
}

/* A share prices its own ids only, and a triangle put back where it was costs nothing. */
static void test_share_is_own(void **state)
{
    (void)state;
    rig r;
    rig_init(&r);
    lm_surface_table *t = NULL;
    assert_int_equal(lm_surface_table_create(r.bvh, 1.0e7, 1, 3, &t), LM_OK);
    assert_int_equal(lm_surface_table_set_mesh(t, r.tris, r.n), LM_OK);
    lm_patch p;
    lm_patch_init(&p);
    for (size_t i = 0; i < 9; i++) {
        lm_tri_data d = r.tris[i];
        lm_patch_reset(&p);
        assert_int_equal(lm_patch_remove(&p, d.id), LM_OK);
        assert_int_equal(lm_patch_add(&p, &d), LM_OK);
        assert_true(lm_surface_table_delta(t, &p) == 0); /* unmoved */
        d.c[1].pos[2] += 0.2f;
        lm_patch_reset(&p);
        assert_int_equal(lm_patch_remove(&p, d.id), LM_OK);
        assert_int_equal(lm_patch_add(&p, &d), LM_OK);
        int64_t dd = lm_surface_table_delta(t, &p);
        assert_true(d.id % 3 == 1 ? dd != 0 : dd == 0);
    }
    lm_patch_free(&p);
    lm_surface_table_destroy(t);
    rig_free(&r);
}

static void test_refused(void **state)
{
    (void)state;
    rig r;
    rig_init(&r);
    lm_surface_table *t = (lm_surface_table *)1;
    assert_int_equal(lm_surface_table_create(r.bvh, 1.0, 2, 2, &t), LM_E_INVALID);
    assert_null(t);
    assert_int_equal(lm_surface_table_create(r.bvh, 1.0, 0, 0, &t), LM_E_INVALID);
    assert_int_equal(lm_surface_table_create(r.bvh, 0.0, 0, 1, &t), LM_E_INVALID);
    assert_int_equal(lm_surface_table_create(r.bvh, NAN, 0, 1, &t), LM_E_INVALID);
    assert_int_equal(lm_surface_table_create(r.bvh, INFINITY, 0, 1, &t), LM_E_INVALID);
    assert_int_equal(lm_surface_table_create(NULL, 1.0, 0, 1, &t), LM_E_INVALID);
    lm_surface_table_destroy(NULL);
    rig_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shares_add_up),
        cmocka_unit_test(test_share_is_own),
        cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
