/* coordinator/job/preset.h — `optimize --quality draft|good|best`: deterministic presets of a
 * job's evaluations, views, image size and view schedule. They fill only the fields a job leaves
 * at 0 (explicit flags win), in resolve_options (job.c), the one place a job's defaults are
 * resolved; `good` is those defaults exactly. Why these values: coordinator/OPTIMIZER.md, "View
 * schedule (issue 38)". */
#ifndef LM_COORDINATOR_JOB_PRESET_H
#define LM_COORDINATOR_JOB_PRESET_H

#include <stdint.h>

#include "common/error.h"
#include "coordinator/job/schedule.h"

typedef enum co_job_quality {
    CO_QUALITY_DEFAULT = 0, /* no --quality: the job's defaults (as good) */
    CO_QUALITY_DRAFT,
    CO_QUALITY_GOOD,
    CO_QUALITY_BEST,
} co_job_quality;

typedef struct co_job_preset {
    const char *name;
    uint64_t evals;
    uint32_t views;
    int size;
    co_view_schedule schedule;
} co_job_preset;

/* "draft", "good" or "best" into *out; LM_E_INVALID naming the word otherwise. */
lm_status co_job_quality_parse(const char *name, co_job_quality *out);

/* The preset of q (CO_QUALITY_DEFAULT: good's). */
const co_job_preset *co_job_preset_of(co_job_quality q);

#endif
