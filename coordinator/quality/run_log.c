/* coordinator/quality/run_log.c — the run log: samples appended in memory, or read line by line
 * from `lumesh optimize --json` output with jansson. */
#include "coordinator/quality/run_log.h"

#include <errno.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

#define RUN_LOG_MAX_LINE (1u << 20)

void co_run_log_init(co_run_log *log)
{
    memset(log, 0, sizeof *log);
}

void co_run_log_free(co_run_log *log)
{
    free(log->samples);
    co_run_log_init(log);
}

lm_status co_run_log_set_kinds(co_run_log *log, const char *const *names, uint32_t n)
{
    if (n > CO_RUN_LOG_KINDS)
        return lm_fail(LM_E_RANGE, "a run log names at most %d move kinds", CO_RUN_LOG_KINDS);
    for (uint32_t i = 0; i < n; i++)
        snprintf(log->kinds[i], sizeof log->kinds[i], "%s", names[i]);
    log->n_kinds = n;
    return LM_OK;
}

lm_status co_run_log_add(co_run_log *log, uint64_t evals, double energy_rel,
                         const uint64_t *accepted)
{
    if (log->n == log->cap && !LM_GROW32(&log->samples, &log->cap, (size_t)log->n + 1, 256))
        return lm_fail(LM_E_NOMEM, "out of memory for the run log");
    co_run_sample *s = &log->samples[log->n++];
    memset(s, 0, sizeof *s);
    s->evals = evals;
    s->energy_rel = energy_rel;
    for (uint32_t k = 0; k < log->n_kinds; k++)
        s->accepted[k] = accepted[k];
    return LM_OK;
}

static uint64_t get_u64(const json_t *o, const char *key)
{
    const json_t *v = json_object_get(o, key);
    return json_is_integer(v) && json_integer_value(v) > 0 ? (uint64_t)json_integer_value(v) : 0;
}

static int64_t get_i64(const json_t *o, const char *key)
{
    const json_t *v = json_object_get(o, key);
    return json_is_integer(v) ? (int64_t)json_integer_value(v) : 0;
}

static double get_real(const json_t *o, const char *key)
{
    const json_t *v = json_object_get(o, key);
    return json_is_number(v) ? json_number_value(v) : 0.0;
}

static void get_string(const json_t *o, const char *key, char *out, size_t cap)
{
    const json_t *v = json_object_get(o, key);
    snprintf(out, cap, "%s", json_is_string(v) ? json_string_value(v) : "");
}

/* The kinds from the first record's "accepted" object (in its order), then counts by name. */
static lm_status accepted_counts(co_run_log *log, const json_t *acc, uint64_t *out)
{
    const char *key;
    json_t *v;
    if (!json_is_object(acc))
        return LM_OK;
    if (log->n_kinds == 0)
        json_object_foreach((json_t *)acc, key, v)
        {
            if (log->n_kinds < CO_RUN_LOG_KINDS)
                snprintf(log->kinds[log->n_kinds++], sizeof log->kinds[0], "%s", key);
        }
    for (uint32_t k = 0; k < log->n_kinds; k++)
        out[k] = get_u64(acc, log->kinds[k]);
    return LM_OK;
}

static lm_status take_record(co_run_log *log, const json_t *rec)
{
    const char *type = json_string_value(json_object_get(rec, "type"));
    uint64_t acc[CO_RUN_LOG_KINDS] = {0};
    if (type && !strcmp(type, "progress")) {
        accepted_counts(log, json_object_get(rec, "accepted"), acc);
        return co_run_log_add(log, get_u64(rec, "evals"), get_real(rec, "energy_rel"), acc);
    }
    if (type && !strcmp(type, "summary")) {
        log->has_summary = 1;
        log->evals = get_u64(rec, "evals");
        log->wall_s = get_real(rec, "wall_s");
        log->energy_start = get_i64(rec, "energy_start");
        log->energy_end = get_i64(rec, "energy_end");
        get_string(rec, "renderer", log->renderer, sizeof log->renderer);
        get_string(rec, "stop_reason", log->stop_reason, sizeof log->stop_reason);
    }
    return LM_OK;
}

static lm_status read_lines(FILE *fp, const char *path, co_run_log *log)
{
    char *line = NULL;
    size_t cap = 0;
    ssize_t len;
    lm_status s = LM_OK;
    for (unsigned no = 1; !s && (len = getline(&line, &cap, fp)) >= 0; no++) {
        if (len == 0 || line[0] == '\n')
            continue;
        json_error_t err;
        json_t *rec =
            (size_t)len <= RUN_LOG_MAX_LINE ? json_loadb(line, (size_t)len, 0, &err) : NULL;
        if (!json_is_object(rec))
            s = lm_fail(LM_E_FORMAT,
                        "%s: line %u is not a JSON record (the log is what lumesh optimize "
                        "--json writes)",
                        path, no);
        else
            s = take_record(log, rec);
        json_decref(rec);
    }
    free(line);
    return s;
}

lm_status co_run_log_read(const char *path, co_run_log *log)
{
    co_run_log_init(log);
    FILE *fp = fopen(path, "r");
    if (!fp)
        return lm_fail(LM_E_IO, "cannot read %s: %s", path, strerror(errno));
    lm_status s = read_lines(fp, path, log);
    fclose(fp);
    if (!s && log->n == 0 && !log->has_summary)
        s = lm_fail(LM_E_FORMAT,
                    "%s: no progress records and no summary (write the log with lumesh optimize "
                    "--json)",
                    path);
    if (s)
        co_run_log_free(log);
    return s;
}
