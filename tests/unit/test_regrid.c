/* tests/unit/test_regrid.c — the training views' moving pixel grid (`optimize --regrid-every`):
 * lm_view_shift moves a view's picture by exactly the pixels asked, the camera and depths staying
 * put; the offsets of each draw are under half a pixel, (0, 0) for draw 0, a function of (seed,
 * draw, view) alone, spread over the pixel within a few draws; draws start at multiples of N. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "common/view.h"
#include "coordinator/job/regrid.h"
#include "test_support.h"

static lm_view_set *make_set(void)
{
    lm_view_set *vs = malloc(sizeof *vs);
    assert_non_null(vs);
    const float c[3] = {0.1f, -0.2f, 0.3f};
    assert_int_equal(lm_view_set_make(vs, 30, 208, c, 1.5f), LM_OK);
    return vs;
}

static void test_shift_moves_the_picture(void **state)
{
    (void)state;
    lm_view_set *vs = make_set();
    const double shifts[3][2] = {{0.3, -0.45}, {-0.5, 0.25}, {1.0, 2.0}};
    for (uint32_t i = 0; i < vs->count; i++)
        for (int s = 0; s < 3; s++) {
            lm_view moved = vs->views[i];
            lm_view_shift(&moved, shifts[s][0], shifts[s][1]);
            for (int k = 0; k < 20; k++) {
                const float p[3] = {0.1f + 0.07f * (float)(k % 5) - 0.15f,
                                    -0.2f + 0.05f * (float)(k / 5) - 0.1f, 0.3f + 0.02f * k};
                float a[2], b[2], wa, wb;
                assert_true(lm_view_project(&vs->views[i], p, a, &wa));
                assert_true(lm_view_project(&moved, p, b, &wb));
                assert_float_equal(b[0] - a[0], shifts[s][0], 2e-3);
                assert_float_equal(b[1] - a[1], shifts[s][1], 2e-3);
                assert_float_equal(wa, wb, 1e-6); /* the same camera: the same depths */
            }
        }
    free(vs);
}

static void test_offsets(void **state)
{
    (void)state;
    double o[2], again[2];
    co_regrid_offset(7, 0, 3, o);
    assert_true(o[0] == 0.0 && o[1] == 0.0);
    for (uint32_t view = 0; view < 30; view++) {
        int quadrant[4] = {0};
        for (uint32_t draw = 1; draw <= 16; draw++) {
            co_regrid_offset(7, draw, view, o);
            co_regrid_offset(7, draw, view, again);
            assert_true(o[0] == again[0] && o[1] == again[1]);
            assert_true(o[0] >= -0.5 && o[0] < 0.5 && o[1] >= -0.5 && o[1] < 0.5);
            quadrant[(o[0] >= 0) + 2 * (o[1] >= 0)]++;
        }
        for (int q = 0; q < 4; q++) /* 16 draws reach every quarter of the pixel */
            assert_true(quadrant[q] >= 2);
    }
    double a[2], b[2];
    co_regrid_offset(7, 1, 0, a);
    co_regrid_offset(8, 1, 0, b); /* another seed, other offsets */
    assert_true(a[0] != b[0] || a[1] != b[1]);
    co_regrid_offset(7, 1, 1, b); /* another view, too */
    assert_true(a[0] != b[0] || a[1] != b[1]);
}

static void test_apply(void **state)
{
    (void)state;
    lm_view_set *vs = make_set(), *moved = make_set();
    co_regrid_apply(moved, 5, 0);
    for (uint32_t i = 0; i < vs->count; i++)
        assert_memory_equal(vs->views[i].view_proj, moved->views[i].view_proj, sizeof(float) * 16);
    co_regrid_apply(moved, 5, 3);
    for (uint32_t i = 0; i < vs->count; i++) {
        const float c[3] = {0.1f, -0.2f, 0.3f};
        float a[2], b[2], w;
        double o[2];
        co_regrid_offset(5, 3, i, o);
        assert_true(lm_view_project(&vs->views[i], c, a, &w));
        assert_true(lm_view_project(&moved->views[i], c, b, &w));
        assert_float_equal(b[0] - a[0], o[0], 2e-3);
        assert_float_equal(b[1] - a[1], o[1], 2e-3);
    }
    free(vs);
    free(moved);
}

static void test_draws(void **state)
{
    (void)state;
    assert_int_equal(co_regrid_draw(123456, 0), 0);
    assert_true(co_regrid_next(0, 0) == UINT64_MAX);
    assert_int_equal(co_regrid_draw(9999, 10000), 0);
    assert_int_equal(co_regrid_draw(10000, 10000), 1);
    assert_int_equal(co_regrid_draw(25000, 10000), 2);
    assert_true(co_regrid_next(2, 10000) == 30000);
    assert_true(co_regrid_next(UINT32_MAX, UINT64_MAX / 4) == UINT64_MAX); /* no wrap-around */
    assert_int_equal(co_regrid_draw(UINT64_MAX, 1), UINT32_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shift_moves_the_picture),
        cmocka_unit_test(test_offsets),
        cmocka_unit_test(test_apply),
        cmocka_unit_test(test_draws),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
