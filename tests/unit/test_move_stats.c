/* tests/unit/test_move_stats.c — the inverse error function, attenuated statistics, the choice of
 * the most efficient operation and Inequality 3's selection behaviour. */
#include <math.h>
#include <string.h>

#include "common/optimizer/move_stats.h"
#include "test_support.h"

static void test_erfinv(void **state)
{
    (void)state;
    assert_true(lm_erfinv(0.0) == 0.0);
    assert_true(fabs(lm_erfinv(0.5) - 0.4769362762044699) < 1e-14);
    assert_true(fabs(lm_erfinv(0.9) - 1.1630871536766743) < 1e-13);
    assert_true(isinf(lm_erfinv(1.0)) && lm_erfinv(1.0) > 0);
    assert_true(isinf(lm_erfinv(-1.0)) && lm_erfinv(-1.0) < 0);
    assert_true(isnan(lm_erfinv(1.5)));
    assert_true(isnan(lm_erfinv(NAN)));
    for (int i = -999; i <= 999; i++) {
        double x = i / 1000.0;
        double y = lm_erfinv(x);
        assert_true(fabs(erf(y) - x) < 1e-14);
        assert_true(lm_erfinv(-x) == -y);
    }
    /* tails */
    const double tails[] = {1 - 1e-6, 1 - 1e-10, 1 - 1e-15};
    for (int i = 0; i < 3; i++) {
        double y = lm_erfinv(tails[i]);
        assert_true(isfinite(y) && y > 3.0);
        assert_true(fabs(erfc(y) - (1 - tails[i])) / (1 - tails[i]) < 1e-3);
    }
}

static void test_stat_attenuation(void **state)
{
    (void)state;
    lm_stat s;
    memset(&s, 0, sizeof s);
    lm_stat_view v;
    lm_stat_get(&s, 0, 100, &v);
    assert_true(v.f == 0);
    lm_stat_add(&s, -10, 4, 0, 100);
    lm_stat_add(&s, -30, 8, 0, 100);
    lm_stat_get(&s, 0, 100, &v);
    assert_true(fabs(v.f - 2) < 1e-12);
    assert_true(fabs(v.mean + 20) < 1e-12);
    assert_true(fabs(v.sigma - 10) < 1e-12);
    assert_true(fabs(v.t - 6) < 1e-12);
    lm_stat_get(&s, 100, 100, &v);
    assert_true(fabs(v.f - 1) < 1e-12); /* halved after one half-life, mean unchanged */
    assert_true(fabs(v.mean + 20) < 1e-12);
    /* a new sample weighs more than the old ones */
    lm_stat_add(&s, 0, 2, 200, 100);
    lm_stat_get(&s, 200, 100, &v);
    assert_true(fabs(v.f - 1.5) < 1e-12);
    assert_true(fabs(v.mean - (-40 * 0.25) / 1.5) < 1e-9);
}

static void add_spread(lm_move_stats *st, lm_move_kind k, int l, double de, double spread, double t,
                       int n, uint64_t *now)
{
    for (int i = 0; i < n; i++) {
        lm_move_stats_add(st, k, l, de + (i % 2 ? spread : -spread), t, *now);
        *now += (uint64_t)t;
    }
}

static void add_n(lm_move_stats *st, lm_move_kind k, int l, double de, double t, int n,
                  uint64_t *now)
{
    for (int i = 0; i < n; i++) {
        lm_move_stats_add(st, k, l, de + (i % 2 ? 5 : -5), t, *now);
        *now += (uint64_t)t;
    }
}

static void test_best_and_gating(void **state)
{
    (void)state;
    lm_move_stats st;
    lm_move_stats_init(&st, 1e9, 1.0);
    lm_move_kind k;
    int l;
    assert_false(lm_move_stats_best(&st, 0, &k, &l));
    /* without data everything is tried */
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_SWAP, 2, 0, 0));
    uint64_t now = 0;
    add_n(&st, LM_MOVE_NOOP, 1, -100, 10, 20, &now); /* -10 per evaluation */
    add_n(&st, LM_MOVE_NOOP, 2, -150, 50, 20, &now); /* -3 per evaluation */
    add_n(&st, LM_MOVE_SWAP, 0, -20, 1, 20, &now);   /* -20 per evaluation: the best */
    assert_true(lm_move_stats_best(&st, now, &k, &l));
    assert_int_equal(k, LM_MOVE_SWAP);
    assert_int_equal(l, 0);
    /* the best operation is attempted (its own bound is ΔE* + 0.67σ) */
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_SWAP, 0, 0, now));
    /* no-op level 1 would need ΔE < -20*10 + √2 erf⁻¹(1/2) σ ≈ -196.6: not attempted */
    assert_false(lm_move_stats_should_try(&st, LM_MOVE_NOOP, 1, 0, now));
    /* operations never attempted are */
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_SPLIT, 3, 0, now));
    /* collapse is not an edge operation */
    assert_false(lm_move_is_edge_op(LM_MOVE_COLLAPSE, 1));
    assert_false(lm_move_is_edge_op(LM_MOVE_NOOP, 0));
    assert_true(lm_move_is_edge_op(LM_MOVE_NOOP, 3));
}

static void test_progress_term(void **state)
{
    (void)state;
    lm_move_stats st;
    lm_move_stats_init(&st, 1e9, 1.0);
    uint64_t now = 0;
    add_n(&st, LM_MOVE_NOOP, 1, -100, 10, 20, &now);
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_NOOP, 1, 0, now));
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_NOOP, 1, -50, now));
    /* much progress made on this edge already: the expected -100 is not worth another try */
    assert_false(lm_move_stats_should_try(&st, LM_MOVE_NOOP, 1, -1000, now));
}

static void test_underused_operation_is_retried(void **state)
{
    (void)state;
    lm_move_stats st;
    lm_move_stats_init(&st, 1000, 1.0);
    uint64_t now = 0;
    /* swap level 1 (mean -100, sigma 50, 10 evaluations) was tried a few times early */
    add_spread(&st, LM_MOVE_SWAP, 1, -100, 50, 10, 4, &now);
    /* then no-op level 1 (mean -200 per 10 evaluations) dominated for a long time */
    add_n(&st, LM_MOVE_NOOP, 1, -200, 10, 400, &now);
    lm_stat_view sw;
    lm_stat_get(&st.op[LM_MOVE_SWAP][1], now, st.half_life, &sw);
    assert_true(sw.f < 1.0); /* its weight has decayed below min_weight: refreshed */
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_SWAP, 1, 0, now));
    /* without the minimum weight the probability rule decides: f'/(f+f') is near 1 for the
     * rarely used operation, erf⁻¹ of it is large, and -100 < -200 + 3.1 * 50 */
    st.min_weight = 1e-9;
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_SWAP, 1, 0, now));
    /* used as often as the best one, it is not: -100 > -200 + 0.67 * 50 */
    lm_move_stats st2;
    lm_move_stats_init(&st2, 1e9, 1e-9);
    now = 0;
    for (int i = 0; i < 400; i++) {
        add_spread(&st2, LM_MOVE_SWAP, 1, -100, 50, 10, 1, &now);
        add_n(&st2, LM_MOVE_NOOP, 1, -200, 10, 1, &now);
    }
    assert_false(lm_move_stats_should_try(&st2, LM_MOVE_SWAP, 1, 0, now));
    assert_true(lm_move_stats_should_try(&st2, LM_MOVE_NOOP, 1, 0, now));
}

static void test_cheap_failures_are_retried(void **state)
{
    (void)state;
    lm_move_stats st;
    lm_move_stats_init(&st, 1e9, 1.0);
    uint64_t now = 0;
    /* swap level 0 costs one evaluation and failed 30 times in a row (σ = 0) */
    for (int i = 0; i < 30; i++) {
        lm_move_stats_add(&st, LM_MOVE_SWAP, 0, 0, 1, now);
        now += 1;
    }
    /* no-op level 1 works, at 60 evaluations an attempt */
    add_spread(&st, LM_MOVE_NOOP, 1, -60000, 50000, 60, 100, &now);
    /* 30 evaluations against 6000: the swap is little used, and its spread is not taken as 0 */
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_SWAP, 0, 0, now));
    /* and, costing one evaluation, also after this edge has made progress */
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_SWAP, 0, -100000, now));
    /* an expensive operation is not started after much progress: no-op level 1 itself */
    assert_true(lm_move_stats_should_try(&st, LM_MOVE_NOOP, 1, 0, now));
    assert_false(lm_move_stats_should_try(&st, LM_MOVE_NOOP, 1, -100000, now));
    /* an expensive operation with the same record is not worth it */
    lm_move_stats st2;
    lm_move_stats_init(&st2, 1e9, 1.0);
    now = 0;
    for (int i = 0; i < 30; i++) {
        lm_move_stats_add(&st2, LM_MOVE_SWAP, 3, 0, 400, now);
        now += 400;
    }
    add_spread(&st2, LM_MOVE_NOOP, 1, -60000, 50000, 60, 100, &now);
    assert_false(lm_move_stats_should_try(&st2, LM_MOVE_SWAP, 3, 0, now));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_erfinv),
        cmocka_unit_test(test_stat_attenuation),
        cmocka_unit_test(test_best_and_gating),
        cmocka_unit_test(test_progress_term),
        cmocka_unit_test(test_underused_operation_is_retried),
        cmocka_unit_test(test_cheap_failures_are_retried),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
