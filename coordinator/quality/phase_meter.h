/* coordinator/quality/phase_meter.h — telling the user how a long phase of a command is going
 * (loading the model, QEM, rendering the target images, pricing every edge, the collapses,
 * measuring levels...): its name, how far, how fast and the time left. On a terminal one line on
 * stderr rewritten at most twice a second; in a log a plain line every 5 s; in JSON style a
 * "phase" record (at the phase's start, then at most every second) on the record stream. The
 * work says when it has news; a heartbeat thread repeats the last news when the work is silent
 * for longer (a blocking step with no counts: then the seconds so far), so that no phase goes
 * quiet for more than the period. */
#ifndef LM_COORDINATOR_QUALITY_PHASE_METER_H
#define LM_COORDINATOR_QUALITY_PHASE_METER_H

#include <pthread.h>
#include <stdint.h>
#include <stdio.h>

typedef enum co_meter_style {
    CO_METER_NONE = 0, /* nothing */
    CO_METER_TTY,      /* one line rewritten with '\r' every CO_METER_TTY_S */
    CO_METER_LINES,    /* a plain line every CO_METER_LINES_S */
    CO_METER_JSON,     /* a "phase" record at the start, then every CO_METER_JSON_S */
} co_meter_style;

#define CO_METER_TTY_S 0.5
#define CO_METER_LINES_S 5.0
#define CO_METER_JSON_S 1.0
#define CO_METER_TICK_S 0.25 /* how often the heartbeat looks */

typedef struct co_meter {
    co_meter_style style;
    FILE *out;       /* stderr; JSON style: the record stream */
    char who[32];    /* "lumesh optimize" */
    char stage[32];  /* "" or a stage the phases belong to ("start") */
    char phase[96];  /* "" between phases */
    char detail[64]; /* the latest news beside the counts ("24465 vertices") */
    uint64_t done, total;
    double t0;     /* when the phase began (the rate and the time left count from here) */
    double t_last; /* when a line was last shown */
    int line_open; /* a terminal line is showing */
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t beat;
    int beating, stopping;
} co_meter;

/* A meter for the command `who`; style NONE makes it silent (and starts no thread). */
void co_meter_init(co_meter *m, const char *who, co_meter_style style, FILE *out);
/* End the phase that is open and stop the heartbeat. */
void co_meter_destroy(co_meter *m);

/* The stage that names the next phases ("" or NULL: none). */
void co_meter_stage(co_meter *m, const char *stage);
/* A new phase begins now, named by the format (e.g. "QEM to %u vertices"). */
void co_meter_phase(co_meter *m, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* `done` of `total` units of the phase, with `detail` (NULL: none): shown when a line is due, or at
 * once with force. total 0: no share and no time left. */
void co_meter_show(co_meter *m, const char *detail, uint64_t done, uint64_t total, int force);
/* Other output was shown `ago_s` seconds ago: in a log the next line is due a period after it. */
void co_meter_heard(co_meter *m, double ago_s);
/* The phase is over: a terminal line that is showing is cleared (before other output). */
void co_meter_end(co_meter *m);

/* Columns of the terminal behind `fp` (80 if unknown). */
int co_meter_columns(FILE *fp);

/* "42 s", "4 min 12 s" or "1 h 03 min". */
void co_meter_duration(char *out, size_t cap, double s);

#endif
