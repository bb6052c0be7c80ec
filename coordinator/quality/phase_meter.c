/* coordinator/quality/phase_meter.c — a phase's progress lines and records, and the heartbeat
 * that keeps them coming (phase_meter.h). */
#include "coordinator/quality/phase_meter.h"

#include <signal.h>
#include <stdarg.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>

#include "coordinator/quality/json_text.h"
#include "coordinator/quality/view_setup.h"

static double period_of(co_meter_style s)
{
    return s == CO_METER_TTY    ? CO_METER_TTY_S
           : s == CO_METER_JSON ? CO_METER_JSON_S
                                : CO_METER_LINES_S;
}

void co_meter_duration(char *out, size_t cap, double s)
{
    unsigned long t = s > 0 ? (unsigned long)(s + 0.5) : 0;
    if (t < 60)
        snprintf(out, cap, "%lu s", t);
    else if (t < 3600)
        snprintf(out, cap, "%lu min %02lu s", t / 60, t % 60);
    else
        snprintf(out, cap, "%lu h %02lu min", t / 3600, t / 60 % 60);
}

int co_meter_columns(FILE *fp)
{
    struct winsize ws;
    if (ioctl(fileno(fp), TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 20)
        return ws.ws_col;
    return 80;
}

/* Seconds left at the phase's rate so far, < 0 when unknown. */
static double seconds_left(const co_meter *m, double rate)
{
    return m->total && rate > 0 && m->done <= m->total ? (double)(m->total - m->done) / rate : -1;
}

static void emit_json(co_meter *m, double spent, double rate)
{
    FILE *fp = m->out;
    char name[160];
    snprintf(name, sizeof name, "%s%s%s", m->stage, m->stage[0] ? ": " : "", m->phase);
    fputs("{\"type\":\"phase\",\"phase\":", fp);
    co_json_string(fp, name);
    fputs(",\"detail\":", fp);
    co_json_string(fp, m->detail);
    fprintf(fp, ",\"elapsed_s\":%.3f,\"done\":%llu,\"total\":", spent, (unsigned long long)m->done);
    if (m->total)
        fprintf(fp, "%llu", (unsigned long long)m->total);
    else
        fputs("null", fp);
    fprintf(fp, ",\"rate\":%.1f,\"eta_s\":", rate);
    double left = seconds_left(m, rate);
    if (left >= 0)
        fprintf(fp, "%.1f}\n", left);
    else
        fputs("null}\n", fp);
}

static void emit_human(co_meter *m, double spent, double rate)
{
    char line[320];
    size_t n = 0;
#define CO_APPEND(...)                                                                             \
    if (n < sizeof line)                                                                           \
    n += (size_t)snprintf(line + n, sizeof line - n, __VA_ARGS__)
    CO_APPEND("%s: %s%s%s", m->who, m->stage, m->stage[0] ? ": " : "", m->phase);
    if (m->detail[0])
        CO_APPEND(", %s", m->detail);
    char left[32] = "?";
    double s = seconds_left(m, rate);
    if (s >= 0)
        co_meter_duration(left, sizeof left, s);
    if (m->total) {
        CO_APPEND(", %llu of %llu (%.0f%%), %.0f/s, %s to go", (unsigned long long)m->done,
                  (unsigned long long)m->total, 100.0 * (double)m->done / (double)m->total, rate,
                  left);
    } else {
        co_meter_duration(left, sizeof left, spent);
        CO_APPEND(", %s so far", left);
    }
#undef CO_APPEND
    if (m->style == CO_METER_TTY) {
        fprintf(m->out, "\r\033[K%.*s", co_meter_columns(m->out) - 1, line);
        m->line_open = 1;
    } else {
        fprintf(m->out, "%s\n", line);
    }
}

/* Show the phase's state now (the lock held). */
static void emit(co_meter *m, double t)
{
    m->t_last = t;
    double spent = t - m->t0, rate = spent > 0 ? (double)m->done / spent : 0;
    if (m->style == CO_METER_JSON)
        emit_json(m, spent, rate);
    else
        emit_human(m, spent, rate);
    fflush(m->out);
}

/* When the heartbeat speaks: in a log a tick before the period, so that no gap between lines
 * exceeds it. */
static double beat_due(co_meter_style s)
{
    return s == CO_METER_LINES ? CO_METER_LINES_S - CO_METER_TICK_S : period_of(s);
}

/* The heartbeat: the last news again when the work has been silent for a period. */
static void *heartbeat(void *arg)
{
    co_meter *m = arg;
    pthread_mutex_lock(&m->lock);
    while (!m->stopping) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += (long)(CO_METER_TICK_S * 1e9);
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        pthread_cond_timedwait(&m->wake, &m->lock, &until);
        double t = co_now_s();
        if (!m->stopping && m->phase[0] && t - m->t_last >= beat_due(m->style))
            emit(m, t);
    }
    pthread_mutex_unlock(&m->lock);
    return NULL;
}

void co_meter_init(co_meter *m, const char *who, co_meter_style style, FILE *out)
{
    memset(m, 0, sizeof *m);
    m->style = style;
    m->out = out ? out : stderr;
    snprintf(m->who, sizeof m->who, "%s", who);
    pthread_mutex_init(&m->lock, NULL);
    pthread_cond_init(&m->wake, NULL);
    m->t_last = co_now_s();
    if (style == CO_METER_NONE)
        return;
    /* Signals go to the threads that do the work (they look at the interrupt flags), never to
       this one. */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    m->beating = pthread_create(&m->beat, NULL, heartbeat, m) == 0;
    pthread_sigmask(SIG_SETMASK, &old, NULL);
}

void co_meter_destroy(co_meter *m)
{
    co_meter_end(m);
    if (m->beating) {
        pthread_mutex_lock(&m->lock);
        m->stopping = 1;
        pthread_cond_signal(&m->wake);
        pthread_mutex_unlock(&m->lock);
        pthread_join(m->beat, NULL);
        m->beating = 0;
    }
    pthread_cond_destroy(&m->wake);
    pthread_mutex_destroy(&m->lock);
}

void co_meter_stage(co_meter *m, const char *stage)
{
    pthread_mutex_lock(&m->lock);
    snprintf(m->stage, sizeof m->stage, "%s", stage ? stage : "");
    pthread_mutex_unlock(&m->lock);
}

void co_meter_phase(co_meter *m, const char *fmt, ...)
{
    if (m->style == CO_METER_NONE)
        return;
    pthread_mutex_lock(&m->lock);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(m->phase, sizeof m->phase, fmt, ap);
    va_end(ap);
    m->detail[0] = '\0';
    m->done = m->total = 0;
    m->t0 = co_now_s();
    /* In a log the period counts from the meter's last line, whichever phase it was of, so that
       short phases in a row are not silent together for longer. */
    if (m->style != CO_METER_LINES)
        emit(m, m->t0);
    pthread_mutex_unlock(&m->lock);
}

void co_meter_show(co_meter *m, const char *detail, uint64_t done, uint64_t total, int force)
{
    if (m->style == CO_METER_NONE)
        return;
    pthread_mutex_lock(&m->lock);
    snprintf(m->detail, sizeof m->detail, "%s", detail ? detail : "");
    m->done = done;
    m->total = total;
    double t = co_now_s();
    if (m->phase[0] && (force || t - m->t_last >= period_of(m->style)))
        emit(m, t);
    pthread_mutex_unlock(&m->lock);
}

void co_meter_heard(co_meter *m, double ago_s)
{
    pthread_mutex_lock(&m->lock);
    double t = co_now_s() - ago_s;
    if (t > m->t_last)
        m->t_last = t;
    pthread_mutex_unlock(&m->lock);
}

void co_meter_end(co_meter *m)
{
    if (m->style == CO_METER_NONE)
        return;
    pthread_mutex_lock(&m->lock);
    m->phase[0] = '\0';
    if (m->line_open) {
        fputs("\r\033[K", m->out);
        fflush(m->out);
    }
    m->line_open = 0;
    pthread_mutex_unlock(&m->lock);
}
