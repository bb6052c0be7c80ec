/* coordinator/job/progress.h — telling the user how a job is going, and the final summary.
 * Three styles: a single updating line on a terminal; plain lines every few seconds otherwise; or
 * newline-delimited JSON records (one object per line, "type":"progress" then one
 * "type":"summary"). The reporter only formats; the job decides when to call it. */
#ifndef LM_COORDINATOR_PROGRESS_H
#define LM_COORDINATOR_PROGRESS_H

#include <stdint.h>
#include <stdio.h>

#include "common/optimizer/optimizer.h"
#include "coordinator/quality/json_text.h"
#include "coordinator/views/views.h"

typedef enum co_report_style {
    CO_REPORT_QUIET, /* nothing */
    CO_REPORT_TTY,   /* one line rewritten with '\r' (at most every 0.2 s) */
    CO_REPORT_LINES, /* a plain line every 5 s */
    CO_REPORT_JSON,  /* a JSON record every second */
} co_report_style;

/* One worker as progress shows it. */
typedef struct co_worker_report {
    uint32_t id, pid;
    char host[64], device[32];
    uint32_t first, count, stride; /* its views (an lm_view_deal) */
    uint64_t evals;                /* patches it evaluated for the job */
    double evals_per_s;            /* since it joined */
    double busy;                   /* fraction of that time spent evaluating */
    double busy_loop; /* fraction of the optimisation loop's time (since it began, or the worker
                         joined) spent evaluating: co_pool_loop_busy */
    double heard_s;   /* seconds since it was last heard */
    int lost;
} co_worker_report;

/* A validating job's numbers as progress shows them (coordinator/job/validate.h). */
typedef struct co_validation_report {
    int on;              /* 0: the job does not validate (nothing shown) */
    int64_t energy;      /* the last check's energy on the validation views */
    int64_t best;        /* the best so far (the mesh the job outputs) */
    int64_t first;       /* the first check's (the start's): the fractions' base */
    uint64_t best_evals; /* evaluations at the best */
    uint32_t checks;     /* checks so far */
    uint32_t epoch;      /* training views in force (0 = the job's; n after n plateaus) */
} co_validation_report;

typedef struct co_reporter {
    co_report_style style;
    FILE *out;            /* progress records */
    FILE *summary_out;    /* the final summary: stdout (JSON style: `out`) */
    uint64_t max_evals;   /* budget (for the ETA); 0 = unbounded */
    double time_limit_s;  /* 0 = none */
    double last_report_s; /* elapsed time of the last report, < 0 before the first */
    uint64_t start_evals; /* evaluations at the first update (rates count this process only) */
    uint64_t last_evals;  /* evaluations at the last report */
    int line_open;        /* a TTY line is showing and needs a newline before other output */
    const co_worker_report *workers; /* shown with every report (owned by the caller) */
    uint32_t n_workers;
    co_validation_report val;
} co_reporter;

/* What a finished job reports. */
typedef struct co_job_summary {
    lm_progress progress;    /* final counters (energy_start, energy, evals, accepted...) */
    double wall_s;           /* seconds the whole job took in this process (load to output) */
    double optimize_s;       /* of which the optimisation loop */
    double loop_cpu_s;       /* CPU seconds of this process in the loop (with workers: the
                                coordinator's own work; in process, the rendering too) */
    const char *stop_reason; /* "evals", "time", "converged", "interrupted" or "suspended" */
    const char *output_path; /* NULL when suspended (SIGUSR1): only the checkpoint was written */
    const char *checkpoint_path; /* NULL = none */
    char renderer[128];
    uint64_t resumed_from_evals; /* evaluations done before this process started (0 = fresh) */
    uint32_t workers;            /* worker processes that served the job (0 = in process) */
    co_lane_stats lanes;         /* --lanes remote: what the groups sent (groups 0: none) */
} co_job_summary;

/* The style for a stream: JSON if asked, TTY if `out` is a terminal, plain lines otherwise. */
co_report_style co_report_style_for(FILE *out, int json);

void co_reporter_init(co_reporter *r, co_report_style style, FILE *out, uint64_t max_evals,
                      double time_limit_s);
/* The workers the next reports show (the array stays the caller's; n = 0: none). */
void co_reporter_set_workers(co_reporter *r, const co_worker_report *w, uint32_t n);
/* The validation numbers the next reports and the summary show. */
void co_reporter_set_validation(co_reporter *r, const co_validation_report *v);
/* Report if enough time passed since the last report (always when `force`). */
void co_reporter_update(co_reporter *r, const lm_progress *p, double elapsed_s, int force);
/* A set-up step or event ("original", "views", "checkpoint", "warning"...): a JSON event record;
 * on a terminal a transient status on the progress line; otherwise an info-level log line
 * (hidden by default). "warning" events are always shown (log warning) except in JSON style. */
void co_reporter_note(co_reporter *r, const char *event, const char *detail);
/* End a showing TTY line with a newline (keeps it), or erase it (before an error message). */
void co_reporter_end_line(co_reporter *r);
void co_reporter_abandon_line(co_reporter *r);
/* Close the TTY line, and write the summary to summary_out (JSON record in JSON style, human lines
 * otherwise; nothing when quiet). */
void co_reporter_summary(co_reporter *r, const co_job_summary *s);

/* The end of a JSON record that names its renderer: `, "renderer": "R"}` and a newline. */
void co_json_end_with_renderer(FILE *fp, const char *renderer);
/* Name of a move kind for reports: "noop", "swap", "split", "collapse". */
const char *co_report_move_name(lm_move_kind k);

#endif
