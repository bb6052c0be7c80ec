/* tests/unit/test_view_deal.c — shares of a view set (common/view.h, lm_view_deal), as the
 * coordinator deals a job's views out to its workers: G shares of every G-th view hold each view
 * exactly once, a view's place in its share maps back to it, shares that do not fit the set are
 * refused (a hostile Assign included), each share of the default set looks at the model from both
 * sides, and the text progress prints. */
#include <stdint.h>
#include <stdlib.h>

#include "common/view.h"
#include "test_support.h"

/* The shares views_remote_layout.c's plan() makes: share k holds every g-th view from the k-th. */
static lm_view_deal share(uint32_t n, uint32_t g, uint32_t k)
{
    return (lm_view_deal){k, n / g + (k < n % g), g};
}

static void test_shares_cover_once(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= 40; n++)
        for (uint32_t g = 1; g <= n; g++) {
            uint32_t seen[40] = {0};
            for (uint32_t k = 0; k < g; k++) {
                lm_view_deal d = share(n, g, k);
                assert_true(lm_view_deal_fits(d, n));
                for (uint32_t i = 0; i < d.count; i++) {
                    uint32_t h = lm_view_deal_view(d, i), place = 99;
                    assert_true(h < n);
                    seen[h]++;
                    assert_true(lm_view_deal_place(d, h, &place));
                    assert_int_equal(place, i);
                }
            }
            for (uint32_t h = 0; h < n; h++)
                assert_int_equal(seen[h], 1);
            /* a view of another share is not this one's */
            if (g > 1) {
                uint32_t place;
                assert_false(lm_view_deal_place(share(n, g, 0), 1, &place));
            }
        }
}

static void test_refuses_what_does_not_fit(void **state)
{
    (void)state;
    assert_false(lm_view_deal_fits((lm_view_deal){0, 0, 1}, 20));  /* nothing */
    assert_false(lm_view_deal_fits((lm_view_deal){20, 1, 1}, 20)); /* past the end */
    assert_false(lm_view_deal_fits((lm_view_deal){1, 10, 2}, 19)); /* its last is view 19 */
    assert_true(lm_view_deal_fits((lm_view_deal){1, 10, 2}, 20));
    assert_false(lm_view_deal_fits((lm_view_deal){0, 3, UINT32_MAX}, 20)); /* no wrap-around */
    assert_false(lm_view_deal_fits((lm_view_deal){5, UINT32_MAX, 0}, 20));
    assert_true(lm_view_deal_fits((lm_view_deal){3, 17, 0}, 20)); /* stride 0 is 1 */
    uint32_t place;
    assert_false(lm_view_deal_place((lm_view_deal){3, 4, 5}, 2, &place));
    assert_false(lm_view_deal_place((lm_view_deal){3, 4, 5}, 23, &place)); /* after the last */
}

/* A share of the default set sees the model from above and from below: a contiguous half of a
 * Fibonacci set would see it from one side only, and a patch there would be all one worker's. */
static void test_each_share_sees_both_sides(void **state)
{
    (void)state;
    lm_view_set *vs = malloc(sizeof *vs);
    assert_non_null(vs);
    const float centre[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(vs, 30, 64, centre, 1.0f), LM_OK);
    for (uint32_t g = 2; g <= 4; g++)
        for (uint32_t k = 0; k < g; k++) {
            lm_view_deal d = share(vs->count, g, k);
            int above = 0, below = 0;
            for (uint32_t i = 0; i < d.count; i++) {
                const float *eye = vs->views[lm_view_deal_view(d, i)].eye;
                above += eye[1] > 0.3f;
                below += eye[1] < -0.3f;
            }
            assert_true(above >= 2 && below >= 2);
        }
    free(vs);
}

/* The default set (the dodecahedron) is listed along a tour of neighbouring directions, so that
 * dealt in halves (or quarters), the views that see any one side of the model are shared out
 * evenly: for every direction of the set, the views of the hemisphere around it differ by at most
 * 2 between two shares and 3 between four (in the order the vertices are made, one half held all
 * the +x cube corners: 8 more of a hemisphere than the other). */
static void test_shares_see_each_side_evenly(void **state)
{
    (void)state;
    lm_view_set *vs = malloc(sizeof *vs);
    assert_non_null(vs);
    const float centre[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(vs, LM_DEFAULT_VIEWS, 64, centre, 1.0f), LM_OK);
    for (uint32_t g = 2; g <= 4; g += 2)
        for (uint32_t u = 0; u < vs->count; u++) {
            uint32_t most = 0, least = vs->count;
            for (uint32_t k = 0; k < g; k++) {
                lm_view_deal d = share(vs->count, g, k);
                uint32_t seeing = 0;
                for (uint32_t i = 0; i < d.count; i++) {
                    const float *a = vs->views[lm_view_deal_view(d, i)].dir;
                    const float *b = vs->views[u].dir;
                    seeing += a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0.0f;
                }
                most = seeing > most ? seeing : most;
                least = seeing < least ? seeing : least;
            }
            assert_true(most - least <= (g == 2 ? 2u : 3u));
        }
    free(vs);
}

static void test_text(void **state)
{
    (void)state;
    char b[48];
    lm_view_deal_text((lm_view_deal){4, 6, 1}, b, sizeof b);
    assert_string_equal(b, "4-9");
    lm_view_deal_text((lm_view_deal){1, 15, 2}, b, sizeof b);
    assert_string_equal(b, "1,3..29");
    lm_view_deal_text((lm_view_deal){5, 1, 3}, b, sizeof b);
    assert_string_equal(b, "5");
    lm_view_deal_text((lm_view_deal){0, 0, 1}, b, sizeof b);
    assert_string_equal(b, "-");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shares_cover_once),
        cmocka_unit_test(test_refuses_what_does_not_fit),
        cmocka_unit_test(test_each_share_sees_both_sides),
        cmocka_unit_test(test_shares_see_each_side_evenly),
        cmocka_unit_test(test_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
