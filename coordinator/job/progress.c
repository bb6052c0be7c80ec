/* coordinator/job/progress.c — progress line / plain lines / JSON records, and the final summary.
 */
#include "coordinator/job/progress.h"

#include <inttypes.h>
#include <string.h>
#include <unistd.h>

#include "common/log.h"
#include "common/view.h"
#include "coordinator/quality/phase_meter.h"

static const double co_report_period[] = {
    [CO_REPORT_QUIET] = 1e30,
    [CO_REPORT_TTY] = 0.2,
    [CO_REPORT_LINES] = 5.0,
    [CO_REPORT_JSON] = 1.0,
};

const char *co_report_move_name(lm_move_kind k)
{
    switch (k) {
    case LM_MOVE_NOOP:
        return "noop";
    case LM_MOVE_SWAP:
        return "swap";
    case LM_MOVE_SPLIT:
        return "split";
    case LM_MOVE_COLLAPSE:
        return "collapse";
    default:
        return "?";
    }
}

co_report_style co_report_style_for(FILE *out, int json)
{
    if (json)
        return CO_REPORT_JSON;
    return isatty(fileno(out)) ? CO_REPORT_TTY : CO_REPORT_LINES;
}

void co_reporter_init(co_reporter *r, co_report_style style, FILE *out, uint64_t max_evals,
                      double time_limit_s)
{
    memset(r, 0, sizeof *r);
    r->style = style;
    r->out = out;
    r->summary_out = style == CO_REPORT_JSON ? out : stdout;
    r->max_evals = max_evals;
    r->time_limit_s = time_limit_s;
    r->last_report_s = -1.0;
    r->start_evals = UINT64_MAX;
}

void co_json_end_with_renderer(FILE *fp, const char *renderer)
{
    fputs(", \"renderer\": ", fp);
    co_json_string(fp, renderer);
    fputs("}\n", fp);
}

static double relative(const lm_progress *p)
{
    return p->energy_start > 0 ? (double)p->energy / (double)p->energy_start : 1.0;
}

/* Evaluations per second in this process, and the ETA (< 0 when unbounded or unknown). */
static double rate_of(const co_reporter *r, const lm_progress *p, double elapsed_s)
{
    if (r->start_evals == UINT64_MAX || elapsed_s <= 0 || p->evals < r->start_evals)
        return 0.0;
    return (double)(p->evals - r->start_evals) / elapsed_s;
}

static double eta_of(const co_reporter *r, const lm_progress *p, double elapsed_s, double rate)
{
    double eta = -1.0;
    if (r->max_evals && rate > 0)
        eta = p->evals >= r->max_evals ? 0.0 : (double)(r->max_evals - p->evals) / rate;
    if (r->time_limit_s > 0) {
        double left = r->time_limit_s > elapsed_s ? r->time_limit_s - elapsed_s : 0.0;
        if (eta < 0 || left < eta)
            eta = left;
    }
    return eta;
}

static void json_counts(FILE *fp, const char *name, const uint64_t *counts)
{
    fprintf(fp, "\"%s\":{", name);
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        fprintf(fp, "%s\"%s\":%" PRIu64, k ? "," : "", co_report_move_name((lm_move_kind)k),
                counts[k]);
    fputc('}', fp);
}

void co_reporter_set_workers(co_reporter *r, const co_worker_report *w, uint32_t n)
{
    r->workers = w;
    r->n_workers = n;
}

/* ,"workers":[...] */
static void json_workers(FILE *fp, const co_reporter *r)
{
    if (!r->n_workers)
        return;
    fputs(",\"workers\":[", fp);
    for (uint32_t i = 0; i < r->n_workers; i++) {
        const co_worker_report *w = &r->workers[i];
        fprintf(fp, "%s{\"id\":%" PRIu32 ",\"host\":", i ? "," : "", w->id);
        co_json_string(fp, w->host);
        fprintf(fp, ",\"pid\":%" PRIu32 ",\"device\":", w->pid);
        co_json_string(fp, w->device);
        fprintf(fp,
                ",\"views\":[%" PRIu32 ",%" PRIu32 "],\"views_stride\":%" PRIu32
                ",\"evals\":%" PRIu64
                ",\"evals_per_s\":%.1f,\"busy\":%.3f,\"busy_loop\":%.3f,\"last_heard_s\":%.2f,"
                "\"lost\":%s}",
                w->first, w->count, w->stride ? w->stride : 1, w->evals, w->evals_per_s, w->busy,
                w->busy_loop, w->heard_s, w->lost ? "true" : "false");
    }
    fputc(']', fp);
}

void co_reporter_set_validation(co_reporter *r, const co_validation_report *v)
{
    r->val = *v;
}

static double val_rel(const co_validation_report *v, int64_t e)
{
    return v->first > 0 ? (double)e / (double)v->first : 1.0;
}

/* ,"validation":E,... (nothing for a job without validation) */
static void json_validation(FILE *fp, const co_reporter *r, int summary)
{
    const co_validation_report *v = &r->val;
    if (!v->on)
        return;
    fprintf(fp,
            ",\"validation\":%" PRId64 ",\"validation_rel\":%.6f,\"validation_best\":%" PRId64
            ",\"validation_best_rel\":%.6f,\"validation_best_evals\":%" PRIu64,
            v->energy, val_rel(v, v->energy), v->best, val_rel(v, v->best), v->best_evals);
    if (summary)
        fprintf(fp,
                ",\"validation_start\":%" PRId64 ",\"validation_checks\":%" PRIu32
                ",\"training_views_epoch\":%" PRIu32,
                v->first, v->checks, v->epoch);
}

static uint32_t alive_workers(const co_reporter *r)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < r->n_workers; i++)
        n += !r->workers[i].lost;
    return n;
}

static void json_progress(const co_reporter *r, const lm_progress *p, double elapsed_s, double rate,
                          double eta)
{
    FILE *fp = r->out;
    fprintf(fp,
            "{\"type\":\"progress\",\"elapsed_s\":%.3f,\"evals\":%" PRIu64
            ",\"evals_per_s\":%.1f,\"iterations\":%" PRIu64 ",\"energy_start\":%" PRId64
            ",\"energy\":%" PRId64 ",\"energy_rel\":%.6f,",
            elapsed_s, p->evals, rate, p->iterations, p->energy_start, p->energy, relative(p));
    json_counts(fp, "accepted", p->accepted);
    fputc(',', fp);
    json_counts(fp, "attempted", p->attempted);
    fprintf(fp, ",\"verts\":%" PRIu32 ",\"tris\":%" PRIu32 ",\"eta_s\":", p->live_verts,
            p->live_tris);
    if (eta >= 0)
        fprintf(fp, "%.1f", eta);
    else
        fputs("null", fp);
    json_validation(fp, r, 0);
    json_workers(fp, r);
    fputs("}\n", fp);
    fflush(fp);
}

/* Replace the TTY line with `text`, cut to the terminal's width so that '\r' can rewrite it. */
static void tty_line(co_reporter *r, const char *text)
{
    int cols = co_meter_columns(r->out) - 1;
    fprintf(r->out, "\r\033[K%.*s", cols, text);
    r->line_open = 1;
    fflush(r->out);
}

static void human_progress(co_reporter *r, const lm_progress *p, double rate, double eta)
{
    char line[512];
    size_t n = 0;
#define CO_APPEND(...)                                                                             \
    if (n < sizeof line)                                                                           \
    n += (size_t)snprintf(line + n, sizeof line - n, __VA_ARGS__)
    CO_APPEND("energy %.2f%% | %" PRIu64, 100.0 * relative(p), p->evals);
    if (r->max_evals)
        CO_APPEND("/%" PRIu64, r->max_evals);
    CO_APPEND(" evals %.0f/s", rate);
    if (eta >= 0)
        CO_APPEND(" | ETA %d:%02d", (int)(eta / 60), (int)eta % 60);
    CO_APPEND(" | accepted:");
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        CO_APPEND(" %s %" PRIu64, co_report_move_name((lm_move_kind)k), p->accepted[k]);
    if (r->val.on)
        CO_APPEND(" | validation %.2f%% (best %.2f%%)", 100.0 * val_rel(&r->val, r->val.energy),
                  100.0 * val_rel(&r->val, r->val.best));
    CO_APPEND(" | %" PRIu32 " verts", p->live_verts);
    if (r->n_workers)
        CO_APPEND(" | %" PRIu32 " worker%s", alive_workers(r), alive_workers(r) == 1 ? "" : "s");
#undef CO_APPEND
    if (r->style == CO_REPORT_TTY) {
        tty_line(r, line);
    } else {
        fprintf(r->out, "%s\n", line);
        fflush(r->out);
    }
}

void co_reporter_update(co_reporter *r, const lm_progress *p, double elapsed_s, int force)
{
    if (r->start_evals == UINT64_MAX)
        r->start_evals = p->evals;
    if (r->style == CO_REPORT_QUIET)
        return;
    if (r->last_report_s >= 0 &&
        (force ? p->evals == r->last_evals
               : elapsed_s - r->last_report_s < co_report_period[r->style]))
        return;
    r->last_report_s = elapsed_s;
    r->last_evals = p->evals;
    double rate = rate_of(r, p, elapsed_s);
    double eta = eta_of(r, p, elapsed_s, rate);
    if (r->style == CO_REPORT_JSON)
        json_progress(r, p, elapsed_s, rate, eta);
    else
        human_progress(r, p, rate, eta);
}

void co_reporter_end_line(co_reporter *r)
{
    if (r->line_open && r->out) {
        fputc('\n', r->out);
        r->line_open = 0;
    }
}

void co_reporter_abandon_line(co_reporter *r)
{
    if (r->line_open && r->out) {
        fputs("\r\033[K", r->out);
        fflush(r->out);
        r->line_open = 0;
    }
}

void co_reporter_note(co_reporter *r, const char *event, const char *detail)
{
    if (r->style == CO_REPORT_JSON) {
        fputs("{\"type\":\"event\",\"event\":", r->out);
        co_json_string(r->out, event);
        fputs(",\"detail\":", r->out);
        co_json_string(r->out, detail);
        fputs("}\n", r->out);
        fflush(r->out);
    } else if (strcmp(event, "warning") == 0) {
        co_reporter_end_line(r);
        lm_warn("%s", detail);
    } else if (r->style == CO_REPORT_TTY) {
        char line[512];
        snprintf(line, sizeof line, "%s: %s", event, detail);
        tty_line(r, line);
    } else {
        lm_info("%s: %s", event, detail);
    }
}

/* --lanes remote: what the groups sent to the workers (nothing without groups). */
static void json_lanes(FILE *fp, const co_lane_stats *l)
{
    if (!l->groups)
        return;
    fprintf(fp,
            ",\"lanes_remote\":{\"groups\":%" PRIu64 ",\"starts_full\":%" PRIu64
            ",\"starts_delta\":%" PRIu64 ",\"start_bytes\":%" PRIu64
            ",\"start_record_bytes\":%" PRIu64 ",\"queues_full\":%" PRIu64
            ",\"queues_delta\":%" PRIu64 ",\"queue_bytes\":%" PRIu64
            ",\"queue_record_bytes\":%" PRIu64 ",\"request_bytes\":%" PRIu64 ",\"audits\":%" PRIu64
            ",\"audit_mismatches\":%" PRIu64 ",\"audit_fenced\":%" PRIu64
            ",\"audits_skipped\":%" PRIu64 "}",
            l->groups, l->starts_full, l->starts_delta, l->start_bytes, l->start_record_bytes,
            l->queues_full, l->queues_delta, l->queue_bytes, l->queue_record_bytes,
            l->request_bytes, l->audits, l->audit_mismatches, l->audit_fenced, l->audits_skipped);
}

static void json_summary(FILE *fp, const co_reporter *r, const co_job_summary *s)
{
    const lm_progress *p = &s->progress;
    double run_evals = (double)(p->evals - s->resumed_from_evals);
    fprintf(fp,
            "{\"type\":\"summary\",\"energy_start\":%" PRId64 ",\"energy_end\":%" PRId64
            ",\"energy_rel\":%.6f,\"evals\":%" PRIu64 ",\"resumed_from_evals\":%" PRIu64
            ",\"iterations\":%" PRIu64 ",\"wall_s\":%.3f,\"optimize_s\":%.3f,\"evals_per_s\":%.1f"
            ",\"loop_cpu_s\":%.3f,\"loop_cpu_us_per_eval\":%.1f,\"stop_reason\":",
            p->energy_start, p->energy, relative(p), p->evals, s->resumed_from_evals, p->iterations,
            s->wall_s, s->optimize_s, s->optimize_s > 0 ? run_evals / s->optimize_s : 0.0,
            s->loop_cpu_s, run_evals > 0 ? 1e6 * s->loop_cpu_s / run_evals : 0.0);
    co_json_string(fp, s->stop_reason);
    fputs(",\"output\":", fp);
    if (s->output_path)
        co_json_string(fp, s->output_path);
    else
        fputs("null", fp);
    fputs(",\"checkpoint\":", fp);
    if (s->checkpoint_path)
        co_json_string(fp, s->checkpoint_path);
    else
        fputs("null", fp);
    fputs(",\"renderer\":", fp);
    co_json_string(fp, s->renderer);
    fprintf(fp,
            ",\"geometric_start\":%" PRId64 ",\"geometric_end\":%" PRId64
            ",\"geometric_by_workers\":%.3f,\"verts\":%" PRIu32 ",\"tris\":%" PRIu32 ",",
            p->geometric_start, p->geometric, p->geometric_by_workers, p->live_verts, p->live_tris);
    json_counts(fp, "accepted", p->accepted);
    fputc(',', fp);
    json_counts(fp, "attempted", p->attempted);
    json_validation(fp, r, 1);
    json_lanes(fp, &s->lanes);
    json_workers(fp, r);
    fputs("}\n", fp);
}

/* One line per worker: what it served and how busy it was. */
static void human_workers(FILE *fp, const co_reporter *r)
{
    for (uint32_t i = 0; i < r->n_workers; i++) {
        const co_worker_report *w = &r->workers[i];
        char views[48];
        lm_view_deal_text((lm_view_deal){w->first, w->count, w->stride}, views, sizeof views);
        fprintf(fp,
                "worker %" PRIu32 ": %s pid %" PRIu32 ", views %s, %" PRIu64
                " evaluations, %.0f%% busy (%.0f%% of the optimisation)%s\n",
                w->id, w->host, w->pid, views, w->evals, 100.0 * w->busy, 100.0 * w->busy_loop,
                w->lost ? " (lost)" : "");
    }
}

static void human_summary(FILE *fp, const co_reporter *r, const co_job_summary *s)
{
    const lm_progress *p = &s->progress;
    uint64_t run_evals = p->evals - s->resumed_from_evals;
    fprintf(fp, "energy %" PRId64 " -> %" PRId64 " (%.2f%% of start) after %" PRIu64 " evaluations",
            p->energy_start, p->energy, 100.0 * relative(p), p->evals);
    if (s->resumed_from_evals)
        fprintf(fp, " (%" PRIu64 " after resuming)", run_evals);
    fprintf(fp, ", %.1f s (%.1f s optimising, %.0f evals/s); stopped by %s\n", s->wall_s,
            s->optimize_s, s->optimize_s > 0 ? (double)run_evals / s->optimize_s : 0.0,
            s->stop_reason);
    if (s->workers && run_evals)
        fprintf(fp, "coordinator: %.1f CPU seconds in the loop, %.0f us per evaluation\n",
                s->loop_cpu_s, 1e6 * s->loop_cpu_s / (double)run_evals);
    fputs("accepted moves:", fp);
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        fprintf(fp, " %s %" PRIu64 "/%" PRIu64 "%s", co_report_move_name((lm_move_kind)k),
                p->accepted[k], p->attempted[k], k + 1 < LM_MOVE_KINDS ? "," : "");
    fprintf(fp, "; %" PRIu32 " vertices, %" PRIu32 " triangles\n", p->live_verts, p->live_tris);
    human_workers(fp, r);
    if (r->val.on)
        fprintf(fp,
                "validation: %.2f%% of the start at the end, best %.2f%% at %" PRIu64
                " evaluations (the output; %" PRIu32 " checks, %" PRIu32 " new training views)\n",
                100.0 * val_rel(&r->val, r->val.energy), 100.0 * val_rel(&r->val, r->val.best),
                r->val.best_evals, r->val.checks, r->val.epoch);
    if (s->output_path)
        fprintf(fp, "wrote %s (renderer: %s)\n", s->output_path, s->renderer);
    else
        fprintf(fp, "suspended: no output written; the run goes on with --resume %s\n",
                s->checkpoint_path);
}

void co_reporter_summary(co_reporter *r, const co_job_summary *s)
{
    if (r->style == CO_REPORT_QUIET)
        return;
    co_reporter_end_line(r);
    if (r->style == CO_REPORT_JSON)
        json_summary(r->summary_out, r, s);
    else
        human_summary(r->summary_out, r, s);
    fflush(r->summary_out);
}
