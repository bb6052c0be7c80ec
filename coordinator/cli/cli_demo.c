/* coordinator/cli/cli_demo.c — `lumesh demo`: generate the frog, simplify it with QEM, optimise the
 * coarse mesh, and write the three models, a before/after picture grid, a close-up of the coarse
 * mesh's worst cracks, a summary with held-out energies and crack pixels (views not used by
 * the optimisation), and the quality report (DIR/report/index.html). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/folders.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/frog/frog.h"
#include "coordinator/job/job.h"
#include "coordinator/job/job_log.h"
#include "coordinator/quality/compare.h"
#include "coordinator/quality/report.h"
#include "coordinator/simplify/simplify.h"

#define CO_DEMO_TRIS 20000u
#define CO_DEMO_TARGET 300u
#define CO_DEMO_EVALS 40000ull
#define CO_DEMO_GRID_VIEWS 4u

typedef struct demo_options {
    const char *dir;
    uint64_t evals;
    lm_view_spec views;
    uint32_t tris, target_verts, size;
    uint64_t seed;
    const char *device;
    uint32_t workers; /* co_job_options.workers */
} demo_options;

typedef struct demo_paths {
    char frog[4096], coarse[4096], optimized[4096], grid[4096], closeup[4096], report[4096];
} demo_paths;

#define CMD "demo"

static const char co_demo_help[] =
    "usage: lumesh demo [-o DIR] [--evals N] [--tris N] [--target-verts N] [--views N]\n"
    "                   [--size PIXELS] [--seed S] [--device D] [--workers N]\n"
    "\n"
    "Generate the procedural frog (separate, interpenetrating body, legs and eyes with a "
    "texture),\n"
    "simplify it with QEM, optimise the coarse mesh so that its images match the frog's, and "
    "write\n"
    "into DIR: frog.obj, coarse.obj, optimized.obj (each with .mtl and texture) and\n"
    "before_after.png (one row per view: original | coarse | optimized) and closeup.png (the\n"
    "window, at 4x the view size, where the coarse mesh shows the most cracks and holes). Prints\n"
    "the image energy of the coarse and optimised models over 24 held-out views that the\n"
    "optimisation never saw, and their cracks and holes: pixels inside the frog's silhouette\n"
    "where the model shows the background. The quality report (lumesh report --help) goes to\n"
    "DIR/report/index.html: open it in a browser.\n"
    "\n"
    "  -o, --output DIR     output folder, created with its parents if needed\n"
    "                       (default ./lumesh-demo)\n"
    "  --evals N            optimisation budget in energy evaluations (default %llu)\n"
    "  --tris N             triangles of the generated frog (default %u)\n"
    "  --target-verts N     vertices of the QEM coarse mesh (default %u)\n"
    "  --views N            optimisation views (default %u); upper[:N]: on the hemisphere\n"
    "                       above the frog (+Y up), the held-out views mirrored into it\n"
    "  --views-from FILE    the cameras of a JSON file instead (as lumesh optimize)\n"
    "  --size PIXELS        side of every view image (default %d)\n"
    "  --seed S             seed of the frog and of the optimiser (default 1)\n"
    "  --device D           rendering device: auto, cpu, host, egl:N (default auto)\n"
    "  --workers N          lumesh-worker processes rendering the views (default one per\n"
    "                       core; 0 = in this process); the result is the same for any N\n"
    "  -h, --help           this help\n";

static void usage(FILE *f)
{
    fprintf(f, co_demo_help, (unsigned long long)CO_DEMO_EVALS, CO_DEMO_TRIS, CO_DEMO_TARGET,
            CO_JOB_DEFAULT_VIEWS, CO_JOB_DEFAULT_SIZE);
}

static const co_cli_spec spec = {CMD, usage, 0, 0, NULL, NULL, 0};

/* Returns -1 to go on, 0 after --help, or an exit code. */
static int parse_args(int argc, char **argv, demo_options *o)
{
    *o = (demo_options){.dir = "lumesh-demo",
                        .evals = CO_DEMO_EVALS,
                        .tris = CO_DEMO_TRIS,
                        .target_verts = CO_DEMO_TARGET,
                        .views = {.count = CO_JOB_DEFAULT_VIEWS},
                        .size = CO_JOB_DEFAULT_SIZE,
                        .seed = 1,
                        .device = "auto"};
    const co_opt opts[] = {
        CO_OPT_OUTPUT(&o->dir),
        CO_OPT_EVALS(&o->evals),
        CO_OPT_U32("tris", 0, &o->tris, CO_FROG_MIN_TRIS, CO_FROG_MAX_TRIS),
        CO_OPT_U32("target-verts", 0, &o->target_verts, 4, LM_MESH_MAX_VERTS),
        CO_OPT_VIEWS(&o->views),
        CO_OPT_SIZE(&o->size),
        CO_OPT_SEED(&o->seed, 1),
        CO_OPT_DEVICE(&o->device),
        CO_OPT_JOB_WORKERS(&o->workers),
    };
    return co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
}

static lm_status make_paths(const char *dir, demo_paths *p)
{
    lm_status st = lm_make_folders(dir);
    if (st != LM_OK)
        return st;
    int n = snprintf(p->frog, sizeof p->frog, "%s/frog.obj", dir);
    snprintf(p->coarse, sizeof p->coarse, "%s/coarse.obj", dir);
    snprintf(p->optimized, sizeof p->optimized, "%s/optimized.obj", dir);
    snprintf(p->grid, sizeof p->grid, "%s/before_after.png", dir);
    snprintf(p->closeup, sizeof p->closeup, "%s/closeup.png", dir);
    snprintf(p->report, sizeof p->report, "%s/report", dir);
    if (n < 0 || (size_t)n + 16 >= sizeof p->frog)
        return lm_fail(LM_E_INVALID, "folder name '%s' is too long", dir);
    return LM_OK;
}

/* frog.obj and its QEM simplification coarse.obj. */
static lm_status make_inputs(const demo_options *o, const demo_paths *p)
{
    lm_mesh *frog = NULL, *coarse = NULL;
    printf("generating the frog (%" PRIu32 " triangles) and simplifying it to %" PRIu32
           " vertices...\n",
           o->tris, o->target_verts);
    fflush(stdout);
    lm_status st = co_frog_generate(o->tris, o->seed, &frog);
    if (st == LM_OK)
        st = lm_mesh_save(p->frog, frog);
    if (st == LM_OK) {
        st = co_simplify(frog, CO_SIMPLIFY_QEM, o->target_verts, &coarse);
        if (st == LM_E_RANGE && coarse) /* close enough: the best QEM could do */
            st = LM_OK;
    }
    if (st == LM_OK)
        st = lm_mesh_save(p->coarse, coarse);
    if (coarse)
        lm_mesh_destroy(coarse);
    if (frog)
        lm_mesh_destroy(frog);
    return st;
}

static lm_status optimize(const demo_options *o, const demo_paths *p, co_job_summary *s,
                          co_run_log *log)
{
    co_job_options jo = {
        .original_path = p->frog,
        .output_path = p->optimized,
        .initial_path = p->coarse,
        .views = o->views,
        .size = (int)o->size,
        .max_evals = o->evals,
        .seed = o->seed,
        .device_spec = o->device,
        .workers = o->workers,
        .on_progress = co_job_log_progress,
        .progress_ctx = log,
    };
    printf("optimising (%" PRIu64 " evaluations, %" PRIu32 " views of %" PRIu32 "x%" PRIu32
           ")...\n",
           o->evals, o->views.count, o->size, o->size);
    fflush(stdout);
    return co_job_run(&jo, s);
}

typedef struct demo_models {
    lm_mesh *frog, *coarse, *optimized;
} demo_models;

static void free_models(demo_models *m)
{
    if (m->frog)
        lm_mesh_destroy(m->frog);
    if (m->coarse)
        lm_mesh_destroy(m->coarse);
    if (m->optimized)
        lm_mesh_destroy(m->optimized);
}

/* What the demo measured on the files as written. */
typedef struct demo_judgement {
    int64_t heldout[2]; /* coarse, optimised */
    co_coverage cov[2];
    co_crop closeup;
    uint64_t closeup_missing; /* the coarse mesh's uncovered pixels in the close-up */
} demo_judgement;

#define CO_DEMO_ZOOM 4 /* close-up: views rendered this many times larger, one view-size window */

/* The before/after grid and the close-up of the coarse mesh's worst cracks. */
static lm_status write_pictures(const demo_options *o, const demo_paths *p, const lm_mesh *frog,
                                const lm_mesh *const models[2], lm_view_set *vs, demo_judgement *j)
{
    float centre[3], radius = 0;
    lm_mesh_bounding_sphere(frog, centre, &radius);
    lm_image *grid = NULL;
    lm_status st = lm_view_set_make(vs, CO_DEMO_GRID_VIEWS, (int)o->size, centre, radius);
    if (st == LM_OK)
        st = co_compare_grid(frog, vs, o->device, models, 2, NULL, &grid);
    if (st == LM_OK)
        st = lm_image_write(p->grid, grid);
    lm_image_destroy(grid);
    grid = NULL;
    int big = (int)o->size * CO_DEMO_ZOOM;
    if (st == LM_OK && big <= LM_MAX_VIEW_SIZE) {
        st = lm_view_set_make(vs, CO_DEMO_GRID_VIEWS, big, centre, radius);
        if (st == LM_OK)
            st = co_compare_find_cracks(frog, vs, o->device, models[0], (int)o->size, &j->closeup,
                                        &j->closeup_missing);
        if (st == LM_OK)
            st = co_compare_grid(frog, vs, o->device, models, 2, &j->closeup, &grid);
        if (st == LM_OK)
            st = lm_image_write(p->closeup, grid);
        lm_image_destroy(grid);
    }
    return st;
}

/* Held-out energies and coverage of coarse and optimised, and the pictures. */
static lm_status evaluate(const demo_options *o, const demo_paths *p, demo_judgement *j)
{
    demo_models m = {0};
    lm_status st = lm_mesh_load(p->frog, NULL, &m.frog);
    if (st == LM_OK)
        st = lm_mesh_load(p->coarse, NULL, &m.coarse);
    if (st == LM_OK)
        st = lm_mesh_load(p->optimized, NULL, &m.optimized);
    lm_view_set *vs = st == LM_OK ? malloc(sizeof *vs) : NULL;
    if (st == LM_OK && !vs)
        st = lm_fail(LM_E_NOMEM, "out of memory");
    float centre[3], radius = 0;
    if (st == LM_OK) {
        lm_mesh_bounding_sphere(m.frog, centre, &radius);
        st = lm_view_set_make_spec(vs, &o->views, LM_VIEWS_HELDOUT, (int)o->size, centre, radius);
    }
    const lm_mesh *const models[2] = {m.coarse, m.optimized};
    if (st == LM_OK)
        st = co_compare_energies(m.frog, vs, o->device, models, 2, j->heldout, NULL, j->cov, NULL);
    if (st == LM_OK)
        st = write_pictures(o, p, m.frog, models, vs, j);
    free(vs);
    free_models(&m);
    return st;
}

static double percent(double part, double whole)
{
    return whole > 0 ? 100.0 * part / whole : 100.0;
}

static void print_summary(const demo_options *o, const demo_paths *p, const co_job_summary *s,
                          const demo_judgement *j)
{
    printf("\nheld-out energy (24 views of %" PRIu32 "x%" PRIu32 " not used by the optimisation):\n"
           "  coarse    %" PRId64 "\n  optimized %" PRId64 "  (%.1f%% of coarse)\n",
           o->size, o->size, j->heldout[0], j->heldout[1],
           percent((double)j->heldout[1], (double)j->heldout[0]));
    printf("cracks and holes (held-out pixels inside the frog's silhouette where the model shows\n"
           "the background):\n  coarse    %" PRIu64 "\n  optimized %" PRIu64
           "  (%.1f%% of coarse; outline pixels missing: %" PRIu64 " -> %" PRIu64 ")\n",
           j->cov[0].cracks_px, j->cov[1].cracks_px,
           percent((double)j->cov[1].cracks_px, (double)j->cov[0].cracks_px), j->cov[0].missing_px,
           j->cov[1].missing_px);
    printf("optimisation: %" PRIu64 " evaluations in %.1f s on %" PRIu32 " worker%s, %s\n",
           s->progress.evals, s->wall_s, s->workers, s->workers == 1 ? "" : "s", s->renderer);
    printf("files in %s:\n  %s\n  %s\n  %s\n  %s  (rows: %u views; columns: original | coarse | "
           "optimized)\n",
           o->dir, p->frog, p->coarse, p->optimized, p->grid, CO_DEMO_GRID_VIEWS);
    if (j->closeup.w > 0)
        printf("  %s  (view %u at %dx, window at (%d, %d): original | coarse | optimized)\n",
               p->closeup, j->closeup.view, CO_DEMO_ZOOM, j->closeup.x, j->closeup.y);
}

/* The quality report of the three files; returns its page's path in page. */
static lm_status report(const demo_options *o, const demo_paths *p, const co_job_summary *s,
                        co_run_log *log, char *page, size_t cap)
{
    co_job_log_finish(log, s);
    co_report_options ro = {.original = p->frog,
                            .initial = p->coarse,
                            .optimized = p->optimized,
                            .log = log,
                            .device = o->device,
                            .size = (int)o->size,
                            .dir = p->report,
                            .views = o->views};
    printf("writing the quality report...\n");
    fflush(stdout);
    return co_report_write(&ro, page, cap);
}

int co_cli_demo(int argc, char **argv)
{
    demo_options o;
    int rc = parse_args(argc, argv, &o);
    if (rc >= 0)
        return rc;
    demo_paths p;
    co_job_summary s;
    demo_judgement j = {0};
    co_run_log log;
    co_run_log_init(&log);
    char page[4096];
    lm_status st = make_paths(o.dir, &p);
    if (st == LM_OK)
        st = make_inputs(&o, &p);
    if (st == LM_OK)
        st = optimize(&o, &p, &s, &log);
    if (st == LM_OK)
        st = evaluate(&o, &p, &j);
    if (st == LM_OK)
        st = report(&o, &p, &s, &log, page, sizeof page);
    co_run_log_free(&log);
    if (st != LM_OK)
        return co_cli_fail(CMD, st);
    print_summary(&o, &p, &s, &j);
    printf("\nquality report: %s  (open it in a browser)\n", page);
    return 0;
}
