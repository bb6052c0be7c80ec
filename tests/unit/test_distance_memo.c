/* tests/unit/test_distance_memo.c — the geometric term's memo of distances
 * (common/distance_memo.h): whatever it holds, every answer is the very double
 * lm_bvh_closest_sq gives, for points asked once, again, and after others took their slot. */
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "common/distance_memo.h"
#include "test_support.h"

static void check_against_bvh(uint32_t log2_slots)
{
    lm_mesh *sphere = lmt_make_sphere(3);
    assert_non_null(sphere);
    lm_bvh *bvh = NULL;
    assert_int_equal(lm_bvh_create(sphere, &bvh), LM_OK);
    lm_distance_memo *m = NULL;
    assert_int_equal(lm_distance_memo_create(bvh, log2_slots, &m), LM_OK);
    enum { N = 300 };
    double q[N][3];
    uint64_t seed = 7;
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 3; k++)
            q[i][k] = 3.0 * lmt_urand(&seed) - 1.5;
    memcpy(q[2], q[1], sizeof q[1]); /* two points whose bits differ but whose values do not */
    q[1][0] = -0.0, q[2][0] = 0.0;
    memcpy(q[3], q[0], sizeof q[0]);
    for (int round = 0; round < 3; round++)
        for (int i = 0; i < N; i++) {
            int j = (i * 7 + round * 13) % N; /* another order each round */
            double want = lm_bvh_closest_sq(bvh, q[j]), got = lm_distance_memo_sq(m, q[j]);
            assert_memory_equal(&want, &got, sizeof want);
        }
    lm_distance_memo_destroy(m);
    lm_bvh_destroy(bvh);
    lm_mesh_destroy(sphere);
}

static void test_same_as_bvh(void **state)
{
    (void)state;
    check_against_bvh(14); /* room for every point */
    check_against_bvh(1);  /* two slots: points keep taking each other's */
}

static void test_refuses_bad_sizes(void **state)
{
    (void)state;
    lm_distance_memo *m = (lm_distance_memo *)1;
    assert_int_equal(lm_distance_memo_create(NULL, 4, &m), LM_E_INVALID);
    assert_null(m);
    lm_distance_memo_destroy(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_as_bvh),
        cmocka_unit_test(test_refuses_bad_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
