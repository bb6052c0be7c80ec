/* coordinator/job/job_log.c — lm_progress samples and the job summary into a co_run_log. */
#include "coordinator/job/job_log.h"

#include <stdio.h>

_Static_assert(LM_MOVE_KINDS <= CO_RUN_LOG_KINDS, "a run log names every move kind");

void co_job_log_progress(void *ctx, const lm_progress *p, double elapsed_s)
{
    (void)elapsed_s;
    co_run_log *log = ctx;
    if (log->n_kinds == 0) {
        const char *names[LM_MOVE_KINDS];
        for (int k = 0; k < LM_MOVE_KINDS; k++)
            names[k] = co_report_move_name((lm_move_kind)k);
        if (co_run_log_set_kinds(log, names, LM_MOVE_KINDS) != LM_OK)
            return;
    }
    if (log->n && log->samples[log->n - 1].evals == p->evals)
        return;
    double rel = p->energy_start > 0 ? (double)p->energy / (double)p->energy_start : 1.0;
    if (co_run_log_add(log, p->evals, rel, p->accepted) != LM_OK)
        lm_clear_error();
}

void co_job_log_finish(co_run_log *log, const co_job_summary *s)
{
    log->has_summary = 1;
    log->evals = s->progress.evals;
    log->wall_s = s->wall_s;
    log->energy_start = s->progress.energy_start;
    log->energy_end = s->progress.energy;
    snprintf(log->renderer, sizeof log->renderer, "%s", s->renderer);
    snprintf(log->stop_reason, sizeof log->stop_reason, "%s", s->stop_reason ? s->stop_reason : "");
}
