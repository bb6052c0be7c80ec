/* tests/bench/bench_scaling.c — the costs that decide how the job runner scales on a cluster, and
 * the efficiency they predict.
 *
 * A real optimisation (the model simplified by QEM to 1%, in-process views behind a measuring
 * wrapper, the geometric term on as in a job from a QEM start) is run twice, one edge at a time and
 * K edges in flight. For every evaluation batch the wrapper records its patches, the bytes of the
 * Evaluate message a worker would receive (encoded exactly as the remote backend encodes it) and
 * the time the views took; the process CPU outside the views is the coordinator's own work. One
 * worker process then answers small requests over its link (the socketpair local mode uses) and
 * again over the pool's ZeroMQ ipc socket (as workers that connect by address talk), to measure
 * this machine's round trips, and two processes bounce 8 bytes over a plain Unix socket with
 * blocking calls: the least a transport that sleeps between messages pays here (the floor; the link
 * goes under it by spinning and through its shared-memory lane). The link is timed a second time
 * with coordinator and worker on one core: the difference is what waking a sleeping processor costs
 * (on a VM, most of a round trip).
 *
 * The model for W workers over V views, per batch i of n_i patches (perfect balance, a (patch,
 * view) pair the smallest piece of work), the coordinator's work split into the geometric term
 * (geo_i, as the in-process views price it) and the rest; the term is priced where that is
 * faster (surface_term.h): here while the workers render, or by them, each group of views a share
 * of the triangles:
 *     out_i  = RTT + bytes_i * min(W, V) / bandwidth
 *     T_i(W) = rest_i + min(max(geo_i, out_i + n_i * V * c / p_i),
 *                           out_i + (n_i * V * c + geo_i) / p_i),   p_i = min(W, n_i * V)
 * plus, once for the run, the views' other work S (commits, meshes, energies and the oracle's
 * potentials: the workers', each on its share of the views), a round trip per energy or
 * potentials request and the commits' bytes to every group: S / min(W, V) + requests * RTT +
 * commit bytes * min(W, V) / bandwidth (in process: S);
 * against the in-process T_i = rest_i + geo_i + n_i * V * c; speed-up = sum T / sum T(W),
 * efficiency = speed-up / W. Printed for W = 1, 2, 4, 8, 16, 128 at --rtt-us (default 100) and
 * --gbps (default 10), both orders of edges; and for 2 workers at the round trips measured here
 * (ZeroMQ, and the floor): what local multi-process mode can reach on this machine at best (the
 * model gives the coordinator a core of its own, so on a machine with as many cores as workers the
 * real figure is lower).
 *
 * usage: bench_scaling [MODEL] [--evals N] [--in-flight K] [--views N] [--size S] [--rtt-us U]
 *                      [--gbps G] [--device D] [--json] */
#define _GNU_SOURCE
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "common/replica.h"
#include "common/view.h"
#include "coordinator/optimizer/optimizer.h"
#include "coordinator/pool/pool.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/views/views.h"
#include "proto/wire_records.h"

typedef struct opts {
    const char *model, *device;
    uint64_t evals;
    uint32_t in_flight, views, size;
    double rtt_us, gbps;
    int json;
} opts;

/* ---- the measuring views --------------------------------------------------------------------- */

typedef struct meter {
    lm_views base;
    lm_views *in;
    uint32_t *n;     /* patches of batch i */
    uint32_t *bytes; /* its Evaluate message for one worker */
    float *overlap;  /* seconds of the coordinator's work done while batch i is out */
    size_t batches, cap;
    uint64_t patches, commits, commit_bytes;
    uint64_t added, kept_pos; /* added triangle records; of them, with the workers' positions */
    double views_s, views_cpu_s, encode_cpu_s, overlap_cpu_s;
    double state_cpu_s;   /* the views' commits, meshes, energies and potentials: the workers' */
    uint64_t round_trips; /* energy and potentials requests (each a round trip with workers) */
    double overlap_now;   /* the overlap of the batch being evaluated */
    lm_wire_arena arena;
    wk_replica rep; /* the workers' current records, which patches are encoded against */
} meter;

static double wall(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double cpu(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Bytes of an Evaluate (or, with n == 1 and commit, a Commit) message carrying these patches. */
static size_t message_bytes(meter *m, const lm_patch *p, uint32_t n, int commit)
{
    Lumesh__Patch *wp = lm_wire_arena_alloc(&m->arena, n * sizeof *wp);
    Lumesh__Patch **pp = lm_wire_arena_alloc(&m->arena, n * sizeof *pp);
    for (uint32_t i = 0; i < n; i++) {
        lm_wire_patch_encode_against(&p[i], wk_replica_current, &m->rep, &m->arena, &wp[i]);
        pp[i] = &wp[i];
    }
    Lumesh__Evaluate e = LUMESH__EVALUATE__INIT;
    Lumesh__Commit c = LUMESH__COMMIT__INIT;
    e.n_patches = n, e.patches = pp, c.patch = wp;
    lm_msg msg;
    lm_wire_msg_init(&msg, 1, 1, commit ? LUMESH__MSG__BODY_COMMIT : LUMESH__MSG__BODY_EVALUATE,
                     commit ? (void *)&c : (void *)&e);
    size_t bytes = lumesh__msg__get_packed_size(&msg);
    lm_wire_arena_reset(&m->arena);
    return bytes;
}

static lm_status me_evaluate(lm_views *v, const lm_patch *p, uint32_t n, int64_t *d)
{
    meter *m = (meter *)v;
    double c0 = cpu(), t0 = wall();
    lm_status st = m->in->ops->evaluate(m->in, p, n, d);
    m->views_s += wall() - t0;
    double c1 = cpu();
    m->views_cpu_s += c1 - c0;
    if (m->batches == m->cap) {
        m->cap = m->cap ? 2 * m->cap : 4096;
        m->n = realloc(m->n, m->cap * sizeof *m->n);
        m->bytes = realloc(m->bytes, m->cap * sizeof *m->bytes);
        m->overlap = realloc(m->overlap, m->cap * sizeof *m->overlap);
    }
    m->overlap[m->batches] = (float)m->overlap_now;
    m->overlap_now = 0;
    m->n[m->batches] = n;
    m->bytes[m->batches++] = (uint32_t)message_bytes(m, p, n, 0);
    m->encode_cpu_s += cpu() - c1;
    m->patches += n;
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = 0; j < p[i].n_added; j++) {
            const lm_tri_data *cur = wk_replica_current(&m->rep, p[i].added[j].id);
            m->added++;
            m->kept_pos += cur && !memcmp(cur->c[0].pos, p[i].added[j].c[0].pos, 12) &&
                           !memcmp(cur->c[1].pos, p[i].added[j].c[1].pos, 12) &&
                           !memcmp(cur->c[2].pos, p[i].added[j].c[2].pos, 12);
        }
    return st;
}

/* As a remote backend: the caller's overlapped work (the geometric term), timed apart, then the
 * evaluation. */
static lm_status me_evaluate_overlapped(lm_views *v, const lm_patch *p, uint32_t n, int64_t *d,
                                        void (*overlap)(void *ctx), void *ctx)
{
    meter *m = (meter *)v;
    double c0 = cpu();
    if (overlap)
        overlap(ctx);
    m->overlap_now = cpu() - c0;
    m->overlap_cpu_s += m->overlap_now;
    return me_evaluate(v, p, n, d);
}

static lm_status me_commit(lm_views *v, const lm_patch *p)
{
    meter *m = (meter *)v;
    m->commits++;
    m->commit_bytes += message_bytes(m, p, 1, 1);
    lm_status st = wk_replica_apply(&m->rep, p);
    double c0 = cpu();
    if (st == LM_OK)
        st = m->in->ops->commit(m->in, p);
    m->state_cpu_s += cpu() - c0;
    return st;
}

static lm_status me_set_mesh(lm_views *v, const lm_tri_data *t, size_t n)
{
    meter *m = (meter *)v;
    lm_status st = wk_replica_set(&m->rep, t, n);
    double c0 = cpu();
    if (st == LM_OK)
        st = m->in->ops->set_mesh(m->in, t, n);
    m->state_cpu_s += cpu() - c0;
    return st;
}

static lm_status me_set_materials(lm_views *v, const lm_material *mat, uint32_t n)
{
    meter *m = (meter *)v;
    return m->in->ops->set_materials(m->in, mat, n);
}

static lm_status me_energy(lm_views *v, int64_t *t, int64_t *pv)
{
    meter *m = (meter *)v;
    double c0 = cpu();
    lm_status st = m->in->ops->energy(m->in, t, pv);
    m->state_cpu_s += cpu() - c0;
    m->round_trips++;
    return st;
}

static lm_status me_potentials(lm_views *v, const float (*pts)[3], size_t n, int64_t *out)
{
    meter *m = (meter *)v;
    double c0 = cpu();
    lm_status st = m->in->ops->potentials(m->in, pts, n, out);
    m->state_cpu_s += cpu() - c0;
    m->round_trips++;
    return st;
}

static lm_status me_read_image(lm_views *v, lm_image_kind k, uint32_t view, uint8_t *out)
{
    meter *m = (meter *)v;
    return m->in->ops->read_image(m->in, k, view, out);
}

static void me_info(lm_views *v, lm_views_info *out)
{
    meter *m = (meter *)v;
    m->in->ops->info(m->in, out);
}

static void me_destroy(lm_views *v)
{
    (void)v;
}

static const lm_views_ops meter_ops = {
    .set_mesh = me_set_mesh,
    .set_materials = me_set_materials,
    .evaluate = me_evaluate,
    .evaluate_overlapped = me_evaluate_overlapped,
    .commit = me_commit,
    .energy = me_energy,
    .potentials = me_potentials,
    .read_image = me_read_image,
    .info = me_info,
    .destroy = me_destroy,
};

/* ---- runs ------------------------------------------------------------------------------------ */

typedef struct costs {
    uint32_t k;
    uint64_t evals, batches;
    double per_patch_view_us;   /* c */
    double coord_us_per_eval;   /* the optimizer and encoding */
    double overlap_us_per_eval; /* of which the geometric term (the workers' with workers) */
    double bytes_per_batch, patches_per_batch, commit_bytes;
    double tris_per_patch, moved_share; /* added records a patch; share with corners moved */
    double state_us_per_eval;           /* the views' commits, meshes, energies, potentials */
    double round_trips, commits, total_commit_bytes; /* of the run */
    double setup_s;                                  /* the optimizer's set-up, once */
    double t_local_s;                                /* sum of the in-process T_i */
    const meter *m;
} costs;

static lm_status run_once(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                          const lm_view_set *vs, uint32_t k, meter *m, costs *c)
{
    co_views_desc d = {.original = orig,
                       .views = vs,
                       .materials = coarse->materials,
                       .n_materials = coarse->n_materials,
                       .device = o->device};
    lm_mesh *mesh = NULL;
    co_optimizer *opt = NULL;
    memset(m, 0, sizeof *m);
    m->base.ops = &meter_ops;
    lm_wire_arena_init(&m->arena);
    lm_status st = co_views_create(&d, &m->in);
    if (st == LM_OK)
        st = lm_mesh_clone(coarse, &mesh);
    /* as a job from a QEM start: the geometric term on, its weight from CO_SURFACE_SHARE */
    co_params params = {.seed = 1, .edges_in_flight = k, .surface = orig};
    double c_create = cpu();
    if (st == LM_OK)
        st = co_optimizer_create(mesh, &m->base, &params, &opt);
    /* the optimizer's set-up (the start's energies, the term's weight, the edge queue) is done
       once a job: not a cost per evaluation */
    double c0 = cpu(), state0 = m->state_cpu_s;
    uint64_t trips0 = m->round_trips;
    for (int guard = 0; st == LM_OK && guard < 100000; guard++) {
        co_progress p;
        co_optimizer_progress(opt, &p);
        if (p.evals >= o->evals)
            break;
        st = co_optimizer_step(opt, o->evals);
    }
    double total_cpu = cpu() - c0;
    m->state_cpu_s -= state0;
    m->round_trips -= trips0;
    co_optimizer_destroy(opt);
    lm_views_destroy(m->in);
    wk_replica_free(&m->rep);
    if (st != LM_OK)
        return st;
    double views = vs->count, bytes = 0;
    for (size_t i = 0; i < m->batches; i++)
        bytes += m->bytes[i];
    *c = (costs){.k = k, .evals = m->patches, .batches = m->batches, .m = m};
    c->setup_s = c0 - c_create;
    c->per_patch_view_us = 1e6 * m->views_s / ((double)m->patches * views);
    c->coord_us_per_eval = 1e6 * (total_cpu - m->views_cpu_s - m->state_cpu_s) / (double)m->patches;
    c->state_us_per_eval = 1e6 * m->state_cpu_s / (double)m->patches;
    c->round_trips = (double)m->round_trips;
    c->commits = (double)m->commits;
    c->total_commit_bytes = (double)m->commit_bytes;
    c->overlap_us_per_eval = 1e6 * m->overlap_cpu_s / (double)m->patches;
    c->bytes_per_batch = bytes / (double)m->batches;
    c->patches_per_batch = (double)m->patches / (double)m->batches;
    c->commit_bytes = m->commits ? (double)m->commit_bytes / (double)m->commits : 0;
    c->tris_per_patch = (double)m->added / (double)m->patches;
    c->moved_share = m->added ? 1.0 - (double)m->kept_pos / (double)m->added : 0;
    return LM_OK;
}

/* Predicted speed-up over in process for w workers at a round trip of rtt_us. */
static double speedup_at(const opts *o, const costs *c, uint32_t views, uint32_t w, double rtt_us)
{
    double t1 = 0, tw = 0, rtt = rtt_us * 1e-6, bw = o->gbps * 1e9 / 8.0;
    double cost = c->per_patch_view_us * 1e-6;
    double rest = (c->coord_us_per_eval - c->overlap_us_per_eval) * 1e-6; /* the coordinator's */
    for (size_t i = 0; i < c->m->batches; i++) {
        double n = c->m->n[i], work = n * views * cost, geo = c->m->overlap[i];
        double pieces = n * views < w ? n * views : w;
        double ranges = w < views ? w : views;
        double round = rtt + c->m->bytes[i] * ranges / bw; /* the batch out and back */
        double by_workers = round + (work + geo) / pieces, here = round + work / pieces;
        here = here > geo ? here : geo; /* the term priced here while they render */
        t1 += rest * n + geo + work;
        tw += rest * n + (here < by_workers ? here : by_workers);
    }
    /* the views' other work (commits, meshes, energies, potentials) on the workers, each its
       share of the views, with a round trip per request and the commits' bytes to every group */
    double ranges = w < views ? w : views, state = c->state_us_per_eval * 1e-6 * (double)c->evals;
    t1 += state;
    tw += state / ranges + c->round_trips * rtt + c->total_commit_bytes * ranges / bw;
    return t1 / tw;
}

static double speedup(const opts *o, const costs *c, uint32_t views, uint32_t w)
{
    return speedup_at(o, c, views, w, o->rtt_us);
}

/* Round trip of a small request to one local worker process, in µs: over its link (a socketpair,
 * proto/stream.h) as local mode runs, or with socket_only over the pool's ZeroMQ ipc socket, as
 * a worker that connects by address talks. */
static lm_status measure_rtt(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                             const lm_view_set *vs, int socket_only, double *us)
{
    co_pool *pool = NULL;
    lm_views *v = NULL;
    co_pool_options po = {
        .local_workers = 1, .device = o->device, .quiet = 1, .socket_only = socket_only};
    lm_status st = co_pool_create(&po, &pool);
    if (st == LM_OK)
        st = co_pool_wait(pool, 1, 60);
    co_views_desc d = {.kind = CO_VIEWS_REMOTE,
                       .original = orig,
                       .views = vs,
                       .mesh = coarse,
                       .materials = coarse->materials,
                       .n_materials = coarse->n_materials,
                       .pool = pool};
    if (st == LM_OK)
        st = co_views_create(&d, &v);
    lm_patch none; /* an empty patch: a whole Evaluate round trip, next to no rendering */
    lm_patch_init(&none);
    int64_t delta;
    if (st == LM_OK) /* warm */
        st = v->ops->evaluate(v, &none, 1, &delta);
    double t0 = wall();
    const int reps = 1000;
    for (int i = 0; i < reps && st == LM_OK; i++)
        st = v->ops->evaluate(v, &none, 1, &delta);
    *us = 1e6 * (wall() - t0) / reps;
    lm_patch_free(&none);
    lm_views_destroy(v);
    co_pool_destroy(pool);
    return st;
}

/* The link's round trip with this process, and so the worker it starts, on the first core it
 * may use (then given back all of them); 0 where affinity cannot be set. */
static lm_status measure_rtt_one_core(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                                      const lm_view_set *vs, double *us)
{
    cpu_set_t all, one;
    *us = 0;
    if (sched_getaffinity(0, sizeof all, &all) != 0)
        return LM_OK;
    CPU_ZERO(&one);
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, &all)) {
            CPU_SET(c, &one);
            break;
        }
    if (sched_setaffinity(0, sizeof one, &one) != 0)
        return LM_OK;
    lm_status st = measure_rtt(o, orig, coarse, vs, 0, us);
    sched_setaffinity(0, sizeof all, &all);
    return st;
}

/* Round trip of 8 bytes between this process and a child over a Unix socket pair, in µs: no
 * library, no I/O thread, two wake-ups per trip. */
static lm_status measure_floor_rtt(double *us)
{
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM, 0, sv) != 0)
        return lm_fail(LM_E_IO, "cannot make a socket pair");
    const int reps = 2000;
    char b[8] = {0};
    pid_t pid = fork();
    if (pid == 0) {
        close(sv[0]);
        for (int i = 0; i < reps; i++)
            if (read(sv[1], b, sizeof b) != (ssize_t)sizeof b ||
                write(sv[1], b, sizeof b) != (ssize_t)sizeof b)
                _exit(1);
        _exit(0);
    }
    close(sv[1]);
    int ok = pid > 0;
    double t0 = wall();
    for (int i = 0; i < reps && ok; i++)
        ok = write(sv[0], b, sizeof b) == (ssize_t)sizeof b &&
             read(sv[0], b, sizeof b) == (ssize_t)sizeof b;
    *us = 1e6 * (wall() - t0) / reps;
    close(sv[0]);
    int status = 0;
    if (pid > 0)
        waitpid(pid, &status, 0);
    return ok && WIFEXITED(status) && WEXITSTATUS(status) == 0
               ? LM_OK
               : lm_fail(LM_E_IO, "the socket-pair round trip failed");
}

/* ---- report ---------------------------------------------------------------------------------- */

static const uint32_t workers[] = {1, 2, 4, 8, 16, 128};
#define N_W (sizeof workers / sizeof *workers)

/* Round trips measured here, in µs. */
typedef struct rtts {
    double link, zmq, floor; /* a local worker's link, the ZeroMQ ipc socket, a bare socketpair */
    double link_one_core;    /* the link, coordinator and worker on one core (0: not measured) */
} rtts;

static void print_human(const opts *o, const costs *c, uint32_t views, const rtts *t)
{
    printf(
        "bench scaling: %s, %u views of %u px, %llu evaluations per run; round trip here "
        "(small request) %.0f us over a local worker's link (%.0f us with both on one core), "
        "%.0f us over ZeroMQ ipc, %.0f us over a plain Unix socket, asleep between (the floor)\n",
        o->model, views, o->size, (unsigned long long)o->evals, t->link, t->link_one_core, t->zmq,
        t->floor);
    for (int r = 0; r < 2; r++) {
        const costs *x = &c[r];
        printf(
            "  %u in flight: %.1f us per (patch, view); coordinator %.1f us per evaluation in "
            "process (%.1f of it the geometric term, which workers can price) and %.1f us of the "
            "views' commits and oracle, which workers do; %.1f patches and "
            "%.0f bytes per batch (%.0f per commit); %.1f triangles a patch, %.0f%% of them "
            "moved; the optimizer's set-up %.2f s, once\n",
            x->k, x->per_patch_view_us, x->coord_us_per_eval, x->overlap_us_per_eval,
            x->state_us_per_eval, x->patches_per_batch, x->bytes_per_batch, x->commit_bytes,
            x->tris_per_patch, 100.0 * x->moved_share, x->setup_s);
        printf("    predicted at %.0f us RTT, %.0f Gb/s:", o->rtt_us, o->gbps);
        for (size_t i = 0; i < N_W; i++) {
            double s = speedup(o, x, views, workers[i]);
            printf(" %u: x%.1f (%.0f%%)", workers[i], s, 100.0 * s / workers[i]);
        }
        printf("\n    2 workers at best on this machine: x%.2f over links, x%.2f over ZeroMQ, "
               "x%.2f at the floor\n",
               speedup_at(o, x, views, 2, t->link), speedup_at(o, x, views, 2, t->zmq),
               speedup_at(o, x, views, 2, t->floor));
    }
}

static void print_json(const opts *o, const costs *c, uint32_t views, const rtts *t)
{
    printf("{\"bench\": \"scaling\", \"model\": \"%s\", \"views\": %u, \"size\": %u, "
           "\"evals\": %llu, \"rtt_here_us\": %.1f, \"rtt_one_core_us\": %.1f, \"zmq_rtt_us\": "
           "%.1f, \"floor_rtt_us\": %.1f, \"model_rtt_us\": %.1f, \"model_gbps\": %.1f, "
           "\"runs\": [",
           o->model, views, o->size, (unsigned long long)o->evals, t->link, t->link_one_core,
           t->zmq, t->floor, o->rtt_us, o->gbps);
    for (int r = 0; r < 2; r++) {
        const costs *x = &c[r];
        printf("%s{\"edges_in_flight\": %u, \"us_per_patch_view\": %.3f, "
               "\"coordinator_us_per_eval\": %.3f, \"geometric_us_per_eval\": %.3f, "
               "\"patches_per_batch\": %.3f, "
               "\"bytes_per_batch\": %.1f, \"bytes_per_commit\": %.1f, "
               "\"tris_per_patch\": %.2f, \"moved_share\": %.3f, \"state_us_per_eval\": %.3f, "
               "\"two_workers_here\": %.3f, \"two_workers_zmq\": %.3f, "
               "\"two_workers_floor\": %.3f, \"predicted\": [",
               r ? ", " : "", x->k, x->per_patch_view_us, x->coord_us_per_eval,
               x->overlap_us_per_eval, x->patches_per_batch, x->bytes_per_batch, x->commit_bytes,
               x->tris_per_patch, x->moved_share, x->state_us_per_eval,
               speedup_at(o, x, views, 2, t->link), speedup_at(o, x, views, 2, t->zmq),
               speedup_at(o, x, views, 2, t->floor));
        for (size_t i = 0; i < N_W; i++) {
            double s = speedup(o, x, views, workers[i]);
            printf("%s{\"workers\": %u, \"speedup\": %.3f, \"efficiency\": %.3f}", i ? ", " : "",
                   workers[i], s, s / workers[i]);
        }
        printf("]}");
    }
    printf("]}\n");
}

/* ---- main ------------------------------------------------------------------------------------ */

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
        else if (v && !strcmp(a, "--views"))
            o->views = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--size"))
            o->size = (uint32_t)atoi(argv[++i]);
        else if (v && !strcmp(a, "--rtt-us"))
            o->rtt_us = atof(argv[++i]);
        else if (v && !strcmp(a, "--gbps"))
            o->gbps = atof(argv[++i]);
        else if (v && !strcmp(a, "--device"))
            o->device = argv[++i];
        else if (a[0] != '-')
            o->model = a;
        else
            return fprintf(stderr, "bench_scaling: unknown argument '%s'\n", a), 1;
    }
    if (!o->model || !o->evals || o->in_flight < 1 || o->in_flight > CO_MAX_EDGES_IN_FLIGHT ||
        o->views < 1 || o->views > LM_MAX_VIEWS || o->size < 16)
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

int main(int argc, char **argv)
{
    opts o = {.model = getenv("LUMESH_TEST_DATA") ? NULL : "tests/data/cache/meshes/bunny00.off",
              .device = "auto",
              .evals = 3000,
              .in_flight = 8,
              .views = LM_DEFAULT_VIEWS,
              .size = LM_DEFAULT_VIEW_SIZE,
              .rtt_us = 100,
              .gbps = 10};
    char buf[4096];
    if (!o.model) {
        snprintf(buf, sizeof buf, "%s/cache/meshes/bunny00.off", getenv("LUMESH_TEST_DATA"));
        o.model = buf;
    }
    if (parse(argc, argv, &o))
        return 1;
    lm_mesh *orig = NULL, *coarse = NULL;
    static lm_view_set vs;
    static meter m[2];
    costs c[2];
    rtts t = {0, 0, 0, 0};
    lm_status st = setup(&o, &orig, &coarse, &vs);
    uint32_t ks[2] = {1, o.in_flight};
    for (int r = 0; r < 2 && st == LM_OK; r++)
        st = run_once(&o, orig, coarse, &vs, ks[r], &m[r], &c[r]);
    if (st == LM_OK)
        st = measure_rtt(&o, orig, coarse, &vs, 0, &t.link);
    if (st == LM_OK)
        st = measure_rtt_one_core(&o, orig, coarse, &vs, &t.link_one_core);
    if (st == LM_OK)
        st = measure_rtt(&o, orig, coarse, &vs, 1, &t.zmq);
    if (st == LM_OK)
        st = measure_floor_rtt(&t.floor);
    if (st != LM_OK) {
        fprintf(stderr, "bench_scaling: %s\n", lm_last_error());
        return 2;
    }
    if (o.json)
        print_json(&o, c, vs.count, &t);
    else
        print_human(&o, c, vs.count, &t);
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
