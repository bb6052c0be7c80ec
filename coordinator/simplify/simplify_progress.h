/* coordinator/simplify/simplify_progress.h — how the image-driven simplification tells the user how
 * it is going, phase by phase (pricing every edge, then the collapses): how far, how fast, and the
 * time left, on stderr. On a terminal one line rewritten at most twice a second; in a log a plain
 * line every 5 s. It only formats: the simplification says when it has news. */
#ifndef LM_COORDINATOR_SIMPLIFY_SIMPLIFY_PROGRESS_H
#define LM_COORDINATOR_SIMPLIFY_SIMPLIFY_PROGRESS_H

#include <stdint.h>

typedef enum co_simplify_progress {
    CO_SIMPLIFY_PROGRESS_NONE = 0, /* nothing */
    CO_SIMPLIFY_PROGRESS_TTY,      /* one line rewritten with '\r' */
    CO_SIMPLIFY_PROGRESS_LINES,    /* a plain line every CO_SIMPLIFY_PROGRESS_LINES_S */
} co_simplify_progress;

#define CO_SIMPLIFY_PROGRESS_TTY_S 0.5
#define CO_SIMPLIFY_PROGRESS_LINES_S 5.0

typedef struct co_simplify_meter {
    co_simplify_progress style;
    double t0;     /* when the phase began */
    double t_last; /* when a line was last shown */
    int line_open; /* a terminal line is showing */
} co_simplify_meter;

/* A new phase begins now (the rate and the time left count from here). */
void co_simplify_meter_phase(co_simplify_meter *m, co_simplify_progress style);

/* `done` of `total` units of the phase, described by `what` (e.g. "pricing the edges"): shown when
 * a line is due, or at once with force. total 0: no share and no time left. */
void co_simplify_meter_show(co_simplify_meter *m, const char *what, uint64_t done, uint64_t total,
                            int force);

/* Clear a terminal line that is showing (before other output, and at the end). */
void co_simplify_meter_close(co_simplify_meter *m);

#endif
