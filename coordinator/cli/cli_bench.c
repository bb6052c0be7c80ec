/* coordinator/cli/cli_bench.c — `lumesh bench eval [--json] [--model FILE] [--views N] [--size S]
 * [--evals N] [--device D] [--seed S]`: how fast the views evaluate ΔE for the optimizer's typical
 * move. The model (default: the CGAL bunny from the test data) is simplified by QEM to 1% of its
 * vertices; each evaluation moves one random vertex by a small random displacement (a third of a
 * mean edge at most) and re-evaluates its 1-ring, as the downhill simplex does. Reports
 * evaluations per second (one per readback, and four per readback), the time of a full re-render
 * of every view and the speed-up of an incremental evaluation over it. */
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "common/patch.h"
#include "common/view.h"
#include "coordinator/cli/bench_moves.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/job/progress.h"
#include "coordinator/pool/pool.h"
#include "coordinator/quality/view_setup.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/views/views.h"

#define CMD "bench"
#define BENCH_PATCHES 512
#define BENCH_MAX_RUNS 10 /* worker counts measured: 1, 2, 4, ... 256 and N */
#define BENCH_ROUNDS 3    /* with --workers: rounds of every worker count in turn (--rounds) */
#define BENCH_MAX_ROUNDS 20
#define BUNNY_REL "tests/data/cache/meshes/bunny00.off"

typedef struct bench_args {
    const char *model, *device;
    lm_view_spec views;
    uint32_t size, evals, workers, rounds;
    uint64_t seed;
    int json;
} bench_args;

typedef struct bench_result {
    uint32_t workers;
    uint32_t orig_tris, coarse_verts, coarse_tris;
    double full_ms, evals_per_s, evals_per_s_batch, commits_per_s, tris_per_eval;
    double regions_per_eval, pixels_per_region, evals_per_cpu_s;
    double ratio, ratio_batch; /* to one worker, paired within each round (--workers) */
    char renderer[128];
} bench_result;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: lumesh bench eval [--json] [--model FILE] [--views N] [--size S] [--evals N]\n"
            "                         [--device D] [--seed S] [--workers N [--rounds R]]\n"
            "Measures incremental ΔE evaluations per second for single-vertex moves (1-ring\n"
            "patches) on MODEL simplified by QEM to 1%% of its vertices, and a full re-render.\n"
            "  --model FILE   default: the CGAL bunny of the test data (" BUNNY_REL "),\n"
            "                 from LUMESH_TEST_DATA if set, else the current folder, the folders\n"
            "                 above the program or the source tree it was built from\n"
            "  --views N      default %u, --size S default %d, --evals N default 5000;\n"
            "                 --views upper[:N] or --views-from FILE as lumesh optimize\n"
            "  --device D     auto (default), cpu, egl:N or host;  --json  one JSON object\n"
            "  --workers N    through lumesh-worker processes: measured with 1, 2, 4, ... and N\n"
            "                 workers (each rendering on one core), with the ratio to 1 worker\n"
            "  --rounds R     with --workers: every worker count measured R times in turn\n"
            "                 (1, 2, ... N, 1, 2, ...; default %d); the medians are printed, and\n"
            "                 the median of the ratios to 1 worker taken within each round, so\n"
            "                 that a drift of the machine's speed moves both sides of a ratio\n",
            LM_DEFAULT_VIEWS, LM_DEFAULT_VIEW_SIZE, BENCH_ROUNDS);
}

static const co_cli_spec spec = {CMD, usage, 0, 0, NULL, NULL, 1};

static int parse(int argc, char **argv, bench_args *a)
{
    const co_opt opts[] = {
        CO_OPT_STR("model", 0, &a->model),
        CO_OPT_VIEWS(&a->views),
        CO_OPT_SIZE(&a->size),
        CO_OPT_U32("evals", 0, &a->evals, 1, 100000000),
        CO_OPT_SEED(&a->seed, 0),
        CO_OPT_DEVICE(&a->device),
        CO_OPT_FLAG("json", 0, &a->json),
        CO_OPT_U32("workers", 0, &a->workers, 1, 256),
        CO_OPT_U32("rounds", 0, &a->rounds, 1, BENCH_MAX_ROUNDS),
    };
    if (argc < 2 || (strcmp(argv[1], "eval") && strcmp(argv[1], "--help") && strcmp(argv[1], "-h")))
        return co_cli_usage_error(CMD, "expects a benchmark name: eval (see --help)");
    if (strcmp(argv[1], "eval")) {
        usage(stdout);
        return 0;
    }
    optind = 2;
    return co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
}

/* The bunny of the test data. LUMESH_TEST_DATA, when set, is the only place looked at; otherwise
 * the current folder, the folders above the program (a build folder inside the source tree) and
 * the source tree the program was built from. */
static const char *default_model(char *buf, size_t cap)
{
    const char *env = getenv("LUMESH_TEST_DATA");
    if (env && *env) {
        snprintf(buf, cap, "%s/cache/meshes/bunny00.off", env);
        return access(buf, R_OK) == 0 ? buf : NULL;
    }
    if (access(BUNNY_REL, R_OK) == 0)
        return BUNNY_REL;
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    for (int up = 1; n > 0 && up <= 3; up++) {
        exe[n] = 0;
        char *slash = strrchr(exe, '/');
        if (!slash)
            break;
        *slash = 0;
        n = (ssize_t)(slash - exe);
        snprintf(buf, cap, "%s/%s", exe, BUNNY_REL);
        if (access(buf, R_OK) == 0)
            return buf;
    }
    snprintf(buf, cap, "%s/%s", LUMESH_SOURCE_DIR, BUNNY_REL);
    return access(buf, R_OK) == 0 ? buf : NULL;
}

static int model_not_found(void)
{
    const char *env = getenv("LUMESH_TEST_DATA");
    if (env && *env)
        return co_cli_usage_error(CMD,
                                  "LUMESH_TEST_DATA=%s has no cache/meshes/bunny00.off (the "
                                  "bunny); run scripts/install-deps.sh or pass --model FILE",
                                  env);
    return co_cli_usage_error(CMD,
                              "the bunny (" BUNNY_REL ") is not in the current folder, above the "
                              "program or in %s; run scripts/install-deps.sh there, set "
                              "LUMESH_TEST_DATA=DIR/tests/data or pass --model FILE",
                              LUMESH_SOURCE_DIR);
}

/* Mean time of a full re-render (set_mesh) of every view, in ms. */
static lm_status time_full(lm_views *v, const lm_mesh *coarse, double *ms)
{
    const int reps = 10;
    lm_status st = LM_OK;
    double t0 = co_now_s();
    for (int i = 0; st == LM_OK && i < reps; i++)
        st = lm_views_set_mesh_from(v, coarse);
    *ms = (co_now_s() - t0) * 1000.0 / reps;
    return st;
}

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Evaluations per second (wall clock, and per second of this process's CPU time when cpu_rate is
 * not NULL), `batch` patches per evaluate call, n evaluations in all. */
static lm_status time_evals(lm_views *v, const lm_patch *p, uint32_t np, uint32_t n, uint32_t batch,
                            double *rate, double *cpu_rate)
{
    double c0 = cpu_s();
    int64_t delta[8];
    lm_status st = LM_OK;
    uint32_t done = 0, k = 0;
    double t0 = co_now_s();
    while (st == LM_OK && done < n) {
        uint32_t b = batch < n - done ? batch : n - done;
        if (k + b > np)
            k = 0;
        st = v->ops->evaluate(v, p + k, b, delta);
        k += b;
        done += b;
    }
    *rate = done / (co_now_s() - t0);
    if (cpu_rate)
        *cpu_rate = done / (cpu_s() - c0);
    return st;
}

/* Evaluate and commit (each commit reuses its evaluation's pixels), commits per second. */
static lm_status time_commits(lm_views *v, const lm_patch *p, uint32_t n, double *rate)
{
    int64_t delta;
    lm_status st = LM_OK;
    double t0 = co_now_s();
    for (uint32_t i = 0; st == LM_OK && i < n; i++) {
        st = v->ops->evaluate(v, &p[i], 1, &delta);
        if (st == LM_OK)
            st = v->ops->commit(v, &p[i]);
    }
    *rate = n / (co_now_s() - t0);
    return st;
}

static lm_status measure(const bench_args *a, lm_views *v, const lm_mesh *coarse, bench_result *r)
{
    lm_patch p[BENCH_PATCHES];
    for (int i = 0; i < BENCH_PATCHES; i++)
        lm_patch_init(&p[i]);
    lm_status st = co_bench_vertex_moves(coarse, a->seed, p, BENCH_PATCHES);
    double warm;
    if (st == LM_OK)
        st = time_full(v, coarse, &r->full_ms);
    if (st == LM_OK)
        st = time_evals(v, p, BENCH_PATCHES, 200, 1, &warm, NULL);
    lm_views_info s0, s1;
    v->ops->info(v, &s0);
    if (st == LM_OK)
        st = time_evals(v, p, BENCH_PATCHES, a->evals, 1, &r->evals_per_s, &r->evals_per_cpu_s);
    v->ops->info(v, &s1);
    r->tris_per_eval = (double)(s1.tris_drawn - s0.tris_drawn) / (s1.evaluations - s0.evaluations);
    r->regions_per_eval = (double)(s1.regions - s0.regions) / (s1.evaluations - s0.evaluations);
    r->pixels_per_region =
        (double)(s1.region_pixels - s0.region_pixels) / (s1.regions - s0.regions);
    if (st == LM_OK)
        st = time_evals(v, p, BENCH_PATCHES, a->evals, 4, &r->evals_per_s_batch, NULL);
    /* commits change the mesh: they come last, each patch at most once */
    if (st == LM_OK)
        st = time_commits(v, p, BENCH_PATCHES / 2, &r->commits_per_s);
    for (int i = 0; i < BENCH_PATCHES; i++)
        lm_patch_free(&p[i]);
    return st;
}

static void report(const bench_args *a, const char *model, const bench_result *r)
{
    double speedup = r->full_ms * r->evals_per_s / 1000.0;
    const char *lp = getenv("LP_NUM_THREADS");
    if (!a->json) {
        printf("bench eval: %s (%u tris) -> QEM %u verts / %u tris, %u views of %u px, %s\n"
               "  full re-render: %.3f ms\n"
               "  evaluations:    %.0f /s (one per readback; %.0f per CPU second), %.0f /s (4 per "
               "readback), %.1f tris drawn each\n"
               "  regions:        %.1f per evaluation, %.0f pixels each\n"
               "  commits:        %.0f /s (evaluate + commit)\n"
               "  speed-up vs full re-render: %.1fx\n",
               model, r->orig_tris, r->coarse_verts, r->coarse_tris, a->views.count, a->size,
               r->renderer, r->full_ms, r->evals_per_s, r->evals_per_cpu_s, r->evals_per_s_batch,
               r->tris_per_eval, r->regions_per_eval, r->pixels_per_region, r->commits_per_s,
               speedup);
        return;
    }
    printf("{\"bench\": \"eval\", \"model\": ");
    co_json_string(stdout, model);
    printf(", \"original_tris\": %u, \"coarse_verts\": %u, \"coarse_tris\": %u, \"views\": %u, "
           "\"size\": %u, \"evals\": %u, \"evals_per_s\": %.1f, \"evals_per_cpu_s\": %.1f, "
           "\"evals_per_s_batch4\": %.1f, "
           "\"commits_per_s\": %.1f, \"tris_per_eval\": %.1f, \"regions_per_eval\": %.1f, "
           "\"pixels_per_region\": %.1f, \"full_render_ms\": %.3f, "
           "\"speedup_vs_full\": %.2f, \"lp_num_threads\": ",
           r->orig_tris, r->coarse_verts, r->coarse_tris, a->views.count, a->size, a->evals,
           r->evals_per_s, r->evals_per_cpu_s, r->evals_per_s_batch, r->commits_per_s,
           r->tris_per_eval, r->regions_per_eval, r->pixels_per_region, r->full_ms, speedup);
    co_json_string(stdout, lp ? lp : "");
    co_json_end_with_renderer(stdout, r->renderer);
}

/* One line (or JSON record) per worker count, with the ratio to one worker. */
static void report_workers(const bench_args *a, const char *model, const bench_result *r)
{
    uint32_t n = 0;
    while (n < BENCH_MAX_RUNS && r[n].workers)
        n++;
    if (!a->json) {
        printf("bench eval: %s (%u tris) -> QEM %u verts, %u views of %u px, through workers on "
               "%s; medians of %u rounds\n",
               model, r[0].orig_tris, r[0].coarse_verts, a->views.count, a->size, r[0].renderer,
               a->rounds);
        for (uint32_t i = 0; i < n; i++)
            printf("  %3u worker%s %7.0f evals/s (x%.2f), %7.0f /s in batches of 4 (x%.2f)\n",
                   r[i].workers, r[i].workers == 1 ? ": " : "s:", r[i].evals_per_s, r[i].ratio,
                   r[i].evals_per_s_batch, r[i].ratio_batch);
        return;
    }
    printf("{\"bench\": \"eval\", \"model\": ");
    co_json_string(stdout, model);
    printf(", \"views\": %u, \"size\": %u, \"evals\": %u, \"rounds\": %u, \"renderer\": ",
           a->views.count, a->size, a->evals, a->rounds);
    co_json_string(stdout, r[0].renderer);
    printf(", \"runs\": [");
    for (uint32_t i = 0; i < n; i++)
        printf("%s{\"workers\": %u, \"evals_per_s\": %.1f, \"ratio\": %.3f, "
               "\"evals_per_s_batch4\": %.1f, \"ratio_batch4\": %.3f, \"commits_per_s\": %.1f}",
               i ? ", " : "", r[i].workers, r[i].evals_per_s, r[i].ratio, r[i].evals_per_s_batch,
               r[i].ratio_batch, r[i].commits_per_s);
    printf("]}\n");
}

/* Views of orig with coarse set, in process (workers 0) or through a pool of local workers. */
static lm_status make_views(const bench_args *a, const lm_mesh *orig, const lm_mesh *coarse,
                            const lm_view_set *vs, uint32_t workers, co_pool **pool, lm_views **v)
{
    co_views_desc d = {.original = orig,
                       .views = vs,
                       .materials = coarse->materials,
                       .n_materials = coarse->n_materials,
                       .mesh = coarse,
                       .device = a->device};
    lm_status st = LM_OK;
    if (workers) {
        co_pool_options po = {.local_workers = workers, .device = a->device, .quiet = 1};
        st = co_pool_create(&po, pool);
        if (st == LM_OK)
            st = co_pool_wait(*pool, workers, 60);
        d.kind = CO_VIEWS_REMOTE;
        d.pool = *pool;
    }
    return st == LM_OK ? co_views_create(&d, v) : st;
}

static lm_status measure_with(const bench_args *a, const lm_mesh *orig, const lm_mesh *coarse,
                              const lm_view_set *vs, uint32_t workers, bench_result *r)
{
    co_pool *pool = NULL;
    lm_views *v = NULL;
    lm_status st = make_views(a, orig, coarse, vs, workers, &pool, &v);
    if (st == LM_OK) {
        lm_views_info info;
        v->ops->info(v, &info);
        snprintf(r->renderer, sizeof r->renderer, "%s", info.renderer);
        r->orig_tris = orig->live_tris;
        r->coarse_verts = coarse->live_verts;
        r->coarse_tris = coarse->live_tris;
        st = measure(a, v, coarse, r);
    }
    lm_views_destroy(v);
    co_pool_destroy(pool);
    return st;
}

/* The median of x[0..n) (sorted in place; n >= 1). */
static double median(double *x, uint32_t n)
{
    for (uint32_t i = 1; i < n; i++)
        for (uint32_t j = i; j > 0 && x[j] < x[j - 1]; j--) {
            double t = x[j];
            x[j] = x[j - 1];
            x[j - 1] = t;
        }
    return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

/* r[i]: worker count i's figures as the medians over the rounds rr[k][i], and its ratios to one
 * worker as the medians of the ratios within each round. */
static void combine_rounds(const bench_result (*rr)[BENCH_MAX_RUNS], uint32_t rounds, uint32_t n,
                           bench_result *r)
{
    double x[6][BENCH_MAX_ROUNDS];
    for (uint32_t i = 0; i < n; i++) {
        r[i] = rr[0][i];
        for (uint32_t k = 0; k < rounds; k++) {
            const bench_result *q = &rr[k][i], *one = &rr[k][0];
            x[0][k] = q->evals_per_s, x[1][k] = q->evals_per_s_batch;
            x[2][k] = q->commits_per_s, x[3][k] = q->evals_per_cpu_s;
            x[4][k] = q->evals_per_s / one->evals_per_s;
            x[5][k] = q->evals_per_s_batch / one->evals_per_s_batch;
        }
        r[i].evals_per_s = median(x[0], rounds), r[i].evals_per_s_batch = median(x[1], rounds);
        r[i].commits_per_s = median(x[2], rounds), r[i].evals_per_cpu_s = median(x[3], rounds);
        r[i].ratio = median(x[4], rounds), r[i].ratio_batch = median(x[5], rounds);
    }
}

/* Round k: one result per worker count, 0 (in process) or 1, 2, 4, ... and a->workers, into
 * out[0..*n). */
static lm_status measure_round(const bench_args *a, const lm_mesh *orig, const lm_mesh *coarse,
                               const lm_view_set *vs, bench_result *out, uint32_t *n)
{
    lm_status st = LM_OK;
    *n = 0;
    for (uint32_t w = a->workers ? 1 : 0; st == LM_OK && *n < BENCH_MAX_RUNS;) {
        st = measure_with(a, orig, coarse, vs, w, &out[*n]);
        out[(*n)++].workers = w;
        if (w == a->workers)
            break;
        w = 2 * w < a->workers ? 2 * w : a->workers;
    }
    return st;
}

static lm_status run(const bench_args *a, const char *model_path, bench_result *r)
{
    lm_mesh *orig = NULL, *coarse = NULL;
    lm_view_set *vs = NULL;
    uint32_t rounds = a->workers ? a->rounds : 1, n = 0;
    bench_result(*rr)[BENCH_MAX_RUNS] = calloc(rounds, sizeof *rr);
    lm_status st = rr ? lm_mesh_load(model_path, NULL, &orig)
                      : lm_fail(LM_E_NOMEM, "out of memory for the results");
    if (st == LM_OK) {
        uint32_t target = orig->live_verts / 100 > 4 ? orig->live_verts / 100 : 4;
        st = co_simplify(orig, CO_SIMPLIFY_QEM, target, &coarse);
        if (st == LM_E_RANGE && coarse)
            st = LM_OK; /* near enough for a benchmark */
    }
    if (st == LM_OK)
        st = lm_mesh_build_adjacency(coarse);
    if (st == LM_OK)
        st = co_view_set_of(orig, &a->views, (int)a->size, LM_VIEWS_TRAINING, &vs);
    for (uint32_t k = 0; st == LM_OK && k < rounds; k++)
        st = measure_round(a, orig, coarse, vs, rr[k], &n);
    if (st == LM_OK)
        combine_rounds((const bench_result(*)[BENCH_MAX_RUNS])rr, rounds, n, r);
    free(rr);
    free(vs);
    lm_mesh_destroy(orig);
    lm_mesh_destroy(coarse);
    return st;
}

int co_cli_bench(int argc, char **argv)
{
    bench_args a = {.views = {.count = LM_DEFAULT_VIEWS},
                    .size = LM_DEFAULT_VIEW_SIZE,
                    .evals = 5000,
                    .rounds = BENCH_ROUNDS,
                    .seed = 1,
                    .device = "auto"};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    char buf[PATH_MAX + 64];
    const char *model = a.model ? a.model : default_model(buf, sizeof buf);
    if (!model)
        return model_not_found();
    bench_result r[BENCH_MAX_RUNS] = {0};
    lm_status st = run(&a, model, r);
    if (st != LM_OK)
        return co_cli_fail(CMD, st);
    if (a.workers)
        report_workers(&a, model, r);
    else
        report(&a, model, &r[0]);
    return 0;
}
