/* coordinator/job/preset.c — the --quality presets' table (preset.h). */
#include "coordinator/job/preset.h"

#include <string.h>

#include "coordinator/job/job.h"

static const co_job_preset presets[] = {
    [CO_QUALITY_DRAFT] = {"draft", CO_JOB_DRAFT_EVALS, CO_JOB_DEFAULT_VIEWS, CO_JOB_DEFAULT_SIZE,
                          CO_SCHEDULE_FIXED},
    [CO_QUALITY_GOOD] = {"good", CO_JOB_DEFAULT_EVALS, CO_JOB_DEFAULT_VIEWS, CO_JOB_DEFAULT_SIZE,
                         CO_JOB_DEFAULT_SCHEDULE},
    [CO_QUALITY_BEST] = {"best", CO_JOB_BEST_EVALS, CO_JOB_DEFAULT_VIEWS, CO_JOB_DEFAULT_SIZE,
                         CO_JOB_BEST_SCHEDULE},
};

lm_status co_job_quality_parse(const char *name, co_job_quality *out)
{
    for (int q = CO_QUALITY_DRAFT; q <= CO_QUALITY_BEST; q++)
        if (name && strcmp(name, presets[q].name) == 0) {
            *out = (co_job_quality)q;
            return LM_OK;
        }
    return lm_fail(LM_E_INVALID, "--quality: unknown preset '%s' (use draft, good or best)",
                   name ? name : "");
}

const co_job_preset *co_job_preset_of(co_job_quality q)
{
    return &presets[q >= CO_QUALITY_DRAFT && q <= CO_QUALITY_BEST ? q : CO_QUALITY_GOOD];
}
