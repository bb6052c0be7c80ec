/* tests/unit/test_run_log.c — the report's run log read from `lumesh optimize --json` output:
 * progress records become samples (move kinds named by the first record), the summary gives the
 * totals, events are skipped, and a line that is not JSON or a file without records is refused
 * naming the problem. */
#include "test_support.h"

#include <stdio.h>
#include <string.h>

#include "coordinator/quality/run_log.h"

static char *write_log(const char *dir, const char *text)
{
    static char path[1200];
    snprintf(path, sizeof path, "%s/run.jsonl", dir);
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fputs(text, fp);
    fclose(fp);
    return path;
}

static void test_read(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    const char *path = write_log(
        dir,
        "{\"type\":\"event\",\"event\":\"original\",\"detail\":\"x\"}\n"
        "{\"type\":\"progress\",\"evals\":0,\"energy_rel\":1.0,\"accepted\":{\"noop\":0,"
        "\"swap\":0}}\n\n"
        "{\"type\":\"progress\",\"evals\":900,\"energy_rel\":0.75,\"accepted\":{\"noop\":2,"
        "\"swap\":5}}\n"
        "{\"type\":\"summary\",\"energy_start\":123456789012,\"energy_end\":92592591759,"
        "\"evals\":1000,\"wall_s\":2.5,\"stop_reason\":\"evals\",\"renderer\":\"llvmpipe\"}\n");
    co_run_log log;
    assert_int_equal(co_run_log_read(path, &log), LM_OK);
    assert_int_equal(log.n, 2);
    assert_int_equal(log.n_kinds, 2);
    assert_string_equal(log.kinds[1], "swap");
    assert_int_equal(log.samples[1].evals, 900);
    assert_float_equal(log.samples[1].energy_rel, 0.75, 0);
    assert_int_equal(log.samples[1].accepted[1], 5);
    assert_true(log.has_summary);
    assert_int_equal(log.evals, 1000);
    assert_true(log.energy_start == 123456789012ll);
    assert_float_equal(log.wall_s, 2.5, 0);
    assert_string_equal(log.renderer, "llvmpipe");
    assert_string_equal(log.stop_reason, "evals");
    co_run_log_free(&log);
    lmt_rmdir(dir);
}

static void test_refused(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    co_run_log log;
    const char *path =
        write_log(dir, "{\"type\":\"progress\",\"evals\":1}\nenergy 100%% | 5 evals\n");
    assert_int_equal(co_run_log_read(path, &log), LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "line 2"));
    assert_int_equal(log.n, 0);
    path = write_log(dir, "{\"type\":\"event\",\"event\":\"views\"}\n");
    assert_int_equal(co_run_log_read(path, &log), LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "--json"));
    assert_int_equal(co_run_log_read("/nonexistent/run.jsonl", &log), LM_E_IO);
    lmt_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_read), cmocka_unit_test(test_refused)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
