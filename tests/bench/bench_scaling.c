/* tests/bench/bench_scaling.c — the costs that decide how the job runner scales on a cluster, and
 * the efficiency they predict.
 *
 * A real optimisation (the model simplified by QEM to 1%, or to --target-verts, in-process views
 * behind a measuring wrapper, scaling/meter.c; the geometric term on as in a job from a QEM start)
 * is run twice, one edge at a time and K edges in flight, for today's schedule (one evaluation the
 * unit of remote work; the run and its model: scaling/per_eval.c), and a third time, one edge at a
 * time, for the whole-edge schedules: the costs of every edge (scaling/edge_costs.c). This
 * machine's round trips are measured (scaling/rtt.c). The whole edges are modelled in rounds with
 * a barrier (scaling/rounds.c) and, with --schedule window, without one: a lag of D edges between
 * an edge and the mesh it is optimised against, on nodes of G processes that share the views
 * (scaling/window.c). The report (scaling/report.c) gives, per modelled worker count, the speed-up
 * over one process and the efficiency, and the coordinator's CPU per evaluation. With
 * --schedule lanes, instead of all that: the real isolated-lane engine run at each K of
 * --lanes-k on the job's own set-up (co_job_setup_make: `lumesh optimize`'s start, attributes,
 * views, tuning and regrids, its defaults resolved where the job resolves them), then the same job
 * as `--lanes remote` runs it on --coordinator-workers local workers for the coordinator's own CPU
 * (scaling/lanes_run.c), and the whole-lane schedule modelled from both (scaling/lanes_model.c).
 *
 * usage: bench_scaling [MODEL] [--evals N] [--in-flight K] [--views N] [--size S] [--rtt-us U]
 *                      [--gbps G] [--device D] [--edge-evals N] [--round R] [--target-verts N]
 *                      [--schedule rounds|window|lanes] [--lag D] [--group G] [--sync-us S]
 *                      [--cap N] [--lanes-k K,...] [--lanes-per-worker L] [--plan N]
 *                      [--lanes-detached] [--initial MESH | --start qem|adaptive]
 *                      [--regrid-every N] [--coordinator-workers N] [--json]
 * (--edge-evals: the whole-edge run's evaluations, default 30000; --target-verts: the QEM start's
 * vertices, default 1% of the model's, at least 100; --schedule window adds the window model at
 * --lag (default 1024) and --group (processes per node, default 1), and over lags 64..4096 and
 * nodes of 1, 4 and 16; --sync-us: a node's synchronisation per evaluation, default the measured
 * round trip of a local worker's link; --cap: visits of at most N evaluations, the rest of an
 * edge a continuation later in plan order, scaling/visits.c; --cap, --lag and --group take
 * comma-separated lists, e.g. --cap 16,64 --lag 256,4096 --group 1,4, and with --cap the window
 * is modelled for every (N, D, G) of them from the one measurement; a single --lag and --group
 * are the first of theirs; --lanes-k: the edges in flight of the lanes' runs, 2..1024, default
 * 2,8,16,64; --lanes-per-worker: K = workers x L in the predictions, default 1; --plan: the lanes'
 * runs' edges per iteration, the plan their groups are taken from, default the optimizer's 64;
 * --lanes-detached: every lane as --lanes remote runs it, through its request and result messages
 * and a lane host of its own (lm_optimizer_set_lanes_detached), so that a lane's cost is a
 * worker's: its start taken from the request, the encodings; with --schedule lanes: --views and
 * --size default to the job's (0: theirs), --initial MESH starts from a saved coarse mesh (as
 * `optimize --initial`), else --start qem (the default here) or adaptive simplifies the model to
 * --target-verts (the job's default without it; the image start is refused: it prices its
 * collapses on workers), --regrid-every N the job's regrids (default the job's, 0 never),
 * --coordinator-workers N the remote run's local workers (default 2, 0: no remote run, the
 * coordinator then only its in-process planning and merge); LUMESH_WORKER names the worker
 * program, else this build's) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "common/optimizer/optimizer.h"
#include "coordinator/simplify/simplify.h"
#include "scaling/scaling.h"

/* A comma-separated list of at most SC_MAX_LIST values; *first the first. Their count. */
static uint32_t parse_list(const char *s, uint32_t *out, uint32_t *first)
{
    uint32_t n = 0;
    for (char *end; n < SC_MAX_LIST; s = end + 1) {
        out[n++] = (uint32_t)strtoul(s, &end, 10);
        if (*end != ',')
            break;
    }
    if (first)
        *first = out[0];
    return n;
}

/* Every value of the list at least 1. */
static int positive(const uint32_t *v, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        if (v[i] < 1)
            return 0;
    return 1;
}

/* Every K of --lanes-k in 2..LM_MAX_EDGES_IN_FLIGHT. */
static int lanes_k_ok(const opts *o)
{
    for (uint32_t i = 0; i < o->n_lanes_k; i++)
        if (o->lanes_k[i] < 2 || o->lanes_k[i] > LM_MAX_EDGES_IN_FLIGHT)
            return 0;
    return 1;
}

static int parse(int argc, char **argv, opts *o)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--json"))
            o->json = 1;
        else if (v && !strcmp(a, "--evals"))
            o->evals = strtoull(argv[++i], NULL, 10);
        else if (v && !strcmp(a, "--in-flight"))
            o->in_flight = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--edge-evals"))
            o->edge_evals = strtoull(argv[++i], NULL, 10);
        else if (v && !strcmp(a, "--round"))
            o->round = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--target-verts"))
            o->target_verts = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--views"))
            o->views = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--size"))
            o->size = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--rtt-us"))
            o->rtt_us = atof(argv[++i]);
        else if (v && !strcmp(a, "--gbps"))
            o->gbps = atof(argv[++i]);
        else if (v && !strcmp(a, "--schedule")) {
            const char *s = argv[++i];
            o->schedule = !strcmp(s, "window")  ? SCHEDULE_WINDOW
                          : !strcmp(s, "lanes") ? SCHEDULE_LANES
                                                : SCHEDULE_ROUNDS;
            if (strcmp(s, "window") && strcmp(s, "rounds") && strcmp(s, "lanes"))
                return fprintf(stderr, "bench_scaling: unknown schedule '%s'\n", s), 1;
        } else if (v && !strcmp(a, "--lag"))
            o->n_lags = parse_list(argv[++i], o->lags, &o->lag);
        else if (v && !strcmp(a, "--group"))
            o->n_groups = parse_list(argv[++i], o->groups, &o->group);
        else if (v && !strcmp(a, "--cap"))
            o->n_caps = parse_list(argv[++i], o->caps, NULL);
        else if (v && !strcmp(a, "--lanes-k"))
            o->n_lanes_k = parse_list(argv[++i], o->lanes_k, NULL);
        else if (v && !strcmp(a, "--plan"))
            o->plan = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--initial"))
            o->initial = argv[++i];
        else if (v && !strcmp(a, "--start")) {
            const char *s = argv[++i];
            o->start = !strcmp(s, "qem") ? CO_JOB_START_QEM : CO_JOB_START_ADAPTIVE;
            if (strcmp(s, "qem") && strcmp(s, "adaptive"))
                return fprintf(stderr, "bench_scaling: --start takes qem or adaptive, not '%s'\n",
                               s),
                       1;
        } else if (v && !strcmp(a, "--regrid-every")) {
            o->regrid_every = strtoull(argv[++i], NULL, 10);
            o->regrid_set = 1;
        } else if (v && !strcmp(a, "--coordinator-workers"))
            o->coordinator_workers = (uint32_t)atoi(argv[++i]);
        else if (!strcmp(a, "--lanes-detached"))
            o->lanes_detached = 1;
        else if (v && !strcmp(a, "--lanes-per-worker"))
            o->lanes_per_worker = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--sync-us"))
            o->sync_us = atof(argv[++i]);
        else if (v && !strcmp(a, "--device"))
            o->device = argv[++i];
        else if (a[0] != '-')
            o->model = a;
        else
            return fprintf(stderr, "bench_scaling: unknown argument '%s'\n", a), 1;
    }
    if (!o->model || !o->evals || !o->edge_evals || o->round < 1 || o->round > 65536 ||
        o->in_flight < 1 || !positive(o->lags, o->n_lags) || !positive(o->groups, o->n_groups) ||
        o->in_flight > LM_MAX_EDGES_IN_FLIGHT || o->views > LM_MAX_VIEWS ||
        (o->size && o->size < 16) || (o->initial && o->target_verts) || !lanes_k_ok(o) ||
        o->lanes_per_worker < 1)
        return fprintf(stderr, "bench_scaling: bad arguments (see the comment at the top of "
                               "tests/bench/bench_scaling.c)\n"),
               1;
    return 0;
}

static lm_status setup(const opts *o, lm_mesh **orig, lm_mesh **coarse, lm_view_set *vs)
{
    lm_status st = lm_mesh_load(o->model, NULL, orig);
    if (st == LM_OK) {
        uint32_t target = (*orig)->live_verts / 100 > 100 ? (*orig)->live_verts / 100 : 100;
        target = o->target_verts ? o->target_verts : target;
        st = co_simplify(*orig, CO_SIMPLIFY_QEM, target, coarse);
        if (st == LM_E_RANGE && *coarse)
            st = LM_OK;
    }
    if (st == LM_OK)
        st = lm_mesh_build_adjacency(*coarse);
    float c[3], r;
    if (st == LM_OK) {
        lm_mesh_bounding_sphere(*orig, c, &r);
        st = lm_view_set_make(vs, o->views, (int)o->size, c, r);
    }
    return st;
}

/* --schedule lanes: the isolated-lane runs on the job's set-up, one at a time, and their model. */
static int run_lanes(const opts *o)
{
    co_job_setup js;
    static lanes_run runs[SC_MAX_LIST], remote[SC_MAX_LIST];
    lm_status st = sc_job_setup(o, &js);
    uint32_t n = 0;
    for (; n < o->n_lanes_k && st == LM_OK; n++)
        st = sc_run_lanes(o, &js, o->lanes_k[n], &runs[n]);
    for (uint32_t i = 0; i < n && st == LM_OK && o->coordinator_workers; i++) {
        st = sc_run_lanes_remote(o, &js, o->lanes_k[i], o->coordinator_workers, &remote[i]);
        runs[i].coord = &remote[i];
    }
    uint32_t views = st == LM_OK ? js.views->count : 0;
    if (st != LM_OK)
        fprintf(stderr, "bench_scaling: %s\n", lm_last_error());
    else if (o->json)
        sc_print_lanes_json(o, &js, runs, n, views);
    else
        sc_print_lanes_human(o, &js, runs, n, views);
    for (uint32_t i = 0; i < n; i++)
        sc_lanes_free(&runs[i]), sc_lanes_free(&remote[i]);
    co_job_setup_free(&js);
    return st == LM_OK ? 0 : 2;
}

int main(int argc, char **argv)
{
    opts o = {.model = getenv("LUMESH_TEST_DATA") ? NULL : "tests/data/cache/meshes/bunny00.off",
              .device = "auto",
              .evals = 3000,
              .edge_evals = 30000,
              .round = 256,
              .in_flight = 8,
              .start = CO_JOB_START_QEM,
              .coordinator_workers = 2,
              .rtt_us = 100,
              .gbps = 10,
              .schedule = SCHEDULE_ROUNDS,
              .lag = 1024,
              .group = 1,
              .lags = {1024},
              .groups = {1},
              .caps = {0},
              .n_lags = 1,
              .n_groups = 1,
              .n_caps = 1,
              .sync_us = -1,
              .lanes_k = {2, 8, 16, 64},
              .n_lanes_k = 4,
              .lanes_per_worker = 1};
    char buf[4096];
    if (!o.model) {
        snprintf(buf, sizeof buf, "%s/cache/meshes/bunny00.off", getenv("LUMESH_TEST_DATA"));
        o.model = buf;
    }
    if (parse(argc, argv, &o))
        return 1;
    if (o.schedule == SCHEDULE_LANES) /* the views' defaults: the job's (co_job_setup_make) */
        return run_lanes(&o);
    o.views = o.views ? o.views : LM_DEFAULT_VIEWS;
    o.size = o.size ? o.size : LM_DEFAULT_VIEW_SIZE;
    lm_mesh *orig = NULL, *coarse = NULL;
    static lm_view_set vs;
    static meter m[3];
    static edges_run er;
    costs c[2];
    rtts t = {0, 0, 0, 0};
    lm_status st = setup(&o, &orig, &coarse, &vs);
    uint32_t ks[2] = {1, o.in_flight};
    for (int r = 0; r < 2 && st == LM_OK; r++)
        st = sc_run_once(&o, orig, coarse, &vs, ks[r], &m[r], &c[r]);
    if (st == LM_OK)
        st = sc_run_edges(&o, orig, coarse, &vs, &m[2], &er);
    if (st == LM_OK)
        st = sc_measure_rtt(&o, orig, coarse, &vs, 0, &t.link);
    if (st == LM_OK)
        st = sc_measure_rtt_one_core(&o, orig, coarse, &vs, &t.link_one_core);
    if (st == LM_OK)
        st = sc_measure_rtt(&o, orig, coarse, &vs, 1, &t.zmq);
    if (st == LM_OK)
        st = sc_measure_floor_rtt(&t.floor);
    if (st != LM_OK) {
        fprintf(stderr, "bench_scaling: %s\n", lm_last_error());
        return 2;
    }
    if (o.json)
        sc_print_json(&o, c, vs.count, &t, &er);
    else
        sc_print_human(&o, c, vs.count, &t, &er);
    free(er.e);
    free(er.last);
    for (int r = 0; r < 2; r++) {
        free(m[r].n);
        free(m[r].bytes);
        free(m[r].overlap);
        lm_wire_arena_free(&m[r].arena);
    }
    lm_mesh_destroy(orig);
    lm_mesh_destroy(coarse);
    return 0;
}
