/* tests/unit/test_lane_audit.c — the audit rule of --lanes remote (lane_audit.h): --audit-lanes
 * parsing (P,R and 0; anything else refused with one line); probation audits every lane; after it
 * the sample is deterministic, near 1 in R, never with R = 0, always with R = 1; the tally of two
 * and three results (agreement, a third needed, the majority and its odd one, three different). */
#include <string.h>

#include "coordinator/views/lane_audit.h"
#include "test_support.h"

static void test_parse(void **state)
{
    (void)state;
    co_audit_rule r = {9, 9};
    assert_int_equal(co_audit_parse("0", &r), LM_OK);
    assert_true(co_audit_off(r));
    assert_int_equal(co_audit_parse("4,16", &r), LM_OK);
    assert_int_equal(r.probation, 4);
    assert_int_equal(r.rate, 16);
    assert_false(co_audit_off(r));
    assert_int_equal(co_audit_parse("0,1", &r), LM_OK);
    assert_int_equal(r.probation, 0);
    assert_int_equal(r.rate, 1);
    const char *bad[] = {"",
                         "4",
                         "4,",
                         ",16",
                         "4,16,",
                         "-1,4",
                         "4,-1",
                         "a,b",
                         "4 ,16",
                         "4,16x",
                         "1000001,1",
                         "1,1000001",
                         "99999999999999999999,1",
                         " 4,16"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        assert_int_equal(co_audit_parse(bad[i], &r), LM_E_INVALID);
        assert_non_null(strstr(lm_last_error(), "--audit-lanes"));
        assert_null(strchr(lm_last_error(), '\n'));
    }
    assert_int_equal(co_audit_parse(NULL, &r), LM_E_INVALID);
}

static void test_wanted(void **state)
{
    (void)state;
    co_audit_rule r = {4, 16};
    for (uint32_t lane = 0; lane < 64; lane++)
        for (uint64_t c = 0; c < 4; c++)
            assert_true(co_audit_wanted(r, c, 1234, lane)); /* probation: every lane */
    uint32_t hits = 0, n = 64000;
    for (uint32_t i = 0; i < n; i++) {
        uint64_t h = 0x9e3779b97f4a7c15ull * (i / 64 + 1);
        int w = co_audit_wanted(r, 4, h, i % 64);
        assert_int_equal(w, co_audit_wanted(r, 1000, h, i % 64)); /* the same lanes for all */
        hits += (uint32_t)w;
    }
    assert_in_range(hits, n / 16 * 8 / 10, n / 16 * 12 / 10); /* about 1 in 16 */
    co_audit_rule none = {4, 0}, all = {0, 1}, off = {0, 0};
    for (uint32_t lane = 0; lane < 64; lane++) {
        assert_false(co_audit_wanted(none, 4, 77, lane));
        assert_true(co_audit_wanted(none, 3, 77, lane));
        assert_true(co_audit_wanted(all, 0, 77, lane));
        assert_false(co_audit_wanted(off, 0, 77, lane));
    }
}

static co_audit_vote vote(uint32_t worker, const char *s)
{
    return (co_audit_vote){worker, (const uint8_t *)s, strlen(s)};
}

static void test_tally(void **state)
{
    (void)state;
    uint32_t win = 99;
    co_audit_vote v[3] = {vote(1, "abc"), vote(2, "abc"), vote(3, "abd")};
    assert_int_equal(co_audit_tally(v, 2, &win), CO_AUDIT_AGREED);
    assert_int_equal(win, 0);
    co_audit_vote m[3] = {vote(1, "abc"), vote(2, "abd"), vote(3, "abd")};
    assert_int_equal(co_audit_tally(m, 2, &win), CO_AUDIT_MORE);
    assert_int_equal(co_audit_tally(m, 3, &win), CO_AUDIT_AGREED); /* the first is the odd one */
    assert_int_equal(win, 1);
    co_audit_vote f[3] = {vote(1, "abc"), vote(2, "abd"), vote(3, "abc")};
    assert_int_equal(co_audit_tally(f, 3, &win), CO_AUDIT_AGREED); /* the audit is the odd one */
    assert_int_equal(win, 0);
    co_audit_vote s[3] = {vote(1, "abc"), vote(2, "abd"), vote(3, "ab")};
    assert_int_equal(co_audit_tally(s, 3, &win), CO_AUDIT_SPLIT);
    co_audit_vote e[2] = {vote(1, ""), vote(2, "")}; /* empty results agree */
    assert_int_equal(co_audit_tally(e, 2, &win), CO_AUDIT_AGREED);
    co_audit_vote p[2] = {vote(1, "ab"), vote(2, "abc")}; /* a prefix is not the same */
    assert_int_equal(co_audit_tally(p, 2, &win), CO_AUDIT_MORE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse),
        cmocka_unit_test(test_wanted),
        cmocka_unit_test(test_tally),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
