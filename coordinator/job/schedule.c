/* coordinator/job/schedule.c — the stages of a job's view schedule (schedule.h). */
#include "coordinator/job/schedule.h"

#include <string.h>

lm_status co_schedule_parse(const char *name, co_view_schedule *out)
{
    if (name && strcmp(name, "fixed") == 0)
        *out = CO_SCHEDULE_FIXED;
    else if (name && strcmp(name, "grow") == 0)
        *out = CO_SCHEDULE_GROW;
    else if (name && strcmp(name, "extend") == 0)
        *out = CO_SCHEDULE_EXTEND;
    else
        return lm_fail(LM_E_INVALID,
                       "--view-schedule: unknown schedule '%s' (use fixed, grow or extend)",
                       name ? name : "");
    return LM_OK;
}

const char *co_schedule_name(co_view_schedule s)
{
    return s == CO_SCHEDULE_GROW ? "grow" : s == CO_SCHEDULE_EXTEND ? "extend" : "fixed";
}

uint32_t co_schedule_stages(co_view_schedule s)
{
    return s == CO_SCHEDULE_GROW     ? CO_SCHEDULE_STAGES
           : s == CO_SCHEDULE_EXTEND ? CO_SCHEDULE_EXTEND_STAGES
                                     : 1u;
}

/* Where stage k >= 1 begins: grow, k / CO_SCHEDULE_STAGES of the budget (exact integers); extend,
 * CO_SCHEDULE_EXTEND_BASE doubled k - 1 times. */
static uint64_t stage_start(co_view_schedule s, uint32_t k, uint64_t budget)
{
    if (s == CO_SCHEDULE_EXTEND)
        return (uint64_t)CO_SCHEDULE_EXTEND_BASE << (k - 1);
    return budget / CO_SCHEDULE_STAGES * k + budget % CO_SCHEDULE_STAGES * k / CO_SCHEDULE_STAGES;
}

uint32_t co_schedule_stage(co_view_schedule s, uint64_t evals, uint64_t budget)
{
    uint32_t k = 0, n = co_schedule_stages(s);
    while (k + 1 < n && evals >= stage_start(s, k + 1, budget))
        k++;
    return k;
}

uint64_t co_schedule_next(co_view_schedule s, uint32_t stage, uint64_t budget)
{
    if (stage + 1 >= co_schedule_stages(s))
        return UINT64_MAX;
    return stage_start(s, stage + 1, budget);
}

static uint64_t per_mille(uint64_t x, uint32_t pm)
{
    return (x * pm + 500) / 1000;
}

void co_schedule_views(co_view_schedule s, uint32_t stage, uint32_t views, int size,
                       uint32_t max_views, int max_size, uint32_t *out_views, int *out_size)
{
    static const uint32_t views_pm[CO_SCHEDULE_STAGES] = CO_SCHEDULE_VIEWS_PM;
    static const uint32_t size_pm[CO_SCHEDULE_STAGES] = CO_SCHEDULE_SIZE_PM;
    static const uint32_t ext_views_pm[CO_SCHEDULE_EXTEND_STAGES] = CO_SCHEDULE_EXTEND_VIEWS_PM;
    static const uint32_t ext_size_pm[CO_SCHEDULE_EXTEND_STAGES] = CO_SCHEDULE_EXTEND_SIZE_PM;
    int ext = s == CO_SCHEDULE_EXTEND;
    uint32_t k = stage < co_schedule_stages(s) ? stage : 0;
    uint64_t v = per_mille(views, ext ? ext_views_pm[k] : views_pm[k]);
    uint64_t z = per_mille((uint64_t)size, ext ? ext_size_pm[k] : size_pm[k]);
    *out_views = v > max_views ? max_views : (uint32_t)v;
    *out_size = z > (uint64_t)max_size ? max_size : (int)z;
}
