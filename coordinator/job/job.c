/* coordinator/job/job.c — one optimisation job: set-up stages, the optimisation loop with progress
 * and checkpoints, and the atomic output. Reads as: resolve options → load original → coarse mesh →
 * views → optimizer (→ resume) → loop → save. */
#include "coordinator/job/job.h"

#include <errno.h>
#include <inttypes.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

#include "common/folders.h"
#include "common/io/mesh_io.h"
#include "common/mesh.h"
#include "common/mesh_topology.h"
#include "common/optimizer/lane_runner.h"
#include "common/optimizer/optimizer.h"
#include "common/optimizer/optimizer_tuning.h"
#include "common/view.h"
#include "coordinator/job/bake.h"
#include "coordinator/job/bake_loop.h"
#include "coordinator/job/checkpoint.h"
#include "coordinator/job/regrid.h"
#include "coordinator/job/schedule.h"
#include "coordinator/job/validate.h"
#include "coordinator/job/view_turn.h"
#include "coordinator/pool/pool.h"
#include "coordinator/quality/cull_unseen.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/simplify/simplify_job.h"
#include "coordinator/views/views.h"

/* Steps in a row that make no evaluation before the job calls the optimisation converged. */
#define CO_JOB_MAX_IDLE_STEPS 16
/* Wall-clock seconds of work asked of one optimizer step (between progress reports). */
#define CO_JOB_STEP_SECONDS 0.25

typedef struct co_job {
    co_job_options o; /* defaults resolved */
    uint32_t attrs;
    const char *checkpoint_path;
    lm_mesh *original;
    co_original_pack pack;     /* the original's asset for the remote views (regrids copy it) */
    lm_mesh *coarse;           /* until the optimizer takes it */
    co_pool *pool;             /* the workers (NULL: in process) */
    co_worker_report *workers; /* what progress shows of them */
    uint32_t cap_workers;
    lm_views *views;
    uint32_t draw;              /* the regrid draw the views are made with (regrid.h) */
    uint64_t regrid_every;      /* 0 = never */
    co_validation val;          /* with validate_every: the validation views, best mesh and state */
    uint64_t validate_every;    /* 0 = no validation */
    uint32_t validate_patience; /* 0 = the training views never change */
    uint32_t stage;             /* the view schedule's stage in force (schedule.h) */
    co_bake_loop *bake;         /* with bake_every: the maps in the loop (bake_loop.h) */
    uint64_t bake_round;        /* evaluations / bake_every at the last bake; UINT64_MAX = none */
    lm_optimizer *opt;
    co_checkpoint_key key;
    co_reporter rep;
    co_meter meter; /* the set-up's long phases, and the regrids' (once meter_on) */
    int meter_on;
    struct timespec t0;
    double loop_start_s;      /* seconds from t0 to the start of the optimisation loop */
    double loop_cpu_s;        /* CPU seconds of this process at the start of the loop */
    co_lane_stats lane_stats; /* --lanes remote: what earlier views' groups sent */
    double loop_limit_s;      /* the loop's share of the time limit; 0 = none */
    uint64_t resumed_from_evals;
    double start_weight; /* the geometric term's weight the image start used; 0 = none */
    double start_share;  /* the geometric term's share the image start prices with; 0 = none */
    char renderer[128];
} co_job;

/* CPU seconds of this process so far, every thread (not the workers). */
static double process_cpu_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double seconds_since(const struct timespec *t0)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)(t.tv_sec - t0->tv_sec) + 1e-9 * (double)(t.tv_nsec - t0->tv_nsec);
}

uint32_t co_job_local_workers(const co_job_options *o)
{
    if (co_job_is_none(o->workers))
        return 0;
    if (o->workers)
        return o->workers;
    if (o->listen)
        return 0;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (uint32_t)n : 1;
}

lm_status co_job_parse_attrs(const char *spec, uint32_t *out)
{
    uint32_t attrs = 0;
    const char *p = spec;
    if (!spec || !*spec)
        return lm_fail(LM_E_INVALID, "--attrs needs a list such as pos,normal,uv,color");
    while (*p) {
        size_t n = strcspn(p, ",");
        if (n == 3 && strncmp(p, "pos", 3) == 0)
            ;
        else if (n == 6 && strncmp(p, "normal", 6) == 0)
            attrs |= LM_ATTR_NORMAL;
        else if (n == 2 && strncmp(p, "uv", 2) == 0)
            attrs |= LM_ATTR_UV;
        else if ((n == 5 && strncmp(p, "color", 5) == 0) ||
                 (n == 6 && strncmp(p, "colour", 6) == 0))
            attrs |= LM_ATTR_COLOR;
        else
            return lm_fail(LM_E_INVALID,
                           "--attrs: unknown attribute '%.*s' (use pos,normal,uv,color)", (int)n,
                           p);
        p += n;
        if (*p == ',' && *++p == '\0')
            return lm_fail(LM_E_INVALID, "--attrs: trailing comma in '%s'", spec);
    }
    *out = attrs;
    return LM_OK;
}

/* Fail before any work when an output can never be written; missing folders are made. */
static lm_status check_writable(const char *what, const char *path)
{
    if (lm_make_parent_folders(path) != LM_OK) {
        char why[512];
        snprintf(why, sizeof why, "%s", lm_last_error());
        return lm_fail(LM_E_IO, "cannot write %s '%s': %s", what, path, why);
    }
    const char *slash = strrchr(path, '/');
    char dir[4096];
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash == path ? 1 : slash - path), path);
    if (access(dir, W_OK) != 0)
        return lm_fail(LM_E_IO, "cannot write %s '%s': folder '%s': %s", what, path, dir,
                       strerror(errno));
    return LM_OK;
}

static lm_status check_output_path(const char *path)
{
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash) ||
        (strcasecmp(dot, ".obj") && strcasecmp(dot, ".ply") && strcasecmp(dot, ".glb")))
        return lm_fail(LM_E_INVALID, "output '%s': use a .obj, .ply or .glb file name", path);
    return check_writable("output", path);
}

/* The geometric term's share, the one place it is resolved: none (a negative weight or share)
 * turns it off everywhere; a share of 0 is CO_JOB_IMAGE_START_SHARE for the image start's
 * collapses and the optimizer's LM_SURFACE_SHARE after them, from a QEM start or --initial. */
static void resolve_surface_term(co_job *j)
{
    co_job_options *o = &j->o;
    int none = co_job_is_none(o->surface_weight) || co_job_is_none(o->surface_share);
    j->start_share = none ? 0 : o->surface_share > 0 ? o->surface_share : CO_JOB_IMAGE_START_SHARE;
    if (o->surface_share == 0)
        o->surface_share = LM_SURFACE_SHARE;
}

/* Validation's options, the one place they are resolved: off unless asked; as many views as the
 * job's (a camera file's count: its cameras turned, view_turn.h); a patience of
 * CO_JOB_DEFAULT_VALIDATE_PATIENCE checks (0: the training views never change). */
static lm_status resolve_validation(co_job *j)
{
    co_job_options *o = &j->o;
    if (!o->validate_every)
        o->validate_every = CO_JOB_DEFAULT_VALIDATE_EVERY;
    j->validate_every =
        !o->validate_every || co_job_is_none(o->validate_every) ? 0 : o->validate_every;
    if (!j->validate_every) {
        o->validate_views = 0;
        o->validate_patience = 0;
        return LM_OK;
    }
    if (o->views.dist == LM_VIEW_DIST_CAMERAS && o->validate_views &&
        o->validate_views != o->views.count)
        return lm_fail(LM_E_INVALID,
                       "--validate-views %" PRIu32 ": with --views-from the validation views are "
                       "the %" PRIu32 " cameras turned",
                       o->validate_views, o->views.count);
    if (!o->validate_views)
        o->validate_views = o->views.count;
    if (o->validate_views > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "--validate-views %" PRIu32 " is above %d", o->validate_views,
                       LM_MAX_VIEWS);
    if (!o->validate_patience)
        o->validate_patience = CO_JOB_DEFAULT_VALIDATE_PATIENCE;
    if (co_job_is_none(o->validate_patience))
        o->validate_patience = 0;
    j->validate_patience = o->validate_patience;
    return LM_OK;
}

/* --quality: the preset's evaluations, views, size and schedule where the job left them at 0
 * (sphere or hemisphere views: a camera file keeps its count). */
static void apply_preset(co_job_options *o)
{
    const co_job_preset *p = co_job_preset_of(o->quality);
    if (!o->max_evals)
        o->max_evals = p->evals;
    if (!o->views.count && o->views.dist != LM_VIEW_DIST_CAMERAS)
        o->views.count = p->views;
    if (!o->size)
        o->size = p->size;
    if (!o->view_schedule)
        o->view_schedule = p->schedule;
}

/* --bake-every: what it goes with (one line for each thing it refuses); its size. */
static lm_status resolve_bake_loop(co_job *j)
{
    co_job_options *o = &j->o;
    j->bake_round = UINT64_MAX;
    if (!o->bake_every)
        return LM_OK;
    if (!o->bake_kinds)
        return lm_fail(LM_E_INVALID, "--bake-every needs --bake normal, color or normal,color");
    if (j->checkpoint_path)
        return lm_fail(LM_E_INVALID, "--bake-every excludes --checkpoint and --resume (the maps "
                                     "in the loop are not checkpointed)");
    if (j->validate_every)
        return lm_fail(LM_E_INVALID, "--bake-every excludes --validate-every (the validation "
                                     "views render without the maps)");
    if (o->lanes_remote)
        return lm_fail(LM_E_INVALID, "--bake-every excludes --lanes remote");
    if (!o->bake_size)
        o->bake_size = CO_BAKE_DEFAULT_SIZE;
    return LM_OK;
}

/* The job's defaults, the one place they are resolved; with `run` also the checks of what a run
 * writes (an output path required), without it (co_job_setup_make) none. */
static lm_status resolve_options(co_job *j, const co_job_options *in, int run)
{
    j->o = *in;
    co_job_options *o = &j->o;
    if (!o->original_path || (run && !o->output_path))
        return lm_fail(LM_E_INVALID, "an original model and an output path are required");
    if (o->initial_path && o->target_verts)
        return lm_fail(LM_E_INVALID, "--initial and --target-verts exclude each other");
    if (o->initial_path && o->start)
        return lm_fail(LM_E_INVALID, "--initial and --start exclude each other");
    if (!o->start)
        o->start = CO_JOB_DEFAULT_START;
    apply_preset(o);
    if (!o->views.count)
        o->views.count = CO_JOB_DEFAULT_VIEWS;
    if (!o->size)
        o->size = CO_JOB_DEFAULT_SIZE;
    if (o->views.count > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "--views %" PRIu32 " is above %d", o->views.count, LM_MAX_VIEWS);
    if (o->size < 16 || o->size > LM_MAX_VIEW_SIZE)
        return lm_fail(LM_E_RANGE, "--size %d is outside 16..%d", o->size, LM_MAX_VIEW_SIZE);
    if (!o->max_evals)
        o->max_evals = CO_JOB_DEFAULT_EVALS;
    if (!o->seed)
        o->seed = 1;
    if (!o->edges_in_flight)
        o->edges_in_flight = CO_JOB_DEFAULT_IN_FLIGHT;
    if (o->edges_in_flight > LM_MAX_EDGES_IN_FLIGHT)
        return lm_fail(LM_E_RANGE, "--edges-in-flight %" PRIu32 " is above %u", o->edges_in_flight,
                       LM_MAX_EDGES_IN_FLIGHT);
    if (o->edges_per_iteration > LM_MAX_EDGES_PER_ITERATION)
        return lm_fail(LM_E_RANGE, "--edges-per-iteration %" PRIu32 " is above %u",
                       o->edges_per_iteration, LM_MAX_EDGES_PER_ITERATION);
    if (o->lanes_remote && o->edges_in_flight < 2)
        return lm_fail(LM_E_INVALID, "--lanes remote needs --edges-in-flight 2 or more");
    if (o->lanes_remote && co_job_is_none(o->workers))
        return lm_fail(LM_E_INVALID, "--lanes remote needs workers (not --workers 0)");
    if (!o->audit_set)
        o->audit = (co_audit_rule){CO_AUDIT_DEFAULT_PROBATION, CO_AUDIT_DEFAULT_RATE};
    if (!(o->time_limit_s >= 0) || !(o->checkpoint_every_s >= 0))
        return lm_fail(LM_E_RANGE, "time limits must be positive numbers");
    if (!o->checkpoint_every_s && !o->checkpoint_every_evals)
        o->checkpoint_every_s = CO_JOB_DEFAULT_CHECKPOINT_S;
    if (!o->device_spec)
        o->device_spec = "auto";
    if (!o->regrid_every)
        o->regrid_every = CO_JOB_DEFAULT_REGRID_EVERY;
    if (!o->view_schedule)
        o->view_schedule = CO_JOB_DEFAULT_SCHEDULE;
    resolve_surface_term(j);
    j->regrid_every = co_job_is_none(o->regrid_every) ? 0 : o->regrid_every;
    lm_status vst = resolve_validation(j);
    if (vst != LM_OK)
        return vst;
    j->checkpoint_path = o->checkpoint_path ? o->checkpoint_path : o->resume_path;
    lm_status st = resolve_bake_loop(j);
    if (st != LM_OK || !run)
        return st;
    st = check_output_path(o->output_path);
    if (st == LM_OK && j->checkpoint_path)
        st = check_writable("checkpoint", j->checkpoint_path);
    if (st == LM_OK && o->initial_output_path)
        st = check_writable("initial mesh", o->initial_output_path);
    return st;
}

static int has_texture(const lm_mesh *m)
{
    for (uint32_t i = 0; i < m->n_materials; i++)
        if (m->materials[i].texture)
            return 1;
    return 0;
}

/* Attributes to optimise: the user's list (checked against the model) or the default. */
static lm_status choose_attrs(co_job *j)
{
    const lm_mesh *m = j->original;
    if (!j->o.attrs) {
        j->attrs = 0;
        if ((m->attrs & LM_ATTR_UV) && has_texture(m))
            j->attrs |= LM_ATTR_UV;
        if (m->attrs & LM_ATTR_COLOR)
            j->attrs |= LM_ATTR_COLOR;
        return LM_OK;
    }
    lm_status st = co_job_parse_attrs(j->o.attrs, &j->attrs);
    if (st != LM_OK)
        return st;
    if ((j->attrs & LM_ATTR_UV) && !(m->attrs & LM_ATTR_UV))
        return lm_fail(LM_E_INVALID, "--attrs uv: '%s' has no texture coordinates",
                       j->o.original_path);
    if ((j->attrs & LM_ATTR_COLOR) && !(m->attrs & LM_ATTR_COLOR))
        return lm_fail(LM_E_INVALID, "--attrs color: '%s' has no vertex colours",
                       j->o.original_path);
    return LM_OK;
}

static lm_status resolve_target(co_job *j)
{
    uint32_t live = j->original->live_verts;
    if (j->o.initial_path)
        return LM_OK;
    if (live < 8)
        return lm_fail(LM_E_RANGE, "'%s' has only %" PRIu32 " vertices, too few to simplify",
                       j->o.original_path, live);
    if (!j->o.target_verts) {
        uint32_t t = live / 100;
        if (t < CO_JOB_MIN_TARGET_VERTS)
            t = CO_JOB_MIN_TARGET_VERTS;
        if (t > live / 2)
            t = live / 2;
        j->o.target_verts = t;
    }
    if (j->o.target_verts < 4 || j->o.target_verts >= live)
        return lm_fail(LM_E_RANGE,
                       "--target-verts %" PRIu32 " must be in 4..%" PRIu32
                       " (below the original's %" PRIu32 " vertices)",
                       j->o.target_verts, live - 1, live);
    return LM_OK;
}

static void note(co_job *j, const char *event, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void report_validation(co_job *j);
static void note(co_job *j, const char *event, const char *fmt, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    co_reporter_note(&j->rep, event, buf);
}

static lm_status load_original(co_job *j)
{
    co_meter_phase(&j->meter, "loading %s", j->o.original_path);
    lm_status st = lm_mesh_load(j->o.original_path, NULL, &j->original);
    co_meter_end(&j->meter);
    if (st != LM_OK)
        return st;
    st = choose_attrs(j);
    if (st == LM_OK && j->o.bake_every && (j->attrs & LM_ATTR_UV)) {
        j->attrs &= ~(uint32_t)LM_ATTR_UV; /* the views see the loop's atlas (bake_loop.h) */
        note(j, "bake",
             "--bake-every: texture coordinates are not optimised (the views see the "
             "maps' atlas)");
    }
    if (st == LM_OK && j->o.bake_every)
        st = co_bake_loop_create(j->original, j->o.bake_kinds, (int)j->o.bake_size, &j->bake);
    if (st == LM_OK)
        st = resolve_target(j);
    if (st == LM_OK)
        note(j, "original", "%s: %" PRIu32 " vertices, %" PRIu32 " triangles", j->o.original_path,
             j->original->live_verts, j->original->live_tris);
    return st;
}

/* The image start's views: its own default count on the sphere (as ever) or the upper
 * hemisphere, or the job's cameras. */
static lm_view_spec image_start_views(const lm_view_spec *v)
{
    lm_view_spec s = *v;
    if (s.dist != LM_VIEW_DIST_CAMERAS)
        s.count = 0;
    return s;
}

/* The image-driven simplification of the original, on the job's workers (or in this process),
 * with the geometric term the optimizer gets: its weight, or its share (of QEM's mesh there). */
static lm_status image_start(co_job *j, lm_mesh **out)
{
    const co_job_options *o = &j->o;
    co_simplify_options so = {
        .target_verts = o->target_verts,
        .method = CO_PRICE_IMAGE,
        .views = image_start_views(&o->views),
        .device = o->device_spec,
        .surface_weight = o->surface_weight > 0 ? o->surface_weight : 0,
        .surface_share = j->start_share,
        .meter = &j->meter,
    };
    int human = j->rep.style == CO_REPORT_TTY || j->rep.style == CO_REPORT_LINES;
    uint32_t qem = co_simplify_start_verts(j->original->live_verts, o->target_verts, 0);
    co_reporter_abandon_line(&j->rep); /* a terminal's transient note */
    if (human)
        fprintf(stderr,
                "lumesh: the start: QEM to %" PRIu32 " vertices, then the image-driven collapses "
                "to %" PRIu32 " (--start qem skips them)\n",
                qem, o->target_verts);
    co_simplify_summary sum;
    co_meter_stage(&j->meter, "start");
    lm_status st = co_simplify_mesh(j->original, &so, j->pool, out, &sum);
    co_meter_stage(&j->meter, NULL);
    j->start_weight = sum.surface_weight;
    if (st == LM_OK && human)
        fprintf(stderr,
                "lumesh: the start: %" PRIu32 " vertices, %" PRIu32 " collapses in %.1f s\n",
                sum.out_verts, sum.stats.collapses, sum.prepare_s + sum.simplify_s);
    if (st == LM_OK && !human)
        note(j, "start",
             "image-driven simplification: QEM to %" PRIu32 ", then %" PRIu32
             " collapses (%.1f s, geometric term weight %.4g)",
             sum.start_verts, sum.stats.collapses, sum.prepare_s + sum.simplify_s,
             sum.surface_weight);
    return st;
}

/* QEM or the shape-adaptive simplification of the original, the image-driven one, or the user's
 * --initial mesh. */
static lm_status make_coarse(co_job *j, lm_mesh **out)
{
    *out = NULL;
    if (j->o.initial_path)
        return lm_mesh_load(j->o.initial_path, NULL, out);
    if (j->o.start == CO_JOB_START_IMAGE)
        return image_start(j, out);
    int short_of;
    int adaptive = j->o.start == CO_JOB_START_ADAPTIVE;
    co_meter_phase(&j->meter, "start: %s to %" PRIu32 " vertices",
                   adaptive ? "shape-adaptive" : "QEM", j->o.target_verts);
    lm_status st = co_simplify_best(j->original, adaptive ? CO_SIMPLIFY_ADAPTIVE : CO_SIMPLIFY_QEM,
                                    j->o.target_verts, out, &short_of);
    co_meter_end(&j->meter);
    if (short_of)
        note(j, "warning", "%s; going on with %" PRIu32 " vertices", lm_last_error(),
             (*out)->live_verts);
    return st;
}

/* Normals not optimised are derived from geometry: wedges that differ only in them are merged so
 * that they make no seams, and they are recomputed. Adjacency is rebuilt for the optimizer. */
static lm_status prepare_coarse(co_job *j, lm_mesh *m)
{
    if (!(j->attrs & LM_ATTR_NORMAL)) {
        lm_mesh_merge_wedges(m, LM_ATTR_UV | LM_ATTR_COLOR);
        lm_mesh_compute_normals(m);
    }
    lm_status st = lm_mesh_compact(m);
    if (st == LM_OK)
        st = lm_mesh_build_adjacency(m);
    if (st == LM_OK)
        st = lm_mesh_validate(m);
    if (st == LM_OK)
        note(j, "coarse", "%s: %" PRIu32 " vertices, %" PRIu32 " triangles",
             j->o.initial_path                     ? j->o.initial_path
             : j->o.start == CO_JOB_START_IMAGE    ? "image-driven"
             : j->o.start == CO_JOB_START_ADAPTIVE ? "shape-adaptive"
                                                   : "QEM",
             m->live_verts, m->live_tris);
    return st;
}

/* Worker processes (local ones started here, and those that connect to --listen), unless the
 * job renders in process. Local workers are waited for, so that the views are split between all
 * of them from the start. */
static lm_status make_pool(co_job *j)
{
    if (co_job_is_none(j->o.workers))
        return LM_OK;
    uint32_t local = co_job_local_workers(&j->o);
    co_pool_options po = {.listen = j->o.listen,
                          .local_workers = local,
                          .device = j->o.device_spec,
                          .renderer_id = j->o.renderer,
                          .keys = j->o.keys,
                          .quiet = j->rep.style == CO_REPORT_QUIET};
    lm_status st = co_pool_create(&po, &j->pool);
    if (st == LM_OK && local)
        st = co_pool_wait(j->pool, local, CO_JOB_WORKER_START_S);
    if (st == LM_OK && j->o.listen)
        note(j, "listening", "workers may join at %s", co_pool_endpoint(j->pool));
    return st;
}

/* The cameras of `count` views of the job's distribution turned by stream `turn` (view_turn.h) in
 * regrid draw `draw`. */
static lm_status make_view_set(const co_job *j, uint32_t count, int size, uint32_t turn,
                               uint32_t draw, lm_view_set *vs)
{
    float centre[3], radius;
    lm_mesh_bounding_sphere(j->original, centre, &radius);
    lm_view_spec spec = j->o.views;
    spec.count = count;
    lm_status st = lm_view_set_make_spec(vs, &spec, LM_VIEWS_TRAINING, size, centre, radius);
    co_view_turn_apply(vs, spec.dist, j->o.seed, turn, centre);
    co_regrid_apply(vs, j->o.seed, draw);
    return st;
}

/* Views of the original: `count` of the job's distribution turned by stream `turn` (view_turn.h)
 * in regrid draw `draw`, with the coarse mesh's materials (an --initial file has its own; the
 * optimizer keeps the coarse mesh's table). */
static lm_status create_views_of(co_job *j, uint32_t count, int size, uint32_t turn, uint32_t draw,
                                 int local, lm_views **out)
{
    lm_view_set *vs = malloc(sizeof *vs);
    if (!vs)
        return lm_fail(LM_E_NOMEM, "out of memory for the view set");
    lm_status st = make_view_set(j, count, size, turn, draw, vs);
    const lm_mesh *m = j->coarse ? j->coarse : lm_optimizer_mesh(j->opt);
    uint32_t n_baked = 0;
    const lm_material *baked = j->bake ? co_bake_loop_materials(j->bake, &n_baked) : NULL;
    co_views_desc d = {.kind = j->pool && !local ? CO_VIEWS_REMOTE : CO_VIEWS_LOCAL,
                       .original = j->original,
                       .views = vs,
                       .materials = baked ? baked : m->materials,
                       .n_materials = baked ? n_baked : m->n_materials,
                       .device = j->o.device_spec,
                       .pool = j->pool,
                       .whole = j->o.lanes_remote && j->pool && !local,
                       .audit = j->o.audit,
                       .pack = &j->pack};
    if (st == LM_OK)
        st = co_views_create(&d, out);
    free(vs);
    return st;
}

/* The view schedule's stage's count and size (schedule.h) and the training views' turn. */
static void stage_views(const co_job *j, uint32_t *count, int *size, uint32_t *turn)
{
    int cameras = j->o.views.dist == LM_VIEW_DIST_CAMERAS;
    co_schedule_views(j->o.view_schedule, j->stage, j->o.views.count, j->o.size,
                      cameras ? j->o.views.count : LM_MAX_VIEWS, LM_MAX_VIEW_SIZE, count, size);
    *turn = j->val.epoch + CO_SCHEDULE_TURN_STREAM(j->stage);
}

/* The training views in force: the view schedule's stage's count and size (schedule.h), of the
 * training views' epoch, in regrid draw `draw`. A camera file's views keep their count. */
static lm_status create_views(co_job *j, uint32_t draw, lm_views **out)
{
    uint32_t count, turn;
    int size;
    stage_views(j, &count, &size, &turn);
    lm_status st = create_views_of(j, count, size, turn, draw, 0, out);
    if (st == LM_OK && j->bake) /* the loop's maps on the current mesh (bake_loop.h) */
        st = co_bake_loop_wrap(j->bake, *out, out);
    return st;
}

/* The validation views: never fitted, one pixel grid, rendered in this process with the job's
 * device (the workers serve one view set at a time: the training views'). */
static lm_status make_validation_views(co_job *j)
{
    co_meter_phase(&j->meter, "the original's validation images (%" PRIu32 " views of %dx%d)",
                   j->o.validate_views, j->o.size, j->o.size);
    lm_status st = create_views_of(j, j->o.validate_views, j->o.size, CO_VIEW_TURN_VALIDATION, 0, 1,
                                   &j->val.views);
    co_meter_end(&j->meter);
    if (st == LM_OK && j->validate_patience)
        note(j, "validation views",
             "%" PRIu32 " views of %dx%d every %" PRIu64
             " evaluations; new training views after %" PRIu32 " checks without a new best",
             j->o.validate_views, j->o.size, j->o.size, j->validate_every, j->validate_patience);
    else if (st == LM_OK)
        note(j, "validation views", "%" PRIu32 " views of %dx%d every %" PRIu64 " evaluations",
             j->o.validate_views, j->o.size, j->o.size, j->validate_every);
    return st;
}

static lm_status make_views(co_job *j)
{
    co_meter_phase(&j->meter, "the original's target images (%" PRIu32 " views of %dx%d)",
                   j->o.views.count, j->o.size, j->o.size);
    lm_status st = create_views(j, 0, &j->views);
    co_meter_end(&j->meter);
    if (st != LM_OK)
        return st;
    lm_views_info info;
    j->views->ops->info(j->views, &info);
    snprintf(j->renderer, sizeof j->renderer, "%s", info.renderer);
    if (j->pool)
        note(j, "views", "%" PRIu32 " views of %dx%d on %" PRIu32 " workers: %s", info.n_views,
             info.width, info.height, co_pool_alive(j->pool), info.renderer);
    else
        note(j, "views", "%" PRIu32 " views of %dx%d on %s", info.n_views, info.width, info.height,
             info.renderer);
    return j->validate_every ? make_validation_views(j) : LM_OK;
}

/* The optimizer onto views of regrid draw `draw` (the old ones go). rescale_start as in
 * lm_optimizer_replace_views: 1 in the loop, 0 before a resume loads the energies. */
/* --lanes remote: the optimizer runs its lanes on the workers of the views in force. */
static lm_status use_lane_runner(co_job *j)
{
    if (!j->o.lanes_remote || !j->pool)
        return LM_OK;
    lm_lane_runner runner;
    lm_status st = co_views_lane_runner(j->views, &runner);
    if (st == LM_OK)
        lm_optimizer_set_lane_runner(j->opt, &runner);
    return st;
}

static lm_status switch_draw(co_job *j, uint32_t draw, int rescale_start)
{
    lm_views *v = NULL;
    lm_status st = create_views(j, draw, &v);
    if (st == LM_OK)
        st = lm_optimizer_replace_views(j->opt, v, rescale_start);
    if (st != LM_OK) {
        lm_views_destroy(v); /* the optimizer is left without views: the job ends here */
        return st;
    }
    co_views_lane_stats(j->views, &j->lane_stats); /* kept past the views */
    lm_views_destroy(j->views);
    j->views = v;
    j->draw = draw;
    return j->opt ? use_lane_runner(j) : LM_OK;
}

static lm_status make_key(co_job *j)
{
    co_checkpoint_key *k = &j->key;
    memset(k, 0, sizeof *k);
    lm_status st = co_checkpoint_hash_file(j->o.original_path, &k->original_hash);
    if (st == LM_OK && j->o.initial_path)
        st = co_checkpoint_hash_file(j->o.initial_path, &k->initial_hash);
    else if (j->o.start == CO_JOB_START_IMAGE)
        k->initial_hash = CO_CHECKPOINT_IMAGE_START;
    else if (j->o.start == CO_JOB_START_ADAPTIVE)
        k->initial_hash = CO_CHECKPOINT_ADAPTIVE_START;
    k->seed = j->o.seed;
    k->target_verts = j->o.initial_path ? 0 : j->o.target_verts;
    k->views = j->o.views.count;
    k->view_dist = (uint32_t)j->o.views.dist;
    k->cameras_hash = co_checkpoint_hash_cameras(&j->o.views);
    k->size = (uint32_t)j->o.size;
    k->attrs = j->attrs;
    k->regrid_every = j->regrid_every;
    k->validate_every = j->validate_every;
    k->validate_views = j->validate_every ? j->o.validate_views : 0;
    k->validate_patience = j->validate_patience;
    /* A schedule other than fixed is in the key; grow's stages are fractions of the budget, so the
     * budget is too, extend's are not (a resume may extend the run). */
    k->view_schedule =
        co_schedule_stages(j->o.view_schedule) > 1 ? (uint32_t)j->o.view_schedule : 0;
    k->schedule_evals = j->o.view_schedule == CO_SCHEDULE_GROW ? j->o.max_evals : 0;
    return st;
}

static lm_status put_u32_le(FILE *fp, uint32_t v, const char *what)
{
    uint8_t d[4];
    for (int i = 0; i < 4; i++)
        d[i] = (uint8_t)(v >> (8 * i));
    return fwrite(d, 1, 4, fp) == 4 ? LM_OK
                                    : lm_fail(LM_E_IO, "cannot write the checkpoint's %s", what);
}

static lm_status get_u32_le(FILE *fp, uint32_t *v, const char *what)
{
    uint8_t d[4];
    if (fread(d, 1, 4, fp) != 4)
        return lm_fail(LM_E_INVALID, "checkpoint is truncated (no %s)", what);
    *v = 0;
    for (int i = 0; i < 4; i++)
        *v |= (uint32_t)d[i] << (8 * i);
    return LM_OK;
}

/* The payload: the regrid draw the views were in (u32, little-endian), with validation the
 * training views' epoch (u32), with the grow schedule its stage (u32), then the optimizer, with
 * validation then its state (validate.h). */
static lm_status save_payload(const void *ctx, FILE *fp)
{
    const co_job *j = ctx;
    lm_status st = put_u32_le(fp, j->draw, "regrid draw");
    if (st == LM_OK && j->validate_every)
        st = put_u32_le(fp, j->val.epoch, "training views");
    if (st == LM_OK && j->key.view_schedule)
        st = put_u32_le(fp, j->stage, "view schedule stage");
    if (st == LM_OK)
        st = lm_optimizer_save(j->opt, fp);
    if (st == LM_OK && j->validate_every)
        st = co_validation_save(&j->val, fp);
    return st;
}

static lm_status load_payload(void *ctx, FILE *fp)
{
    co_job *j = ctx;
    uint32_t draw = 0, epoch = 0, stage = 0;
    lm_status st = get_u32_le(fp, &draw, "regrid draw");
    if (st == LM_OK && j->validate_every)
        st = get_u32_le(fp, &epoch, "training views");
    if (st == LM_OK && j->key.view_schedule)
        st = get_u32_le(fp, &stage, "view schedule stage");
    if (st != LM_OK)
        return st;
    if (draw && !j->regrid_every)
        return lm_fail(LM_E_INVALID,
                       "checkpoint names regrid draw %" PRIu32 " of a job without one", draw);
    if (stage >= co_schedule_stages(j->o.view_schedule))
        return lm_fail(LM_E_INVALID, "checkpoint names view schedule stage %" PRIu32, stage);
    int other = draw != j->draw || epoch != j->val.epoch || stage != j->stage;
    j->val.epoch = epoch;
    j->stage = stage;
    st = other ? switch_draw(j, draw, 0) : LM_OK;
    if (st == LM_OK)
        st = lm_optimizer_load(j->opt, fp);
    if (st == LM_OK && j->validate_every)
        st = co_validation_load(&j->val, lm_optimizer_mesh(j->opt), fp);
    if (st == LM_OK && j->validate_every)
        report_validation(j);
    return st;
}

static lm_status make_coarse_mesh(co_job *j)
{
    lm_status st = make_coarse(j, &j->coarse);
    if (st == LM_OK)
        st = prepare_coarse(j, j->coarse);
    if (st == LM_OK && j->o.initial_output_path)
        st = lm_mesh_save(j->o.initial_output_path, j->coarse);
    return st;
}

/* The optimizer's parameters and tuning for the job. */
static void optimizer_inputs(const co_job *j, lm_params *params, lm_tuning *tuning)
{
    *params = (lm_params){.seed = j->o.seed,
                          .attrs = j->attrs,
                          .edges_in_flight = j->o.edges_in_flight,
                          .edges_per_iteration = j->o.edges_per_iteration,
                          .lane_isolation = j->o.lane_isolation,
                          .surface = j->original};
    /* From an image start the term keeps the weight the collapses were priced with (the share of
       QEM's mesh), as from a QEM start: one energy from the original to the result. */
    *tuning =
        (lm_tuning){.surface_weight = j->start_weight > 0 ? j->start_weight : j->o.surface_weight,
                    .surface_share = j->o.surface_share};
}

static lm_status make_optimizer(co_job *j)
{
    lm_params params;
    lm_tuning tuning;
    optimizer_inputs(j, &params, &tuning);
    lm_mesh *coarse = j->coarse;
    j->coarse = NULL; /* the optimizer owns it from here on, even when its creation fails */
    co_meter_phase(&j->meter, "the optimizer's first energies (%" PRIu32 " vertices)",
                   coarse->live_verts);
    lm_status st = lm_optimizer_create_tuned(coarse, j->views, &params, &tuning, &j->opt);
    co_meter_end(&j->meter);
    if (st == LM_OK)
        st = use_lane_runner(j);
    if (st != LM_OK || !j->o.resume_path)
        return st;
    co_meter_phase(&j->meter, "resuming %s", j->o.resume_path);
    st = co_checkpoint_read(j->o.resume_path, &j->key, load_payload, j);
    co_meter_end(&j->meter);
    if (st != LM_OK)
        return st;
    lm_progress p;
    lm_optimizer_progress(j->opt, &p);
    j->resumed_from_evals = p.evals;
    note(j, "resumed", "%s at %" PRIu64 " evaluations", j->o.resume_path, p.evals);
    return LM_OK;
}

static void write_checkpoint(co_job *j, const lm_progress *p)
{
    lm_status st = co_checkpoint_write(j->checkpoint_path, &j->key, save_payload, j);
    if (st != LM_OK)
        note(j, "warning", "checkpoint not written: %s", lm_last_error());
    else if (j->rep.style == CO_REPORT_JSON)
        note(j, "checkpoint", "%s at %" PRIu64 " evaluations", j->checkpoint_path, p->evals);
}

/* What progress shows of the workers that served the job. */
static void report_workers(co_job *j)
{
    uint32_t n = j->pool ? co_pool_size(j->pool) : 0, k = 0;
    if (n > j->cap_workers) {
        co_worker_report *w = realloc(j->workers, n * sizeof *w);
        if (!w)
            return;
        j->workers = w;
        j->cap_workers = n;
    }
    double now = co_pool_now();
    for (uint32_t i = 0; i < n; i++) {
        const co_worker *w = co_pool_worker(j->pool, i);
        if (!w->job && !w->evals)
            continue;
        double age = now - w->joined > 1e-3 ? now - w->joined : 1e-3;
        co_worker_report *r = &j->workers[k++];
        *r = (co_worker_report){.id = w->id,
                                .pid = w->pid,
                                .first = w->first,
                                .count = w->count,
                                .stride = w->stride,
                                .evals = w->evals,
                                .evals_per_s = (double)w->evals / age,
                                .busy = w->busy_s / age,
                                .busy_loop = co_pool_loop_busy(j->pool, w, now),
                                .heard_s = now - w->last_heard,
                                .lost = w->lost};
        snprintf(r->host, sizeof r->host, "%.63s", w->host);
        snprintf(r->device, sizeof r->device, "%.31s", w->device);
    }
    co_reporter_set_workers(&j->rep, j->workers, k);
}

/* What progress shows of the validation. */
static void report_validation(co_job *j)
{
    const co_validation *v = &j->val;
    co_validation_report r = {.on = 1,
                              .energy = v->last_energy,
                              .best = v->best_energy,
                              .first = v->first_energy,
                              .best_evals = v->best_evals,
                              .checks = v->checks,
                              .epoch = v->epoch};
    co_reporter_set_validation(&j->rep, &r);
}

/* The reporter, and the caller's progress hook. */
static void progress(co_job *j, const lm_progress *p, double t, int force)
{
    report_workers(j);
    co_reporter_update(&j->rep, p, t, force);
    if (j->o.on_progress)
        j->o.on_progress(j->o.progress_ctx, p, t);
}

/* Why the loop stops now, or NULL to go on. */
static const char *stop_reason(const co_job *j, const lm_progress *p, double t, int idle)
{
    if (p->evals >= j->o.max_evals)
        return "evals";
    if (j->loop_limit_s > 0 && t >= j->loop_limit_s)
        return "time";
    if (idle >= CO_JOB_MAX_IDLE_STEPS)
        return "converged";
    if (co_pool_interrupted()) /* SIGUSR1: suspended for a later --resume, when it has a file */
        return co_pool_interrupt_signal() == SIGUSR1 && j->checkpoint_path ? "suspended"
                                                                           : "interrupted";
    return NULL;
}

/* Evaluations to ask of the next step: about CO_JOB_STEP_SECONDS of work at the rate so far, so
 * that progress and the time limit are looked at often even when an iteration takes minutes. */
static uint64_t step_chunk(uint64_t done, double t)
{
    double rate = t > 0 ? (double)done / t : 0.0;
    double chunk = rate > 0 ? rate * CO_JOB_STEP_SECONDS : 256.0;
    return chunk < 64 ? 64 : chunk > 1e6 ? 1000000 : (uint64_t)chunk;
}

/* The loop's progress lines count for the meter too: its next line is due a period after the
 * reporter's last one. */
static void meter_heard_reporter(co_job *j)
{
    if (j->rep.last_report_s < 0)
        return;
    double loop_s = seconds_since(&j->t0) - j->loop_start_s;
    co_meter_heard(&j->meter, loop_s - j->rep.last_report_s);
}

/* A new pixel grid when the evaluations have reached the next draw's start: before the next step,
 * so that a run resumed from a checkpoint written in between switches at the same point. */
static lm_status regrid_if_due(co_job *j, lm_progress *p)
{
    uint32_t draw = co_regrid_draw(p->evals, j->regrid_every);
    if (draw == j->draw)
        return LM_OK;
    int64_t before = p->energy;
    double t0 = seconds_since(&j->t0);
    meter_heard_reporter(j);
    co_meter_phase(&j->meter, "new pixel grid (draw %" PRIu32 "): the original's target images",
                   draw);
    lm_status st = switch_draw(j, draw, 1);
    co_meter_end(&j->meter);
    if (st == LM_OK)
        lm_optimizer_progress(j->opt, p);
    if (st == LM_OK && j->rep.style == CO_REPORT_JSON)
        note(j, "regrid",
             "draw %" PRIu32 " at %" PRIu64 " evaluations: energy %" PRId64
             " on the last grid, %" PRId64 " on the new one (%.2f s)",
             draw, p->evals, before, p->energy, seconds_since(&j->t0) - t0);
    return st;
}

/* The view schedule's next stage when the evaluations have reached its start (before the next
 * step, as a regrid): more views and pixels, turned by the stage's stream (schedule.h). */
static lm_status stage_if_due(co_job *j, lm_progress *p)
{
    uint32_t stage = co_schedule_stage(j->o.view_schedule, p->evals, j->o.max_evals);
    if (stage == j->stage)
        return LM_OK;
    int64_t before = p->energy;
    double t0 = seconds_since(&j->t0);
    j->stage = stage;
    meter_heard_reporter(j);
    co_meter_phase(&j->meter, "view schedule stage %" PRIu32 ": the original's target images",
                   stage);
    lm_status st = switch_draw(j, j->draw, 1);
    co_meter_end(&j->meter);
    if (st != LM_OK)
        return st;
    lm_optimizer_progress(j->opt, p);
    lm_views_info info;
    j->views->ops->info(j->views, &info);
    if (j->rep.style == CO_REPORT_JSON)
        note(j, "stage",
             "view schedule stage %" PRIu32 " at %" PRIu64 " evaluations: %" PRIu32
             " views of %dx%d; energy %" PRId64 " on the last views, %" PRId64
             " on the new ones (%.2f s)",
             stage, p->evals, info.n_views, info.width, info.height, before, p->energy,
             seconds_since(&j->t0) - t0);
    return LM_OK;
}

/* Fit new training views of the same distribution (the next epoch): the run has stopped paying on
 * the validation views with these ones. */
static lm_status new_training_views(co_job *j, lm_progress *p)
{
    j->val.epoch++;
    j->val.since_best = 0;
    meter_heard_reporter(j);
    co_meter_phase(&j->meter, "new training views (%" PRIu32 "): the original's target images",
                   j->val.epoch);
    lm_status st = switch_draw(j, j->draw, 1);
    co_meter_end(&j->meter);
    if (st == LM_OK)
        lm_optimizer_progress(j->opt, p);
    if (st == LM_OK)
        note(j, "new views",
             "training views %" PRIu32 " at %" PRIu64 " evaluations (%" PRIu32
             " checks without a new best on the validation views)",
             j->val.epoch, p->evals, j->validate_patience);
    return st;
}

/* A validation check when the evaluations have reached the next one's count (before the next
 * step, as a regrid), and on a plateau new training views. */
static lm_status validate_if_due(co_job *j, lm_progress *p)
{
    co_validation *v = &j->val;
    if (!j->validate_every || p->evals < v->next_evals)
        return LM_OK;
    int improved;
    lm_status st = co_validation_check(v, lm_optimizer_mesh(j->opt), p->evals, 1, &improved);
    if (st != LM_OK)
        return st;
    v->next_evals = (p->evals / j->validate_every + 1) * j->validate_every;
    report_validation(j);
    if (j->rep.style == CO_REPORT_JSON)
        note(j, "validation",
             "%" PRIu64 " evaluations: %" PRId64 " on the validation views%s (best %" PRId64
             " at %" PRIu64 ")",
             p->evals, v->last_energy, improved ? ", a new best" : "", v->best_energy,
             v->best_evals);
    if (j->validate_patience && v->since_best >= j->validate_patience)
        st = new_training_views(j, p);
    return st;
}

/* --bake-every: the maps baked onto the current mesh when the evaluations have reached the next
 * bake's count (0 included, before the next step as a regrid), handed to the views with the mesh
 * (its coordinates the new atlas's); the energies follow, as across a regrid. */
static lm_status bake_if_due(co_job *j, lm_progress *p)
{
    if (!j->bake || p->evals / j->o.bake_every == j->bake_round)
        return LM_OK;
    int64_t before = p->energy;
    double t0 = seconds_since(&j->t0);
    j->bake_round = p->evals / j->o.bake_every;
    meter_heard_reporter(j);
    co_meter_phase(&j->meter, "maps in the loop: baking onto %" PRIu32 " triangles", p->live_tris);
    lm_bake_stats bs;
    lm_status st = co_bake_loop_bake(j->bake, lm_optimizer_mesh(j->opt), &bs);
    uint32_t n = 0;
    const lm_material *mats = st == LM_OK ? co_bake_loop_materials(j->bake, &n) : NULL;
    if (st == LM_OK)
        st = j->views->ops->set_materials(j->views, mats, n);
    if (st == LM_OK) /* the mesh again, with the new atlas; the energies on the maps */
        st = lm_optimizer_replace_views(j->opt, j->views, 1);
    co_meter_end(&j->meter);
    if (st != LM_OK)
        return st;
    lm_optimizer_progress(j->opt, p);
    if (j->rep.style == CO_REPORT_JSON)
        note(j, "bake",
             "maps in the loop at %" PRIu64 " evaluations: %" PRIu64 " texels, %" PRIu64
             " met the original; energy %" PRId64 " before, %" PRId64 " with the new maps "
             "(%.2f s)",
             p->evals, bs.texels, bs.hits, before, p->energy, seconds_since(&j->t0) - t0);
    return LM_OK;
}

/* Optimise until the budget, the time limit, or nothing is left to evaluate. The optimizer stops
 * between moves when it reaches the evaluation count it is given and goes on with the same
 * iteration at the next call, so the chunking changes nothing in the result. Periodic checkpoints
 * are written at iteration boundaries, and a last one when the loop stops. */
static lm_status run_loop(co_job *j, const char **reason)
{
    lm_progress p;
    lm_optimizer_progress(j->opt, &p);
    const uint64_t evals0 = p.evals;
    uint64_t ck_evals = p.evals;
    double ck_s = 0.0, t = 0.0;
    int idle = 0;
    progress(j, &p, 0.0, 1);
    while (!(*reason = stop_reason(j, &p, t, idle))) {
        uint64_t before = p.evals, before_it = p.iterations;
        lm_status st = regrid_if_due(j, &p);
        if (st == LM_OK)
            st = stage_if_due(j, &p);
        if (st == LM_OK)
            st = bake_if_due(j, &p);
        if (st == LM_OK)
            st = validate_if_due(j, &p);
        if (st != LM_OK)
            return st;
        uint64_t target = p.evals + step_chunk(p.evals - evals0, t);
        uint64_t regrid = co_regrid_next(j->draw, j->regrid_every);
        target = target < regrid ? target : regrid;
        uint64_t stage = co_schedule_next(j->o.view_schedule, j->stage, j->o.max_evals);
        target = target < stage ? target : stage;
        if (j->validate_every && j->val.next_evals < target)
            target = j->val.next_evals;
        if (j->bake && (j->bake_round + 1) * j->o.bake_every < target)
            target = (j->bake_round + 1) * j->o.bake_every;
        st = lm_optimizer_step(j->opt, target < j->o.max_evals ? target : j->o.max_evals);
        if (st != LM_OK)
            return st;
        lm_optimizer_progress(j->opt, &p);
        idle = p.evals == before ? idle + 1 : 0;
        t = seconds_since(&j->t0) - j->loop_start_s;
        progress(j, &p, t, 0);
        int due =
            (j->o.checkpoint_every_evals && p.evals - ck_evals >= j->o.checkpoint_every_evals) ||
            (j->o.checkpoint_every_s > 0 && t - ck_s >= j->o.checkpoint_every_s);
        if (j->checkpoint_path && due && p.iterations != before_it) {
            write_checkpoint(j, &p);
            ck_evals = p.evals;
            ck_s = t;
        }
    }
    if (j->checkpoint_path && p.evals != ck_evals)
        write_checkpoint(j, &p);
    progress(j, &p, t, 1);
    return LM_OK;
}

/* --cull-unseen: the output without the triangles no training view sees (its pixel grid as the
 * job started), said as an event. */
static lm_status cull_unseen(co_job *j, lm_mesh *out)
{
    uint32_t before = out->live_tris, removed = 0;
    co_meter_phase(&j->meter, "triangles no view sees (%" PRIu32 " views of %dx%d)",
                   j->o.views.count, co_cull_size(j->o.size), co_cull_size(j->o.size));
    lm_status st = co_cull_unseen(out, j->original, &j->o.views, j->o.size, &removed);
    if (st == LM_OK) {
        char msg[96];
        snprintf(msg, sizeof msg, "removed %" PRIu32 " of %" PRIu32 " triangles no view sees",
                 removed, before);
        co_reporter_note(&j->rep, "cull", msg);
    }
    return st;
}

/* The last look at the final mesh on the validation views (after the last checkpoint, which does
 * not keep it): the output is the best of every check and of it. */
static lm_status validate_final(co_job *j)
{
    lm_progress p;
    lm_optimizer_progress(j->opt, &p);
    int improved;
    lm_status st = co_validation_check(&j->val, lm_optimizer_mesh(j->opt), p.evals, 0, &improved);
    if (st != LM_OK)
        return st;
    report_validation(j);
    if (j->rep.style == CO_REPORT_JSON)
        note(j, "validation",
             "%" PRIu64 " evaluations (the end): %" PRId64
             " on the validation views%s (best %" PRId64 " at %" PRIu64 ", the output)",
             p.evals, j->val.last_energy, improved ? ", a new best" : "", j->val.best_energy,
             j->val.best_evals);
    return LM_OK;
}

/* Output: a compacted copy of the optimizer's mesh (with validation: the best one), written
 * atomically (textures kept). */
static lm_status write_output(co_job *j)
{
    lm_mesh *copy;
    const lm_mesh *m = j->validate_every && j->val.best ? j->val.best : lm_optimizer_mesh(j->opt);
    lm_status st = lm_mesh_clone(m, &copy);
    if (st != LM_OK)
        return st;
    meter_heard_reporter(j);
    co_meter_phase(&j->meter, "writing %s", j->o.output_path);
    st = lm_mesh_compact(copy);
    if (st == LM_OK && j->o.cull_unseen)
        st = cull_unseen(j, copy);
    if (st == LM_OK)
        st = lm_mesh_save(j->o.output_path, copy);
    co_meter_end(&j->meter);
    lm_mesh_destroy(copy);
    return st;
}

static lm_status job_stages(co_job *j, co_job_summary *summary)
{
    lm_status st = load_original(j);
    if (st == LM_OK)
        st = make_key(j);
    if (st == LM_OK && j->o.resume_path)
        st = co_checkpoint_verify(j->o.resume_path, &j->key);
    if (st == LM_OK)
        st = make_pool(j);
    if (st == LM_OK)
        st = make_coarse_mesh(j);
    if (st == LM_OK)
        st = make_views(j);
    if (st == LM_OK)
        st = make_optimizer(j);
    if (st != LM_OK)
        return st;
    /* The time limit counts set-up too; the loop gets what is left of it. */
    j->loop_start_s = seconds_since(&j->t0);
    j->loop_cpu_s = process_cpu_s();
    if (j->pool)
        co_pool_mark_loop(j->pool);
    if (j->o.time_limit_s > 0) {
        double left = j->o.time_limit_s - j->loop_start_s;
        j->loop_limit_s = j->rep.time_limit_s = left > 1e-3 ? left : 1e-3;
    }
    const char *reason = NULL;
    st = run_loop(j, &reason);
    if (j->pool)
        co_pool_mark_loop_end(j->pool);
    int suspended = st == LM_OK && strcmp(reason, "suspended") == 0;
    if (st == LM_OK && !suspended && j->validate_every)
        st = validate_final(j);
    if (st == LM_OK && !suspended)
        st = write_output(j);
    if (st != LM_OK)
        return st;
    if (co_pool_interrupt_signal() == SIGUSR1 && !j->checkpoint_path)
        note(j, "warning", "SIGUSR1 without --checkpoint: stopped as for SIGTERM (output written)");
    memset(summary, 0, sizeof *summary);
    lm_optimizer_progress(j->opt, &summary->progress);
    summary->wall_s = seconds_since(&j->t0);
    summary->optimize_s = summary->wall_s - j->loop_start_s;
    summary->loop_cpu_s = process_cpu_s() - j->loop_cpu_s;
    summary->stop_reason = reason;
    summary->output_path = suspended ? NULL : j->o.output_path;
    summary->checkpoint_path = j->checkpoint_path;
    summary->resumed_from_evals = j->resumed_from_evals;
    snprintf(summary->renderer, sizeof summary->renderer, "%s", j->renderer);
    report_workers(j);
    summary->workers = j->rep.n_workers;
    summary->lanes = j->lane_stats;
    co_views_lane_stats(j->views, &summary->lanes);
    co_reporter_summary(&j->rep, summary);
    return LM_OK;
}

/* The phases' meter speaks as the reporter does. */
static co_meter_style meter_style(co_report_style s)
{
    return s == CO_REPORT_TTY     ? CO_METER_TTY
           : s == CO_REPORT_LINES ? CO_METER_LINES
           : s == CO_REPORT_JSON  ? CO_METER_JSON
                                  : CO_METER_NONE;
}

lm_status co_job_run(const co_job_options *opts, co_job_summary *summary)
{
    co_job *j = calloc(1, sizeof *j);
    if (!j)
        return lm_fail(LM_E_NOMEM, "out of memory");
    co_pool_catch_signals(); /* SIGINT/SIGTERM end the loop; checkpoint, output and workers follow
                              */
    clock_gettime(CLOCK_MONOTONIC, &j->t0);
    co_job_summary local;
    lm_status st = resolve_options(j, opts, 1);
    if (st == LM_OK) {
        FILE *out = opts->json ? stdout : stderr;
        co_report_style style =
            opts->quiet ? CO_REPORT_QUIET : co_report_style_for(out, opts->json);
        co_reporter_init(&j->rep, style, out, j->o.max_evals, 0.0);
        co_meter_init(&j->meter, "lumesh optimize", meter_style(style), out);
        j->meter_on = 1;
        st = job_stages(j, summary ? summary : &local);
    }
    if (j->meter_on)
        co_meter_destroy(&j->meter);
    if (st == LM_OK)
        co_reporter_end_line(&j->rep);
    else
        co_reporter_abandon_line(&j->rep);
    char why[512] = ""; /* stopping the workers below handles (and clears) errors of its own */
    if (st != LM_OK)
        snprintf(why, sizeof why, "%s", lm_last_error());
    if (j->opt)
        lm_optimizer_destroy(j->opt);
    lm_views_destroy(j->views);
    co_validation_free(&j->val);
    co_bake_loop_destroy(j->bake);
    co_pool_destroy(j->pool);
    free(j->workers);
    if (j->coarse)
        lm_mesh_destroy(j->coarse);
    co_original_pack_free(&j->pack);
    if (j->original)
        lm_mesh_destroy(j->original);
    free(j);
    if (st != LM_OK && why[0])
        lm_fail(st, "%s", why);
    return st;
}

/* The set-up's steps on a quiet job: the original and its attributes, the coarse start prepared,
 * the stage's training views, the optimizer's inputs. */
static lm_status setup_stages(co_job *j, co_job_setup *out)
{
    if (j->o.start == CO_JOB_START_IMAGE && !j->o.initial_path)
        return lm_fail(LM_E_UNSUPPORTED, "the job's set-up without a run takes --start qem, "
                                         "--start adaptive or --initial (the image start prices "
                                         "its collapses on the job's workers)");
    lm_status st = load_original(j);
    if (st == LM_OK)
        st = make_coarse_mesh(j);
    uint32_t count, turn;
    int size;
    stage_views(j, &count, &size, &turn);
    out->views = malloc(sizeof *out->views);
    if (st == LM_OK && !out->views)
        st = lm_fail(LM_E_NOMEM, "out of memory for the view set");
    if (st == LM_OK)
        st = make_view_set(j, count, size, turn, 0, out->views);
    if (st != LM_OK)
        return st;
    optimizer_inputs(j, &out->params, &out->tuning);
    out->o = j->o;
    out->attrs = j->attrs;
    out->regrid_every = j->regrid_every;
    out->original = j->original, j->original = NULL;
    out->coarse = j->coarse, j->coarse = NULL;
    return LM_OK;
}

lm_status co_job_setup_make(const co_job_options *opts, co_job_setup *out)
{
    memset(out, 0, sizeof *out);
    co_job *j = calloc(1, sizeof *j);
    if (!j)
        return lm_fail(LM_E_NOMEM, "out of memory");
    lm_status st = resolve_options(j, opts, 0);
    if (st == LM_OK) {
        co_reporter_init(&j->rep, CO_REPORT_QUIET, stderr, j->o.max_evals, 0.0);
        co_meter_init(&j->meter, "lumesh optimize", CO_METER_NONE, stderr);
        st = setup_stages(j, out);
        co_meter_destroy(&j->meter);
    }
    if (j->coarse)
        lm_mesh_destroy(j->coarse);
    co_original_pack_free(&j->pack);
    if (j->original)
        lm_mesh_destroy(j->original);
    free(j);
    if (st != LM_OK)
        co_job_setup_free(out);
    return st;
}

lm_status co_job_setup_view_set(const co_job_setup *s, uint32_t draw, lm_view_set *out)
{
    co_job *j = calloc(1, sizeof *j);
    if (!j)
        return lm_fail(LM_E_NOMEM, "out of memory");
    j->o = s->o;
    j->original = s->original; /* borrowed: not destroyed here */
    uint32_t count, turn;
    int size;
    stage_views(j, &count, &size, &turn);
    lm_status st = make_view_set(j, count, size, turn, draw, out);
    free(j);
    return st;
}

void co_job_setup_free(co_job_setup *s)
{
    if (s->coarse)
        lm_mesh_destroy(s->coarse);
    if (s->original)
        lm_mesh_destroy(s->original);
    free(s->views);
    memset(s, 0, sizeof *s);
}
