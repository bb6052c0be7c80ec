/* coordinator/geometric/run.h — `lumesh optimize --energy geometric` as a command: load the
 * original, resolve the target, make the start, optimize with progress on the phase meter, save
 * the result (and the start, if asked), report a summary (a human line or a JSON record). */
#ifndef LM_COORDINATOR_GEOMETRIC_RUN_H
#define LM_COORDINATOR_GEOMETRIC_RUN_H

#include "coordinator/geometric/geo.h"

typedef struct co_geo_run_options {
    const char *original_path, *output_path;
    const char *initial_output_path; /* also save the start here (NULL: not) */
    uint32_t target_verts;           /* 0: as the image job's default (1%, at least 100) */
    double c_rep;                    /* 0: CO_GEO_DEFAULT_C_REP */
    uint32_t start_multiple;         /* 0: CO_GEO_START_MULTIPLE */
    uint32_t improvements;
    uint64_t seed;  /* 0 = 1 */
    int json;       /* phase records and the summary as JSON on stdout */
    int then_image; /* the image optimizer follows: the summary record is "geometric" */
} co_geo_run_options;

lm_status co_geo_run(const co_geo_run_options *o, co_geo_summary *sum);

#endif
