/* coordinator/simplify/simplify_job.h — `lumesh simplify --method image|shard` end to end: load
 * the model (and the reference whose images are matched, by default the model itself), QEM first
 * for large models (work.h's rule), the views (in process, or lumesh-worker processes for the
 * image method), the greedy collapses (isimp.h), the result written atomically, and optionally
 * the progressive mesh of the image-driven range (pm.h). */
#ifndef LM_COORDINATOR_SIMPLIFY_SIMPLIFY_JOB_H
#define LM_COORDINATOR_SIMPLIFY_SIMPLIFY_JOB_H

#include <stdint.h>

#include "coordinator/quality/phase_meter.h"
#include "coordinator/simplify/isimp.h"
#include "coordinator/simplify/work.h"

/* Zero means default for every field but the paths and the target. */
typedef struct co_simplify_options {
    const char *input_path, *output_path;
    const char *reference_path; /* the images to match; NULL = the input's */
    uint32_t target_verts;
    co_price_method method;
    lm_view_spec views;          /* count 0 = 20; dist 0 = the sphere */
    int size;                    /* 0 = 256 */
    const char *device;          /* NULL = auto */
    co_simplify_workers workers; /* image method: lumesh-worker processes (none: this process) */
    uint32_t presimplify;        /* QEM to this many vertices first; 0 = 10 x target when larger */
    double surface_weight;       /* image method: the geometric term's weight (surface_term.h)
                                    added to every collapse's price; 0 = from surface_share */
    double surface_share;        /* the weight that makes E_geo this share of the image energy of
                                    QEM's mesh at the target (as the optimizer's share does at its
                                    start); 0 = none */
    const char *pm_path;         /* write the progressive mesh here; NULL = not */
    int cull_unseen; /* the output without the triangles no view sees (quality/cull_unseen.h;
                        the progressive mesh stays whole) */
    co_meter_style progress; /* lines on stderr: none (0), a terminal's or a log's */
    co_meter *meter;         /* the caller's meter for the phases (borrowed; its stage names
                                them); NULL: one of "lumesh simplify" in style `progress` */
} co_simplify_options;

typedef struct co_simplify_summary {
    uint32_t in_verts, in_tris; /* the model as loaded */
    uint32_t start_verts;       /* where the image-driven collapses started (after QEM) */
    uint32_t out_verts, out_tris, out_parts;
    uint32_t culled_tris; /* triangles --cull-unseen removed from the output */
    co_isimp_stats stats;
    double surface_weight; /* the geometric term's weight; 0 = none */
    double load_s, prepare_s, simplify_s, write_s;
    char renderer[128];
} co_simplify_summary;

lm_status co_simplify_job_run(const co_simplify_options *o, co_simplify_summary *sum);

typedef struct co_pool co_pool;

/* The image method on a model in memory (`in`, borrowed), for the optimizer's start: the stages of
 * co_simplify_job_run between loading and writing, with o's paths, reference and pm unused (they
 * must be NULL) and the views rendered through `pool` (borrowed; its workers are given the
 * simplification's views and released again) or, when pool is NULL, as o->workers says. *out is
 * the compact result (the caller destroys it), NULL on failure. Blocking; interrupted by the
 * pool's signals like any remote views. */
lm_status co_simplify_mesh(const lm_mesh *in, const co_simplify_options *o, co_pool *pool,
                           lm_mesh **out, co_simplify_summary *sum);

#endif
