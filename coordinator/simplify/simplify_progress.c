/* coordinator/simplify/simplify_progress.c — the simplification's progress lines
 * (simplify_progress.h). */
#include "coordinator/simplify/simplify_progress.h"

#include <stdio.h>

#include "coordinator/quality/view_setup.h"

void co_simplify_meter_phase(co_simplify_meter *m, co_simplify_progress style)
{
    m->style = style;
    m->t0 = co_now_s();
    m->t_last = m->t0;
}

/* "42 s", "4 min 12 s" or "1 h 03 min". */
static void say_duration(char *out, size_t cap, double s)
{
    unsigned long t = s > 0 ? (unsigned long)(s + 0.5) : 0;
    if (t < 60)
        snprintf(out, cap, "%lu s", t);
    else if (t < 3600)
        snprintf(out, cap, "%lu min %02lu s", t / 60, t % 60);
    else
        snprintf(out, cap, "%lu h %02lu min", t / 3600, t / 60 % 60);
}

void co_simplify_meter_show(co_simplify_meter *m, const char *what, uint64_t done, uint64_t total,
                            int force)
{
    if (m->style == CO_SIMPLIFY_PROGRESS_NONE)
        return;
    double t = co_now_s();
    double every = m->style == CO_SIMPLIFY_PROGRESS_TTY ? CO_SIMPLIFY_PROGRESS_TTY_S
                                                        : CO_SIMPLIFY_PROGRESS_LINES_S;
    if (!force && t - m->t_last < every)
        return;
    m->t_last = t;
    char line[256];
    int n = snprintf(line, sizeof line, "lumesh simplify: %s", what);
    double spent = t - m->t0, rate = spent > 0 ? (double)done / spent : 0;
    if (total && n > 0 && (size_t)n < sizeof line) {
        char left[32] = "?";
        if (rate > 0 && done <= total)
            say_duration(left, sizeof left, (double)(total - done) / rate);
        snprintf(line + n, sizeof line - (size_t)n, " %llu of %llu (%.0f%%), %.0f/s, %s to go",
                 (unsigned long long)done, (unsigned long long)total,
                 100.0 * (double)done / (double)total, rate, left);
    }
    if (m->style == CO_SIMPLIFY_PROGRESS_TTY) {
        fprintf(stderr, "\r%-79s", line);
        m->line_open = 1;
    } else {
        fprintf(stderr, "%s\n", line);
    }
    fflush(stderr);
}

void co_simplify_meter_close(co_simplify_meter *m)
{
    if (m->line_open)
        fprintf(stderr, "\r%79s\r", "");
    m->line_open = 0;
}
