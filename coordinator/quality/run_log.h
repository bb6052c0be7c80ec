/* coordinator/quality/run_log.h — an optimisation run as the quality report plots it: samples of
 * the energy relative to the start and of the accepted moves by kind against evaluations, and the
 * run's totals. Read from the newline-delimited JSON of `lumesh optimize --json` (its "progress"
 * records and the "summary"), or filled while a run goes (`lumesh optimize --report`). */
#ifndef LM_COORDINATOR_RUN_LOG_H
#define LM_COORDINATOR_RUN_LOG_H

#include <stdint.h>

#include "common/error.h"

#define CO_RUN_LOG_KINDS 8 /* move kinds a log can name */

typedef struct co_run_sample {
    uint64_t evals;
    double energy_rel; /* energy / energy at the start */
    uint64_t accepted[CO_RUN_LOG_KINDS];
} co_run_sample;

typedef struct co_run_log {
    co_run_sample *samples; /* in the order recorded (evaluations never decrease) */
    uint32_t n, cap;
    uint32_t n_kinds;
    char kinds[CO_RUN_LOG_KINDS][16]; /* names of the move kinds, "swap", ... */
    int has_summary;                  /* the totals below are known */
    uint64_t evals;
    double wall_s;
    int64_t energy_start, energy_end;
    char renderer[128];
    char stop_reason[32];
} co_run_log;

/* An empty log (no samples, no summary); what co_run_log_free leaves too. */
void co_run_log_init(co_run_log *log);
void co_run_log_free(co_run_log *log);

/* Name the move kinds of the samples to come (at most CO_RUN_LOG_KINDS). */
lm_status co_run_log_set_kinds(co_run_log *log, const char *const *names, uint32_t n);
/* Append a sample; accepted has log->n_kinds counts. */
lm_status co_run_log_add(co_run_log *log, uint64_t evals, double energy_rel,
                         const uint64_t *accepted);

/* Read the NDJSON of `lumesh optimize --json` (other record types are skipped). LM_E_FORMAT naming
 * the line when a line is not JSON, or when the file has neither progress records nor a summary.
 * *log is initialised here; free it with co_run_log_free. */
lm_status co_run_log_read(const char *path, co_run_log *log);

#endif
