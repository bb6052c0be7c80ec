/* coordinator/simplify/simplify_job.h — `lumesh simplify --method image|shard` end to end: load
 * the model (and the reference whose images are matched, by default the model itself), QEM first
 * for large models (work.h's rule), the views (in process, or lumesh-worker processes for the
 * image method), the greedy collapses (isimp.h), the result written atomically, and optionally
 * the progressive mesh of the image-driven range (pm.h). */
#ifndef LM_COORDINATOR_SIMPLIFY_SIMPLIFY_JOB_H
#define LM_COORDINATOR_SIMPLIFY_SIMPLIFY_JOB_H

#include <stdint.h>

#include "coordinator/simplify/isimp.h"
#include "coordinator/simplify/work.h"

/* Zero means default for every field but the paths and the target. */
typedef struct co_simplify_options {
    const char *input_path, *output_path;
    const char *reference_path; /* the images to match; NULL = the input's */
    uint32_t target_verts;
    co_price_method method;
    uint32_t views;              /* 0 = 20 */
    int size;                    /* 0 = 256 */
    const char *device;          /* NULL = auto */
    co_simplify_workers workers; /* image method: lumesh-worker processes (none: this process) */
    uint32_t presimplify;        /* QEM to this many vertices first; 0 = 10 x target when larger */
    const char *pm_path;         /* write the progressive mesh here; NULL = not */
    int progress;                /* a progress line on stderr */
} co_simplify_options;

typedef struct co_simplify_summary {
    uint32_t in_verts, in_tris; /* the model as loaded */
    uint32_t start_verts;       /* where the image-driven collapses started (after QEM) */
    uint32_t out_verts, out_tris, out_parts;
    co_isimp_stats stats;
    double load_s, prepare_s, simplify_s, write_s;
    char renderer[128];
} co_simplify_summary;

lm_status co_simplify_job_run(const co_simplify_options *o, co_simplify_summary *sum);

#endif
