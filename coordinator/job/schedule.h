/* coordinator/job/schedule.h — a job's view schedule (`optimize --view-schedule grow|extend`):
 * the training views' count and image size grow as the run goes, in stages, each stage new views
 * of the job's distribution (the next rotation stream, view_turn.h) with more views and pixels
 * than the last. "grow": CO_SCHEDULE_STAGES stages that begin at fixed fractions of the job's
 * evaluation budget. "extend": CO_SCHEDULE_EXTEND_STAGES stages that begin at fixed evaluation
 * counts, the first at CO_SCHEDULE_EXTEND_BASE (the default budget) and each later one at twice
 * the last, so a run with a larger budget passes through every state of a run with a smaller one
 * (a longer run extends a shorter one; `--resume` with a larger --evals continues it). Every number
 * is a function of (schedule, budget, views, size, stage) alone: the same for any number of
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
    CO_SCHEDULE_GROW,        /* more views and pixels in each stage, at fractions of the budget */
    CO_SCHEDULE_EXTEND,      /* more views and pixels past fixed evaluation counts */
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
/* extend: stage k >= 1 begins at CO_SCHEDULE_EXTEND_BASE << (k - 1) evaluations (100k, 200k,
 * 400k, 800k: runs up to the default budget are the fixed schedule's, byte for byte); views per
 * mille of the job's as grow's and then on by 1.5x a stage, the image size grow's and then held
 * (pixels per view cost more than views: a view adds a direction, a pixel only resolution). */
#define CO_SCHEDULE_EXTEND_STAGES 5u
#define CO_SCHEDULE_EXTEND_BASE 100000u
#define CO_SCHEDULE_EXTEND_VIEWS_PM                                                                \
    {                                                                                              \
        1000u, 1500u, 2250u, 3375u, 5063u                                                          \
    }
#define CO_SCHEDULE_EXTEND_SIZE_PM                                                                 \
    {                                                                                              \
        1000u, 1120u, 1250u, 1250u, 1250u                                                          \
    }
/* The most stages any schedule has (a checkpoint's stage is below co_schedule_stages). */
#define CO_SCHEDULE_MAX_STAGES CO_SCHEDULE_EXTEND_STAGES

/* The stream of view_turn.h that stage k's views are turned by: apart from the plateaus' epochs. */
#define CO_SCHEDULE_TURN_STREAM(k) ((uint32_t)(k) << 16)

/* "fixed", "grow" or "extend" into *out; LM_E_INVALID naming the word otherwise. */
lm_status co_schedule_parse(const char *name, co_view_schedule *out);
const char *co_schedule_name(co_view_schedule s);

/* How many stages schedule s has (1 for fixed). */
uint32_t co_schedule_stages(co_view_schedule s);

/* The stage in force after `evals` evaluations of a `budget` (0 with the fixed schedule; extend
 * ignores the budget). */
uint32_t co_schedule_stage(co_view_schedule s, uint64_t evals, uint64_t budget);

/* The evaluation count at which the stage after `stage` begins (UINT64_MAX: none). */
uint64_t co_schedule_next(co_view_schedule s, uint32_t stage, uint64_t budget);

/* Stage `stage`'s view count and image size from the job's `views` and `size` (capped at
 * max_views and max_size). */
void co_schedule_views(co_view_schedule s, uint32_t stage, uint32_t views, int size,
                       uint32_t max_views, int max_size, uint32_t *out_views, int *out_size);

#endif
