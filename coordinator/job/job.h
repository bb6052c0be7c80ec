/* coordinator/job/job.h — one optimisation job, end to end: load the original, make (or load) the
 * coarse mesh, render the target views, run the optimizer until its evaluation budget or time
 * limit, report progress, write periodic checkpoints, and save the result atomically.
 *
 * Determinism: with the same inputs, options and seed the output file is byte-identical, whether
 * the run was uninterrupted or resumed from any of its checkpoints: the optimizer's state is
 * complete between moves, the evaluation budget counts from the start of the job, and resuming
 * with a larger --evals continues exactly where a run with the smaller budget stopped.
 * Periodic checkpoints are written at edge-iteration boundaries; a last one when the job stops. */
#ifndef LM_COORDINATOR_JOB_H
#define LM_COORDINATOR_JOB_H

#include <stdint.h>

#include "common/error.h"
#include "common/optimizer/optimizer.h"
#include "common/optimizer/optimizer_tuning.h"
#include "common/view.h"
#include "coordinator/job/preset.h"
#include "coordinator/job/progress.h"
#include "coordinator/job/schedule.h"
#include "coordinator/views/lane_audit.h"

/* A job's defaults (resolved by resolve_options in job.c, nowhere else). The optimizer's own views
 * are 30 of 208²; `energy`, `render` and the others keep LM_DEFAULT_VIEWS of LM_DEFAULT_VIEW_SIZE.
 * Why these values: coordinator/OPTIMIZER.md (views: third round). */
#define CO_JOB_DEFAULT_VIEWS 30u
#define CO_JOB_DEFAULT_SIZE 208
#define CO_JOB_DEFAULT_EVALS 100000ull
#define CO_JOB_DEFAULT_CHECKPOINT_S 60.0
#define CO_JOB_MIN_TARGET_VERTS 100u
#define CO_JOB_DEFAULT_IN_FLIGHT 1u
/* A new sub-pixel grid of the views every so many evaluations (regrid.h; why 10,000:
 * coordinator/OPTIMIZER.md, ninth round). */
#define CO_JOB_DEFAULT_REGRID_EVERY 10000ull
/* Validation (`--validate-every`, validate.h): off unless asked (why: coordinator/OPTIMIZER.md,
 * validation views (issue 38)); when on, as many validation views as training views, and the
 * training views kept on a plateau (a patience of 0: new training views after P checks without a
 * new best measured worse on bunny at 100k, same place). */
#define CO_JOB_DEFAULT_VALIDATE_EVERY 0ull
#define CO_JOB_DEFAULT_VALIDATE_PATIENCE 0u
/* The view schedule (`--view-schedule`, schedule.h): the job's views all along unless asked (why:
 * coordinator/OPTIMIZER.md, view schedule (issue 38)). */
#define CO_JOB_DEFAULT_SCHEDULE CO_SCHEDULE_FIXED
/* `--quality` (preset.h): draft and best's evaluations and best's schedule; good is the defaults
 * above. Best spends its extra compute on views and pixels, not evaluations (the grow schedule
 * beat the fixed views at 100,000 on every model measured; more evaluations of the same views did
 * not help: coordinator/OPTIMIZER.md, view schedule). */
#define CO_JOB_DRAFT_EVALS 10000ull
#define CO_JOB_BEST_EVALS CO_JOB_DEFAULT_EVALS
#define CO_JOB_BEST_SCHEDULE CO_SCHEDULE_GROW
#define CO_JOB_WORKER_START_S 60.0 /* local workers must say hello within this */

/* "None" for the options whose 0 means the default (no geometric term, no regrid, no worker
 * processes): one spelling for all of them. Set a field to CO_JOB_NONE; co_job_is_none(field) tells
 * (an unsigned field holds it as its largest value, a double as -1). */
#define CO_JOB_NONE (-1)
static inline int co_job_none_u32(uint32_t x)
{
    return x == UINT32_MAX;
}
static inline int co_job_none_u64(uint64_t x)
{
    return x == UINT64_MAX;
}
static inline int co_job_none_double(double x)
{
    return x < 0;
}
#define co_job_is_none(field)                                                                      \
    _Generic((field), uint32_t                                                                     \
             : co_job_none_u32, uint64_t                                                           \
             : co_job_none_u64, double                                                             \
             : co_job_none_double)(field)

/* Where a job without --initial starts: QEM's mesh at the target, or the image-driven
 * simplification (coordinator/simplify/, QEM to 10 x the target first) with the geometric term of
 * CO_JOB_IMAGE_START_SHARE (below), the default (why: coordinator/OPTIMIZER.md, sixth round). */
typedef enum co_job_start {
    CO_JOB_START_DEFAULT = 0,
    CO_JOB_START_QEM,
    CO_JOB_START_IMAGE,
    CO_JOB_START_ADAPTIVE, /* Park, Lee & Lee's shape-adaptive simplification at the target */
} co_job_start;
#define CO_JOB_DEFAULT_START CO_JOB_START_IMAGE
/* The geometric term's share for the image start's collapses when the job's is 0 (the default);
 * the optimizer's LM_SURFACE_SHARE stays the share after them, from a QEM start or --initial (why:
 * coordinator/OPTIMIZER.md, seventh round). */
#define CO_JOB_IMAGE_START_SHARE 0.2

/* Zero means default for every field. */
typedef struct co_job_options {
    const char *original_path;   /* required */
    const char *output_path;     /* required: .obj, .ply or .glb */
    const char *initial_path;    /* the coarse mesh to start from; NULL = `start`'s */
    co_job_start start;          /* how the coarse mesh is made without initial_path */
    uint32_t target_verts;       /* its vertices; 0 = 1% of the original's vertices, at least 100 */
    lm_view_spec views;          /* count 0 = CO_JOB_DEFAULT_VIEWS; dist 0 = the sphere */
    int size;                    /* image side in pixels; 0 = CO_JOB_DEFAULT_SIZE */
    uint64_t max_evals;          /* evaluation budget counted from the start of the job; 0 =
                                    CO_JOB_DEFAULT_EVALS */
    double time_limit_s;         /* wall-clock limit for this process; 0 = none */
    uint64_t seed;               /* 0 = 1 */
    const char *attrs;           /* "pos,normal,uv,color" subset; NULL = uv if textured, color if
                                    coloured; normals not listed are derived from geometry */
    const char *checkpoint_path; /* NULL = none (with resume_path: that file) */
    uint64_t checkpoint_every_evals; /* 0 = by time only */
    double checkpoint_every_s;       /* 0 = 60 s unless checkpoint_every_evals is set */
    const char *resume_path;         /* continue from this checkpoint */
    int json;                        /* NDJSON progress + summary on stdout */
    int quiet;                       /* no progress and no summary (callers that report) */
    const char *device_spec;         /* renderer device: "auto" (NULL), "cpu", "host", "egl:N" */
    uint32_t workers;     /* local lumesh-worker processes to spawn; 0 = one per core (none with
                             listen), CO_JOB_NONE = render in this process */
    const char *listen;   /* also take workers that connect here ("tcp://ADDR:PORT") */
    const char *renderer; /* accept only workers of this renderer id; NULL = the first one's */
    const char *keys;     /* CURVE key folder for the workers' connections (proto/keys.h) */
    uint32_t
        edges_in_flight; /* edges optimised at once (lm_params); 0 = CO_JOB_DEFAULT_IN_FLIGHT */
    uint32_t edges_per_iteration; /* the plan's size (lm_params): 0 = the optimizer's default */
    uint32_t lane_isolation;      /* 1: those edges' lanes isolated (lm_params.lane_isolation) */
    uint32_t lanes_remote;   /* 1: isolated lanes run on the workers (--lanes remote: each worker
                                serves every view); the same output as in process */
    co_audit_rule audit;     /* --lanes remote: lanes a second worker runs again (lane_audit.h) */
    int audit_set;           /* 0: audit is CO_AUDIT_DEFAULT_* (resolve_options) */
    double surface_weight;   /* the optimizer's geometric term (lm_tuning.surface_weight): 0 =
                                default, CO_JOB_NONE = none */
    double surface_share;    /* its weight relative to the start (lm_tuning.surface_share): 0 =
                                default (CO_JOB_IMAGE_START_SHARE for the image start's collapses,
                                LM_SURFACE_SHARE after), CO_JOB_NONE = none */
    uint64_t regrid_every;   /* move the views' pixel grid every so many evaluations (regrid.h): 0 =
                                CO_JOB_DEFAULT_REGRID_EVERY, CO_JOB_NONE = never */
    uint64_t validate_every; /* judge the mesh on validation views every so many evaluations
                                and output the best (validate.h): 0 =
                                CO_JOB_DEFAULT_VALIDATE_EVERY, CO_JOB_NONE = never */
    uint32_t validate_views; /* their count: 0 = the training views' count */
    uint32_t validate_patience;      /* checks without a new best before the job fits new training
                                        views (view_turn.h): 0 = CO_JOB_DEFAULT_VALIDATE_PATIENCE,
                                        CO_JOB_NONE = never */
    co_job_quality quality;          /* a preset for the fields below left at 0 (preset.h): 0 =
                                        the defaults (good's) */
    co_view_schedule view_schedule;  /* views and size growing with the evaluations (schedule.h):
                                        0 = CO_JOB_DEFAULT_SCHEDULE; the grow schedule's stages
                                        are fractions of max_evals (with --time alone: of the
                                        default budget) */
    const char *initial_output_path; /* write the coarse mesh the optimisation starts from (after
                                        its preparation) here; NULL = not */
    unsigned bake_kinds; /* with bake_every: the maps baked in the loop (job/bake.h CO_BAKE_*) */
    uint32_t bake_size;  /* their side in texels; 0 = CO_BAKE_DEFAULT_SIZE */
    uint64_t bake_every; /* maps in the loop (bake_loop.h): bake them onto the current mesh every
                            so many evaluations (from 0) and render the current mesh with them;
                            0 = never (the default). Excludes checkpoints, validation and
                            --lanes remote; uv is then not optimised */
    int cull_unseen;     /* remove the output's triangles no view sees (quality/cull_unseen.h); not
                            part of the optimisation, so a checkpoint does not record it */
    /* Called with the counters at the start, after every optimizer step and at the end (the
       quality report's history); NULL = none. */
    void (*on_progress)(void *ctx, const lm_progress *p, double elapsed_s);
    void *progress_ctx;
} co_job_options;

/* The number of local workers `workers` means (0 = one per core; none with listen). */
uint32_t co_job_local_workers(const co_job_options *o);

/* Parse an --attrs list ("pos,normal,uv,color"; "pos" alone = positions only) into LM_ATTR_* bits.
 * LM_E_INVALID naming the bad word. */
lm_status co_job_parse_attrs(const char *spec, uint32_t *out);

/* Run the job. On success the output exists (written atomically) and *summary (may be NULL) holds
 * the final counters; output_path in it points into opts. SIGINT/SIGTERM stop it at the next step
 * (stop_reason "interrupted": last checkpoint and output written); SIGUSR1 with a checkpoint file
 * stops it the same way but writes only the checkpoint (stop_reason "suspended", output_path NULL):
 * a later --resume with the same options finishes it with the bytes of an uninterrupted run. */
lm_status co_job_run(const co_job_options *opts, co_job_summary *summary);

/* The optimizer's inputs exactly as co_job_run makes them for `opts` (the defaults resolved in
 * the one place co_job_run resolves them; the coarse start of --start qem or adaptive, or
 * --initial, prepared as the job prepares it; the training views of the view schedule's first
 * stage in regrid draw 0; the parameters and tuning it creates the optimizer with), for
 * benchmarks that run the job's engine on views of their own. No workers are started, nothing
 * is written (no output path needed). Blocks for the load and the simplification. The image start
 * prices its collapses on the job's workers: refused (LM_E_UNSUPPORTED, one line). On success the
 * caller owns *out (co_job_setup_free); on failure *out holds nothing. */
typedef struct co_job_setup {
    co_job_options o;      /* resolved (the pointers are the caller's) */
    uint32_t attrs;        /* the attributes optimised (LM_ATTR_*) */
    uint64_t regrid_every; /* the job's regrids: every so many evaluations (0 = never) */
    lm_mesh *original;     /* owned; params.surface points to it */
    lm_mesh *coarse;       /* owned: the start, prepared (adjacency built) */
    lm_view_set *views;    /* owned: the training views the loop begins with */
    lm_params params;
    lm_tuning tuning;
} co_job_setup;

lm_status co_job_setup_make(const co_job_options *opts, co_job_setup *out);
/* The training views of the setup's first stage in regrid draw `draw` (the views the job's loop
 * switches to at co_regrid_next(draw - 1, regrid_every) evaluations, regrid.h). */
lm_status co_job_setup_view_set(const co_job_setup *s, uint32_t draw, lm_view_set *out);
void co_job_setup_free(co_job_setup *s);

#endif
