/* coordinator/job/schedule.h — a job's view schedule (`optimize --view-schedule grow`): the
 * training views' count and image size grow as the run goes, in CO_SCHEDULE_STAGES stages that
 * begin at fixed fractions of the job's evaluation budget, each stage new views of the job's
 * distribution (the next rotation stream, view_turn.h) with more views and pixels than the last.
 * Every number is a function of (budget, views, size, stage) alone: the same for any number of
 * workers and for any timing, and the stage in force is saved in the job's checkpoint. "fixed"
 * (the default) keeps the job's views all along. Why these constants: coordinator/OPTIMIZER.md,
 * "View schedule (issue 38)". */
#ifndef LM_COORDINATOR_JOB_SCHEDULE_H
#define LM_COORDINATOR_JOB_SCHEDULE_H

#include <stdint.h>

#include "common/error.h"

typedef enum co_view_schedule {
    CO_SCHEDULE_DEFAULT = 0, /* an option left out: CO_JOB_DEFAULT_SCHEDULE */
    CO_SCHEDULE_FIXED,       /* the job's views all along */
    CO_SCHEDULE_GROW,        /* more views and pixels in each stage */
} co_view_schedule;

#define CO_SCHEDULE_STAGES 3u
/* Stage-to-stage growth, per mille of the job's --views and --size in stage k (stage 0: 1000). */
#define CO_SCHEDULE_VIEWS_PM                                                                       \
    {                                                                                              \
        1000u, 1500u, 2250u                                                                        \
    }
#define CO_SCHEDULE_SIZE_PM                                                                        \
    {                                                                                              \
        1000u, 1120u, 1250u                                                                        \
    }
/* The stream of view_turn.h that stage k's views are turned by: apart from the plateaus' epochs. */
#define CO_SCHEDULE_TURN_STREAM(k) ((uint32_t)(k) << 16)

/* "fixed" or "grow" into *out; LM_E_INVALID naming the word otherwise. */
lm_status co_schedule_parse(const char *name, co_view_schedule *out);
const char *co_schedule_name(co_view_schedule s);

/* The stage in force after `evals` evaluations of a `budget` (0 with the fixed schedule). */
uint32_t co_schedule_stage(co_view_schedule s, uint64_t evals, uint64_t budget);

/* The evaluation count at which the stage after `stage` begins (UINT64_MAX: none). */
uint64_t co_schedule_next(co_view_schedule s, uint32_t stage, uint64_t budget);

/* Stage `stage`'s view count and image size from the job's `views` and `size` (capped at
 * max_views and max_size). */
void co_schedule_views(co_view_schedule s, uint32_t stage, uint32_t views, int size,
                       uint32_t max_views, int max_size, uint32_t *out_views, int *out_size);

#endif
