/* tests/unit/test_schedule.c — the view schedule and the quality presets (schedule.h, preset.h,
 * `optimize --view-schedule grow`, `--quality`): the grow schedule's stages begin at 0, 1/3 and
 * 2/3 of the budget (exact integers, any budget), each with more views and pixels, capped; the
 * fixed schedule never leaves stage 0; the extend schedule's stages begin at fixed evaluation
 * counts whatever the budget; names parse and bad ones are refused; `good` is the job's defaults
 * exactly. */
#include <stdint.h>
#include <string.h>

#include "coordinator/job/job.h"
#include "coordinator/job/preset.h"
#include "coordinator/job/schedule.h"
#include "test_support.h"

static void test_stages(void **state)
{
    (void)state;
    assert_int_equal(co_schedule_stage(CO_SCHEDULE_GROW, 0, 100000), 0);
    assert_int_equal(co_schedule_stage(CO_SCHEDULE_GROW, 33332, 100000), 0);
    assert_int_equal(co_schedule_stage(CO_SCHEDULE_GROW, 33333, 100000), 1);
    assert_int_equal(co_schedule_stage(CO_SCHEDULE_GROW, 66665, 100000), 1);
    assert_int_equal(co_schedule_stage(CO_SCHEDULE_GROW, 66666, 100000), 2);
    assert_int_equal(co_schedule_stage(CO_SCHEDULE_GROW, UINT64_MAX, 100000), 2);
    assert_int_equal(co_schedule_next(CO_SCHEDULE_GROW, 0, 100000), 33333);
    assert_int_equal(co_schedule_next(CO_SCHEDULE_GROW, 1, 100000), 66666);
    assert_true(co_schedule_next(CO_SCHEDULE_GROW, 2, 100000) == UINT64_MAX);
    /* No overflow near the top of the range. */
    uint64_t big = UINT64_MAX - 1;
    assert_true(co_schedule_next(CO_SCHEDULE_GROW, 1, big) >
                co_schedule_next(CO_SCHEDULE_GROW, 0, big));
    for (uint64_t e = 0; e < 200000; e += 997)
        assert_int_equal(co_schedule_stage(CO_SCHEDULE_FIXED, e, 100000), 0);
    assert_true(co_schedule_next(CO_SCHEDULE_FIXED, 0, 100000) == UINT64_MAX);
}

/* extend: stages at 100k, 200k, 400k, 800k evaluations whatever the budget. */
static void test_extend_stages(void **state)
{
    (void)state;
    const uint64_t budgets[] = {1000, 100000, 1000000, UINT64_MAX};
    for (size_t i = 0; i < sizeof budgets / sizeof budgets[0]; i++) {
        uint64_t b = budgets[i];
        assert_int_equal(co_schedule_stage(CO_SCHEDULE_EXTEND, 99999, b), 0);
        assert_int_equal(co_schedule_stage(CO_SCHEDULE_EXTEND, 100000, b), 1);
        assert_int_equal(co_schedule_stage(CO_SCHEDULE_EXTEND, 399999, b), 2);
        assert_int_equal(co_schedule_stage(CO_SCHEDULE_EXTEND, 400000, b), 3);
        assert_int_equal(co_schedule_stage(CO_SCHEDULE_EXTEND, 800000, b), 4);
        assert_int_equal(co_schedule_stage(CO_SCHEDULE_EXTEND, UINT64_MAX, b), 4);
        assert_int_equal(co_schedule_next(CO_SCHEDULE_EXTEND, 0, b), 100000);
        assert_int_equal(co_schedule_next(CO_SCHEDULE_EXTEND, 3, b), 800000);
        assert_true(co_schedule_next(CO_SCHEDULE_EXTEND, 4, b) == UINT64_MAX);
    }
    assert_int_equal(co_schedule_stages(CO_SCHEDULE_EXTEND), 5);
    assert_int_equal(co_schedule_stages(CO_SCHEDULE_GROW), 3);
    assert_int_equal(co_schedule_stages(CO_SCHEDULE_FIXED), 1);
    assert_int_equal(co_schedule_stages(CO_SCHEDULE_DEFAULT), 1);
    uint32_t n;
    int size;
    const uint32_t want_n[] = {30, 45, 68, 101, 152};
    const int want_size[] = {208, 233, 260, 260, 260};
    for (uint32_t k = 0; k < 5; k++) {
        co_schedule_views(CO_SCHEDULE_EXTEND, k, 30, 208, 256, 4096, &n, &size);
        assert_int_equal(n, want_n[k]);
        assert_int_equal(size, want_size[k]);
    }
    co_schedule_views(CO_SCHEDULE_EXTEND, 4, 100, 208, 256, 4096, &n, &size);
    assert_int_equal(n, 256); /* capped */
}

static void test_views(void **state)
{
    (void)state;
    uint32_t n;
    int size;
    co_schedule_views(CO_SCHEDULE_GROW, 0, 30, 208, 256, 4096, &n, &size);
    assert_int_equal(n, 30);
    assert_int_equal(size, 208);
    co_schedule_views(CO_SCHEDULE_GROW, 1, 30, 208, 256, 4096, &n, &size);
    assert_int_equal(n, 45);
    assert_int_equal(size, 233);
    co_schedule_views(CO_SCHEDULE_GROW, 2, 30, 208, 256, 4096, &n, &size);
    assert_int_equal(n, 68);
    assert_int_equal(size, 260);
    co_schedule_views(CO_SCHEDULE_GROW, 2, 200, 4000, 256, 4096, &n, &size);
    assert_int_equal(n, 256);
    assert_int_equal(size, 4096);
    co_schedule_views(CO_SCHEDULE_FIXED, 2, 30, 208, 256, 4096, &n, &size);
    assert_int_equal(n, 30);
    assert_int_equal(size, 208);
}

static void test_names(void **state)
{
    (void)state;
    co_view_schedule s;
    assert_int_equal(co_schedule_parse("grow", &s), LM_OK);
    assert_int_equal(s, CO_SCHEDULE_GROW);
    assert_int_equal(co_schedule_parse("fixed", &s), LM_OK);
    assert_int_equal(s, CO_SCHEDULE_FIXED);
    assert_int_equal(co_schedule_parse("extend", &s), LM_OK);
    assert_int_equal(s, CO_SCHEDULE_EXTEND);
    assert_string_equal(co_schedule_name(CO_SCHEDULE_EXTEND), "extend");
    assert_int_equal(co_schedule_parse("Grow", &s), LM_E_INVALID);
    assert_int_equal(co_schedule_parse(NULL, &s), LM_E_INVALID);
    co_job_quality q;
    assert_int_equal(co_job_quality_parse("best", &q), LM_OK);
    assert_int_equal(q, CO_QUALITY_BEST);
    assert_int_equal(co_job_quality_parse("draft", &q), LM_OK);
    assert_int_equal(q, CO_QUALITY_DRAFT);
    assert_int_equal(co_job_quality_parse("fast", &q), LM_E_INVALID);
    assert_non_null(strstr(lm_last_error(), "'fast'"));
    assert_int_equal(co_job_quality_parse("", &q), LM_E_INVALID);
}

static void test_good_is_the_defaults(void **state)
{
    (void)state;
    const co_job_preset *g = co_job_preset_of(CO_QUALITY_GOOD);
    assert_int_equal(g->evals, CO_JOB_DEFAULT_EVALS);
    assert_int_equal(g->views, CO_JOB_DEFAULT_VIEWS);
    assert_int_equal(g->size, CO_JOB_DEFAULT_SIZE);
    assert_int_equal(g->schedule, CO_JOB_DEFAULT_SCHEDULE);
    assert_ptr_equal(co_job_preset_of(CO_QUALITY_DEFAULT), g);
    const co_job_preset *d = co_job_preset_of(CO_QUALITY_DRAFT),
                        *b = co_job_preset_of(CO_QUALITY_BEST);
    assert_true(d->evals < g->evals && g->evals <= b->evals);
    assert_int_equal(b->schedule, CO_SCHEDULE_GROW);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stages),
        cmocka_unit_test(test_extend_stages),
        cmocka_unit_test(test_views),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_good_is_the_defaults),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
