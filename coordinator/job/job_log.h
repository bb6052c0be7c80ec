/* coordinator/job/job_log.h — a job's run log for the quality report, filled while the job runs:
 * pass co_job_log_progress as co_job_options.on_progress with a co_run_log as its context, then
 * co_job_log_finish with the job's summary. The log then holds what `lumesh optimize --json`
 * would have printed (coordinator/quality/run_log.h). */
#ifndef LM_COORDINATOR_JOB_LOG_H
#define LM_COORDINATOR_JOB_LOG_H

#include "coordinator/job/progress.h"
#include "coordinator/quality/run_log.h"

/* on_progress hook: ctx is a co_run_log (the move kinds are named at the first call). Samples at
 * an evaluation count already logged are not repeated. Out of memory stops the logging only. */
void co_job_log_progress(void *ctx, const lm_progress *p, double elapsed_s);

/* The totals of the finished job. */
void co_job_log_finish(co_run_log *log, const co_job_summary *s);

#endif
