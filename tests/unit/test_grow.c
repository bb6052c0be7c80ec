/* tests/unit/test_grow.c — the growth rule (common/grow.h): capacities double from the first size
 * until they hold what is asked, stop at the most, and a size that would overflow fails with
 * nothing changed. */
#include <stdlib.h>

#include "common/grow.h"
#include "test_support.h"

static void test_capacity(void **state)
{
    (void)state;
    assert_int_equal(lm_grow_cap(0, 1, 16, SIZE_MAX), 16);
    assert_int_equal(lm_grow_cap(0, 17, 16, SIZE_MAX), 32);
    assert_int_equal(lm_grow_cap(16, 17, 64, SIZE_MAX), 32);
    assert_int_equal(lm_grow_cap(16, 16, 64, SIZE_MAX), 16); /* holds them already */
    assert_int_equal(lm_grow_cap(24, 100, 8, SIZE_MAX), 192);
    assert_int_equal(lm_grow_cap(0, 3, 0, SIZE_MAX), 4); /* no first size: from 1 */
    assert_int_equal(lm_grow_cap(64, 65, 8, 100), 100);  /* never past the most */
    assert_int_equal(lm_grow_cap(0, 5, 1024, 100), 100);
    assert_int_equal(lm_grow_cap(64, 101, 8, 100), 0); /* more than the most */
    assert_int_equal(lm_grow_cap((size_t)1 << 62, ((size_t)1 << 62) + 1, 8, SIZE_MAX),
                     (size_t)1 << 63);
    assert_int_equal(lm_grow_cap((size_t)1 << 63, ((size_t)1 << 63) + 1, 8, SIZE_MAX), SIZE_MAX);
    assert_int_equal(lm_grow_cap(1u << 31, (1u << 31) + 1, 8, UINT32_MAX), UINT32_MAX);
}

static void test_grow_arrays(void **state)
{
    (void)state;
    uint32_t *a = NULL, n32 = 0;
    for (uint32_t i = 0; i < 1000; i++) {
        if (i == n32)
            assert_true(LM_GROW32(&a, &n32, i + 1, 8));
        a[i] = i;
    }
    assert_int_equal(n32, 1024);
    for (uint32_t i = 0; i < 1000; i++)
        assert_int_equal(a[i], i);
    double *d = NULL;
    size_t nd = 0;
    assert_true(LM_GROW(&d, &nd, 300, 64));
    assert_int_equal(nd, 512);
    assert_true(LM_GROW(&d, &nd, 100, 64)); /* holds them: nothing changes */
    assert_int_equal(nd, 512);
    /* sizes that overflow fail, and leave the array and its capacity as they were */
    double *before = d;
    assert_false(LM_GROW(&d, &nd, SIZE_MAX / 4, 64));
    assert_ptr_equal(d, before);
    assert_int_equal(nd, 512);
    assert_false(LM_RESIZE(&d, SIZE_MAX / 2));
    assert_ptr_equal(d, before);
    assert_true(LM_RESIZE(&d, 3));
    free(a);
    free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_capacity),
        cmocka_unit_test(test_grow_arrays),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
