/* tests/bench/bench_scaling.c — the costs that decide how the job runner scales on a cluster, and
 * the efficiency they predict.
 *
 * A real optimisation (the model simplified by QEM to 1%, or to --target-verts, in-process views
 * behind a measuring wrapper, the geometric term on as in a job from a QEM start) is run twice, one
 * edge at a time and K edges in flight, for today's schedule (one evaluation the unit of remote
 * work), and a third time for the whole-edge schedule (below). For every evaluation batch the
 * wrapper records its patches, the bytes of the Evaluate message a worker would receive (encoded
 * exactly as the remote backend encodes it) and the time the views took; the process CPU outside
 * the views is the coordinator's own work. One worker process then answers small requests over its
 * link (the socketpair local mode uses) and again over the pool's ZeroMQ ipc socket (as workers
 * that connect by address talk), to measure this machine's round trips, and two processes bounce 8
 * bytes over a plain Unix socket with blocking calls: the least a transport that sleeps between
 * messages pays here (the floor; the link goes under it by spinning and through its shared-memory
 * lane). The link is timed a second time with coordinator and worker on one core: the difference is
 * what waking a sleeping processor costs (on a VM, most of a round trip).
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
 * The whole-edge schedule (issue 36): a worker holding all V views optimises whole edges against
 * the round's start; the coordinator merges them in plan order. The third run, one edge at a
 * time, one planned edge per co_optimizer_step (the evaluation budget stops a step between edges;
 * a planned edge gone before its turn costs nothing and goes with the next), until --edge-evals,
 * records for every edge e: its evaluations; cost_e, its cost in process on one worker (the
 * views' time and all the edge's other CPU: simplex, moves, geometric term, commits; not the
 * meter's encoding); when an iteration began before it, the planning: plan_e, the coordinator's
 * CPU around the oracle's potentials, and pot_e, their views' work; apply_e, the views' CPU of its
 * commits (what every worker spends applying them); b_e, the bytes of its Commit messages; and
 * merge_e, the coordinator's merge: its accepted operations (the optimizer's move observer) done
 * again with co_moves_replay on a copy of the mesh as lanes.c merges them, the patch of the lot
 * (checked against the optimizer's mesh: the mismatches are printed), encoded twice (the
 * re-validation's Evaluate, the Commit) with the replica it is encoded against. The measured
 * sequence, cycled to whole rounds, is cut into rounds of R planned edges; round j, its
 * k_j = (edges that kept operations) - 1 re-validations (the first merge needs none), on W
 * workers:
 *     T_j(W) = sum plan_e + P_j * RTT + sum pot_e / min(W, V)               planning
 *            + RTT + (W * B_{j-1} + 16 R) / bandwidth                       handing out
 *            + A_{j-1}                                                      the last commits
 *            + makespan_W + B_j / bandwidth                                 the edges
 *            + sum merge_e                                                  merging
 *            + [k_j > 0] (RTT + k_j (V c + g) / min(W, k_j V)
 *                         + B_j * min(W, V) / bandwidth)                    re-validating
 * with P_j the potentials requests, B_j = sum b_e, A_j = sum apply_e (round j - 1 of the cycle
 * before the first), makespan_W the list schedule of the cost_e in plan order (each to the worker
 * free first), c the cost per (patch, view) and g the geometric term per evaluation of this run;
 * in process sum (cost_e + plan_e + pot_e). Speed-up = sum in process / sum T_j(W), efficiency =
 * speed-up / W; the coordinator's CPU per evaluation = sum (plan_e + merge_e) / (evaluations +
 * re-validations). Printed for rounds of 64, --round (default 256) and 1024 edges, where the time
 * of 16 and 128 workers goes at --round, and the smallest round (a power of 2, at most 65536)
 * that reaches efficiency 0.8 on 16 workers and 0.6 on 128 (with the efficiencies at 65536).
 *
 * usage: bench_scaling [MODEL] [--evals N] [--in-flight K] [--views N] [--size S] [--rtt-us U]
 *                      [--gbps G] [--device D] [--edge-evals N] [--round R] [--target-verts N]
 *                      [--json]
 * (--edge-evals: the whole-edge run's evaluations, default 30000; --target-verts: the QEM start's
 * vertices, default 1% of the model's, at least 100) */
#define _GNU_SOURCE
#include <sched.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "common/grow.h"
#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "common/replica.h"
#include "common/view.h"
#include "coordinator/optimizer/optimizer.h"
#include "coordinator/optimizer/optimizer_internal.h" /* read only: the move observer, the plan */
#include "coordinator/pool/pool.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/views/views.h"
#include "proto/wire_records.h"

typedef struct opts {
    const char *model, *device;
    uint64_t evals, edge_evals;
    uint32_t in_flight, views, size, round, target_verts;
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
    lm_replica rep; /* the workers' current records, which patches are encoded against */
    /* the whole-edge run's (run_edges): batches are not recorded nor encoded there */
    int light;
    double commit_enc_s;  /* encoding the commits' messages (the coordinator's, with workers) */
    double replica_s;     /* the replica of the workers' records that they are encoded against */
    double state_wall_s;  /* the views' state requests' time (their CPU: state_cpu_s) */
    double commit_wall_s; /* of which the commits: what every worker spends applying them */
    double pot_wall_s;    /* and the potentials: the views' work for the oracle */
    double plan_s;        /* the optimizer's own work around it: the oracle's ranking, the plan */
    double step_c0, pot_end; /* CPU at the step's start, at the end of its potentials */
    int plan_open;           /* potentials done, the optimizer still planning */
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

/* The first request after an iteration's potentials: the planning around them is over. */
static void close_plan(meter *m)
{
    if (m->plan_open)
        m->plan_s += cpu() - m->pot_end;
    m->plan_open = 0;
}

/* A state request (commit, mesh, energy, potentials) that took the views `w` seconds and `c` of
 * CPU from CPU time c0. */
static void state_done(meter *m, double w, double c0, double c1)
{
    m->state_cpu_s += c1 - c0;
    m->state_wall_s += w;
}

/* Bytes of an Evaluate (or, with n == 1 and commit, a Commit) message carrying these patches. */
static size_t message_bytes(meter *m, const lm_patch *p, uint32_t n, int commit)
{
    Lumesh__Patch *wp = lm_wire_arena_alloc(&m->arena, n * sizeof *wp);
    Lumesh__Patch **pp = lm_wire_arena_alloc(&m->arena, n * sizeof *pp);
    for (uint32_t i = 0; i < n; i++) {
        lm_wire_patch_encode_against(&p[i], lm_replica_current, &m->rep, &m->arena, &wp[i]);
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
    close_plan(m);
    double c0 = cpu(), t0 = wall();
    lm_status st = m->in->ops->evaluate(m->in, p, n, d);
    m->views_s += wall() - t0;
    double c1 = cpu();
    m->views_cpu_s += c1 - c0;
    m->patches += n;
    if (m->light) {
        m->overlap_now = 0;
        return st;
    }
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
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = 0; j < p[i].n_added; j++) {
            const lm_tri_data *cur = lm_replica_current(&m->rep, p[i].added[j].id);
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
    close_plan(m);
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
    close_plan(m);
    m->commits++;
    double e0 = cpu();
    m->commit_bytes += message_bytes(m, p, 1, 1);
    double e1 = cpu();
    lm_status st = lm_replica_apply(&m->rep, p);
    double c0 = cpu();
    m->commit_enc_s += e1 - e0;
    m->replica_s += c0 - e1;
    double t0 = wall();
    if (st == LM_OK)
        st = m->in->ops->commit(m->in, p);
    double w = wall() - t0;
    state_done(m, w, c0, cpu());
    m->commit_wall_s += w;
    return st;
}

static lm_status me_set_mesh(lm_views *v, const lm_tri_data *t, size_t n)
{
    meter *m = (meter *)v;
    close_plan(m);
    double r0 = cpu();
    lm_status st = lm_replica_set(&m->rep, t, n);
    double c0 = cpu();
    m->replica_s += c0 - r0;
    double t0 = wall();
    if (st == LM_OK)
        st = m->in->ops->set_mesh(m->in, t, n);
    state_done(m, wall() - t0, c0, cpu());
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
    close_plan(m);
    double c0 = cpu(), t0 = wall();
    lm_status st = m->in->ops->energy(m->in, t, pv);
    state_done(m, wall() - t0, c0, cpu());
    m->round_trips++;
    return st;
}

static lm_status me_potentials(lm_views *v, const float (*pts)[3], size_t n, int64_t *out)
{
    meter *m = (meter *)v;
    close_plan(m);
    double c0 = cpu();
    if (m->light) /* the first request of a step: what came before it was planning */
        m->plan_s += c0 - m->step_c0;
    double t0 = wall();
    lm_status st = m->in->ops->potentials(m->in, pts, n, out);
    double w = wall() - t0, c1 = cpu();
    state_done(m, w, c0, c1);
    m->pot_wall_s += w;
    m->pot_end = c1;
    m->plan_open = m->light;
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

/* The meter over new in-process views, and *mesh a copy of the start for an optimizer. */
static lm_status meter_start(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                             const lm_view_set *vs, int light, meter *m, lm_mesh **mesh)
{
    co_views_desc d = {.original = orig,
                       .views = vs,
                       .materials = coarse->materials,
                       .n_materials = coarse->n_materials,
                       .device = o->device};
    memset(m, 0, sizeof *m);
    m->base.ops = &meter_ops;
    m->light = light;
    lm_wire_arena_init(&m->arena);
    lm_status st = co_views_create(&d, &m->in);
    return st == LM_OK ? lm_mesh_clone(coarse, mesh) : st;
}

static lm_status run_once(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                          const lm_view_set *vs, uint32_t k, meter *m, costs *c)
{
    lm_mesh *mesh = NULL;
    co_optimizer *opt = NULL;
    lm_status st = meter_start(o, orig, coarse, vs, 0, m, &mesh);
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
    lm_replica_free(&m->rep);
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

/* ---- the whole-edge run ---------------------------------------------------------------------- */

/* One step of the optimizer in the whole-edge run: one planned edge (with the planned edges
 * before it that were gone, which cost nothing), its costs in seconds. */
typedef struct edge_rec {
    uint32_t evals, edges, ops; /* evaluations; planned edges; operations it kept (accepted) */
    uint32_t plans;             /* oracle requests before it (an iteration began) */
    float cost_s;  /* in process on one worker: the views' time and all other CPU of the edge */
    float plan_s;  /* the coordinator's planning before it (the oracle's ranking, the plan) */
    float pot_s;   /* the views' work of that planning (potentials) */
    float apply_s; /* the views' commits of its operations: what every worker does to apply them */
    float merge_s; /* the coordinator's merge: replay, patch, encoding (0 without operations) */
    float bytes;   /* its operations' Commit messages (0 without operations) */
} edge_rec;

typedef struct edges_run {
    edge_rec *e;
    size_t n, cap;
    uint64_t evals, planned, replays, mismatches;
    double per_patch_view_us, geo_us_per_eval, replay_s;
    double views_cpu_per_wall; /* the views' evaluations: CPU seconds per second (threads) */
    size_t mesh_edges;         /* of the start */
} edges_run;

/* The accepted operations of the step being run (the optimizer's move observer). */
typedef struct recorded {
    co_move_record r;
    size_t x_at; /* its parameters in x */
} recorded;

typedef struct recorder {
    recorded *r;
    uint32_t n, cap;
    double *x;
    size_t nx, capx;
} recorder;

static void rec_accepted(void *ctx, const co_move_record *r)
{
    recorder *rc = ctx;
    bool grown = LM_GROW32(&rc->r, &rc->cap, (size_t)rc->n + 1, 16) &&
                 LM_GROW(&rc->x, &rc->capx, rc->nx + r->dim, 1024);
    LM_ASSERT(grown);
    memcpy(rc->x + rc->nx, r->x, (size_t)r->dim * sizeof *r->x);
    rc->r[rc->n++] = (recorded){*r, rc->nx};
    rc->nx += r->dim;
}

static void rec_reverted(void *ctx, size_t mark)
{
    recorder *rc = ctx;
    while (rc->n && rc->r[rc->n - 1].r.mark >= mark)
        rc->nx = rc->r[--rc->n].x_at;
}

/* The coordinator's copy of the mesh, on which a worker's operations are done again. */
typedef struct shadow {
    lm_mesh *mesh;
    co_moves *mv;
    lm_patch patch;
} shadow;

static void shadow_free(shadow *s)
{
    co_moves_destroy(s->mv);
    lm_mesh_destroy(s->mesh);
    s->mv = NULL, s->mesh = NULL;
}

static lm_status shadow_make(shadow *s, const co_optimizer *opt, lm_views *v)
{
    shadow_free(s);
    lm_status st = lm_mesh_clone(opt->mesh, &s->mesh);
    return st == LM_OK ? co_moves_create(s->mesh, v, &opt->moves_cfg, &s->mv) : st;
}

/* The step's operations again on the shadow, and the patch of the lot (as a merge does them:
 * coordinator/optimizer/lanes.c); *ok = 0 when one no longer fits. */
static lm_status shadow_replay(shadow *s, const recorder *rc, int *ok)
{
    uint32_t from[64], to[64], nm = 0;
    size_t mark = co_moves_mark(s->mv);
    *ok = 1;
    for (uint32_t i = 0; i < rc->n; i++) {
        co_move_record r = rc->r[i].r;
        for (uint32_t k = 0; k < nm; k++) {
            r.a = r.a == from[k] ? to[k] : r.a;
            r.b = r.b == from[k] ? to[k] : r.b;
        }
        r.x = rc->x + rc->r[i].x_at;
        uint32_t v;
        lm_status st = co_moves_replay(s->mv, &r, &v);
        if (st == LM_E_ILLEGAL) {
            lm_clear_error();
            *ok = 0;
            break;
        }
        if (st != LM_OK)
            return st;
        if (r.kind == CO_MOVE_SPLIT && nm < 64)
            from[nm] = rc->r[i].r.v, to[nm++] = v;
    }
    lm_status st =
        *ok ? lm_patch_from_journal(&s->patch, s->mesh, co_moves_journal(s->mv), mark) : LM_OK;
    co_moves_forget(s->mv);
    return st;
}

/* What the meter has counted so far that an edge's costs are differences of. */
typedef struct tally {
    double cpu, views_s, views_cpu, state_wall, state_cpu, enc, replica, commit, pot, plan, bytes;
    uint64_t patches, commits;
} tally;

static tally tally_of(const meter *m, double c)
{
    return (tally){c,
                   m->views_s,
                   m->views_cpu_s,
                   m->state_wall_s,
                   m->state_cpu_s,
                   m->commit_enc_s,
                   m->replica_s,
                   m->commit_wall_s,
                   m->pot_wall_s,
                   m->plan_s,
                   (double)m->commit_bytes,
                   m->patches,
                   m->commits};
}

/* The step just run as an edge record; the coordinator's replay of its operations timed here. */
static lm_status record_edge(const tally *a, const tally *b, shadow *s, const recorder *rc,
                             const co_optimizer *opt, uint32_t edges, uint32_t plans, edges_run *er)
{
    double r0 = cpu();
    int ok = 1;
    lm_status st = rc->n ? shadow_replay(s, rc, &ok) : LM_OK;
    double replay = cpu() - r0;
    if (st != LM_OK)
        return st;
    er->replays += rc->n;
    er->replay_s += replay;
    if (!ok || lm_mesh_hash(s->mesh) != lm_mesh_hash(opt->mesh)) { /* resynchronised, untimed */
        er->mismatches++;
        if ((st = shadow_make(s, opt, opt->views)) != LM_OK)
            return st;
    }
    if (!LM_GROW(&er->e, &er->cap, er->n + 1, 1024))
        return lm_fail(LM_E_NOMEM, "out of memory for the edges' costs");
    double enc = b->enc - a->enc, replica = b->replica - a->replica, pot = b->pot - a->pot;
    double plan = b->plan - a->plan;
    /* the views' time (evaluations, commits, meshes; not the planning's potentials) and the CPU
       of all the rest but the meter's encoding and the planning */
    double views = (b->views_s - a->views_s) + (b->state_wall - a->state_wall) - pot;
    double other = (b->cpu - a->cpu) - (b->views_cpu - a->views_cpu) -
                   (b->state_cpu - a->state_cpu) - enc - replica - plan;
    er->e[er->n++] = (edge_rec){
        .evals = (uint32_t)(b->patches - a->patches),
        .edges = edges,
        .ops = rc->n,
        .plans = plans,
        .cost_s = (float)(views + other),
        .plan_s = (float)plan,
        .pot_s = (float)pot,
        .apply_s = rc->n ? (float)(b->commit - a->commit) : 0,
        /* the merged patch encoded twice (the re-validation's Evaluate and the Commit) */
        .merge_s = rc->n ? (float)(replay + 2 * enc + replica) : 0,
        .bytes = rc->n ? (float)(b->bytes - a->bytes) : 0};
    return LM_OK;
}

static lm_status run_edge_steps(const opts *o, co_optimizer *opt, meter *m, edges_run *er)
{
    recorder rc = {.n = 0};
    shadow s = {.mesh = NULL};
    lm_patch_init(&s.patch);
    lm_status st = shadow_make(&s, opt, opt->views);
    co_moves_observe(opt->mv, &(co_moves_observer){rec_accepted, rec_reverted, &rc});
    for (int guard = 0; st == LM_OK && guard < 10000000; guard++) {
        co_progress p;
        co_optimizer_progress(opt, &p);
        if (p.evals >= o->edge_evals)
            break;
        uint32_t pos0 = opt->it.active ? opt->it.pos : 0;
        uint64_t trips0 = m->round_trips;
        rc.n = 0, rc.nx = 0;
        double c0 = cpu();
        m->step_c0 = c0;
        tally a = tally_of(m, c0);
        st = co_optimizer_step(opt, p.evals + 1); /* one edge: the budget stops it between edges */
        close_plan(m);
        tally b = tally_of(m, cpu());
        if (st == LM_OK)
            st = record_edge(&a, &b, &s, &rc, opt, opt->it.pos - pos0,
                             (uint32_t)(m->round_trips - trips0), er);
    }
    co_moves_observe(opt->mv, NULL);
    shadow_free(&s);
    lm_patch_free(&s.patch);
    free(rc.r), free(rc.x);
    return st;
}

/* One edge at a time, each optimiser step one edge, until --edge-evals: the costs per edge. */
static lm_status run_edges(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                           const lm_view_set *vs, meter *m, edges_run *er)
{
    lm_mesh *mesh = NULL;
    co_optimizer *opt = NULL;
    memset(er, 0, sizeof *er);
    lm_status st = meter_start(o, orig, coarse, vs, 1, m, &mesh);
    co_params params = {.seed = 1, .edges_in_flight = 1, .surface = orig};
    if (st == LM_OK)
        st = co_optimizer_create(mesh, &m->base, &params, &opt);
    uint32_t(*edges)[2] = NULL;
    if (st == LM_OK)
        st = lm_mesh_list_edges(co_optimizer_mesh(opt), &edges, &er->mesh_edges);
    free(edges);
    m->views_s = m->views_cpu_s = m->overlap_cpu_s = 0;
    m->patches = 0;
    if (st == LM_OK)
        st = run_edge_steps(o, opt, m, er);
    co_optimizer_destroy(opt);
    lm_views_destroy(m->in);
    lm_replica_free(&m->rep);
    lm_wire_arena_free(&m->arena);
    if (st != LM_OK || !er->n || !m->patches)
        return st != LM_OK ? st : lm_fail(LM_E_RANGE, "the whole-edge run evaluated nothing");
    for (size_t i = 0; i < er->n; i++) {
        er->evals += er->e[i].evals;
        er->planned += er->e[i].edges;
    }
    er->per_patch_view_us = 1e6 * m->views_s / ((double)m->patches * vs->count);
    er->geo_us_per_eval = 1e6 * m->overlap_cpu_s / (double)m->patches;
    er->views_cpu_per_wall = m->views_s > 0 ? m->views_cpu_s / m->views_s : 0;
    return LM_OK;
}

/* ---- the edge-at-a-time model ---------------------------------------------------------------- */

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

/* ---- the whole-edge model -------------------------------------------------------------------- */

/* Edge i of the modelled pass: the measured sequence, cycled (a pass of whole rounds). */
static const edge_rec *pass_edge(const edges_run *er, size_t i)
{
    return &er->e[i % er->n];
}

/* One round's sums over its edges. */
typedef struct round_sums {
    double cost, plan, pot, apply, merge, bytes, evals, plans, with_ops;
} round_sums;

static round_sums round_of(const edges_run *er, size_t first, size_t count)
{
    round_sums s = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (size_t i = first; i < first + count; i++) {
        const edge_rec *e = pass_edge(er, i);
        s.cost += e->cost_s, s.plan += e->plan_s, s.pot += e->pot_s, s.apply += e->apply_s;
        s.merge += e->merge_s, s.bytes += e->bytes, s.evals += e->evals, s.plans += e->plans;
        s.with_ops += e->ops > 0;
    }
    return s;
}

/* The workers' makespan of a round: its edges in plan order, each to the worker free first. */
static double makespan(const edges_run *er, size_t first, size_t count, uint32_t w, double *free_at)
{
    double end = 0;
    for (uint32_t k = 0; k < w; k++)
        free_at[k] = 0;
    for (size_t i = first; i < first + count; i++) {
        uint32_t next = 0;
        for (uint32_t k = 1; k < w; k++)
            next = free_at[k] < free_at[next] ? k : next;
        free_at[next] += pass_edge(er, i)->cost_s;
        end = free_at[next] > end ? free_at[next] : end;
    }
    return end;
}

typedef struct whole_edges {
    double t1, tw;          /* the pass in process; with w workers */
    double plan_s, merge_s; /* the coordinator's CPU: planning, merges */
    double evals;           /* evaluations, the merges' re-validations included */
    /* where tw goes: planning (with its requests), handing out (a round trip, the commits'
     * bytes), applying the last round's commits, the edges (makespan, results back), merging,
     * re-validating; and the edges' work spread perfectly (their sum / w) */
    double plan, hand_out, apply, edges, merge, revalidate, balanced;
} whole_edges;

/* The pass as rounds of r edges on w workers over V views (the formula at the top). */
static whole_edges whole_edges_at(const opts *o, const edges_run *er, uint32_t views, uint32_t w,
                                  uint32_t r)
{
    double rtt = o->rtt_us * 1e-6, bw = o->gbps * 1e9 / 8.0, ranges = w < views ? w : views;
    double per_patch = views * er->per_patch_view_us * 1e-6 + er->geo_us_per_eval * 1e-6;
    size_t rounds = (er->n + r - 1) / r;
    double *free_at = calloc(w, sizeof *free_at);
    whole_edges out;
    memset(&out, 0, sizeof out);
    LM_ASSERT(free_at);
    round_sums prev = round_of(er, (rounds - 1) * r, r); /* steady state: the pass cycles */
    for (size_t j = 0; j < rounds; j++) {
        round_sums s = round_of(er, j * r, r);
        double k = s.with_ops > 1 ? s.with_ops - 1 : 0; /* re-validations */
        double pieces = w < k * views ? w : k * views;
        double plan = s.plan + s.plans * rtt + s.pot / ranges;
        double hand_out = rtt + (w * prev.bytes + 16.0 * r) / bw;
        double edges = makespan(er, j * r, r, w, free_at) + s.bytes / bw;
        double revalidate = k ? rtt + k * per_patch / pieces + s.bytes * ranges / bw : 0;
        out.t1 += s.cost + s.plan + s.pot;
        out.tw += plan + hand_out + prev.apply + edges + s.merge + revalidate;
        out.plan += plan, out.hand_out += hand_out, out.apply += prev.apply, out.edges += edges;
        out.merge += s.merge, out.revalidate += revalidate, out.balanced += s.cost / w;
        out.plan_s += s.plan;
        out.merge_s += s.merge;
        out.evals += s.evals + k;
        prev = s;
    }
    free(free_at);
    return out;
}

static double whole_edges_speedup(const opts *o, const edges_run *er, uint32_t views, uint32_t w,
                                  uint32_t r)
{
    whole_edges x = whole_edges_at(o, er, views, w, r);
    return x.t1 / x.tw;
}

/* The smallest round (a power of 2, at most 65536) with efficiency >= eff on w workers; 0 if
 * none. */
static uint32_t round_for(const opts *o, const edges_run *er, uint32_t views, uint32_t w,
                          double eff)
{
    for (uint32_t r = 1; r <= 65536; r *= 2)
        if (whole_edges_speedup(o, er, views, w, r) / w >= eff)
            return r;
    return 0;
}

/* The rounds the report prints: 64, --round, 1024, in order, once each. */
static uint32_t report_rounds(const opts *o, uint32_t out[3])
{
    uint32_t c[3] = {64, o->round, 1024}, n = 0;
    for (int i = 0; i < 3; i++) {
        uint32_t least = 0;
        for (int k = 0; k < 3; k++)
            if (c[k] && (!least || c[k] < least))
                least = c[k];
        if (!least)
            break;
        out[n++] = least;
        for (int k = 0; k < 3; k++)
            c[k] = c[k] == least ? 0 : c[k];
    }
    return n;
}

/* The distribution of the measured edges. */
typedef struct edge_stats {
    double evals_mean, evals_median, evals_p90, evals_p99, evals_max;
    double ms_mean, ms_max, top_share; /* top_share: of all the edges' cost, the costliest 1%'s */
    double ops_mean, with_ops, bytes_mean;
} edge_stats;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static edge_stats edge_stats_of(const edges_run *er)
{
    edge_stats s;
    memset(&s, 0, sizeof s);
    size_t n = er->n, top = n / 100 ? n / 100 : 1;
    double *ev = malloc(n * sizeof *ev), *cost = malloc(n * sizeof *cost);
    LM_ASSERT(ev && cost);
    for (size_t i = 0; i < n; i++) {
        const edge_rec *e = &er->e[i];
        ev[i] = e->evals;
        cost[i] = e->cost_s;
        s.ms_mean += 1e3 * e->cost_s;
        s.ops_mean += e->ops;
        s.with_ops += e->ops > 0;
        s.bytes_mean += e->bytes;
    }
    qsort(ev, n, sizeof *ev, cmp_double);
    qsort(cost, n, sizeof *cost, cmp_double);
    s.evals_median = ev[n / 2], s.evals_p90 = ev[n * 9 / 10], s.evals_p99 = ev[n * 99 / 100];
    s.evals_max = ev[n - 1];
    s.ms_max = 1e3 * cost[n - 1];
    for (size_t i = n - top; i < n; i++)
        s.top_share += 1e3 * cost[i];
    s.top_share /= s.ms_mean;
    free(ev);
    free(cost);
    s.evals_mean = (double)er->evals / (double)er->n;
    s.ms_mean /= (double)er->n;
    s.ops_mean /= (double)er->n;
    s.bytes_mean = s.with_ops ? s.bytes_mean / s.with_ops : 0;
    s.with_ops /= (double)er->n;
    return s;
}

/* ---- round trips ----------------------------------------------------------------------------- */

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

static void print_whole_edges_human(const opts *o, const edges_run *er, uint32_t views);
static void print_whole_edges_json(const opts *o, const edges_run *er, uint32_t views);

static void print_human(const opts *o, const costs *c, uint32_t views, const rtts *t,
                        const edges_run *er)
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
    print_whole_edges_human(o, er, views);
}

static void print_json(const opts *o, const costs *c, uint32_t views, const rtts *t,
                       const edges_run *er)
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
    printf("]");
    print_whole_edges_json(o, er, views);
    printf("}\n");
}

static void print_whole_edges_human(const opts *o, const edges_run *er, uint32_t views)
{
    edge_stats s = edge_stats_of(er);
    whole_edges at = whole_edges_at(o, er, views, 1, o->round);
    printf("  whole edges: %zu edges optimised one at a time over %llu evaluations (%llu planned, "
           "the others gone before their turn; the start has %zu edges): evaluations per edge "
           "mean %.1f, median %.0f, 90th percentile %.0f, 99th %.0f, max %.0f; one edge in "
           "process %.2f ms mean, %.2f ms max, the costliest 1%% of the edges %.0f%% of the work "
           "(%.1f us per (patch, view), the views %.2f CPU seconds a second: under 1, a busy "
           "machine); %.2f operations kept per edge, %.0f%% of the edges keep "
           "some, %.0f bytes of commits each; %llu operations replayed at %.1f us each (%llu "
           "mismatches)\n",
           er->n, (unsigned long long)er->evals, (unsigned long long)er->planned, er->mesh_edges,
           s.evals_mean, s.evals_median, s.evals_p90, s.evals_p99, s.evals_max, s.ms_mean, s.ms_max,
           100.0 * s.top_share, er->per_patch_view_us, er->views_cpu_per_wall, s.ops_mean,
           100.0 * s.with_ops, s.bytes_mean, (unsigned long long)er->replays,
           er->replays ? 1e6 * er->replay_s / (double)er->replays : 0,
           (unsigned long long)er->mismatches);
    printf(
        "    coordinator CPU per evaluation %.2f us (planning %.2f, merges %.2f), rounds of %u\n",
        1e6 * (at.plan_s + at.merge_s) / at.evals, 1e6 * at.plan_s / at.evals,
        1e6 * at.merge_s / at.evals, o->round);
    uint32_t rs[3], nr = report_rounds(o, rs);
    for (uint32_t k = 0; k < nr; k++) {
        printf("    rounds of %u edges, predicted at %.0f us RTT, %.0f Gb/s:", rs[k], o->rtt_us,
               o->gbps);
        for (size_t i = 0; i < N_W; i++) {
            double x = whole_edges_speedup(o, er, views, workers[i], rs[k]);
            printf(" %u: x%.1f (%.0f%%)", workers[i], x, 100.0 * x / workers[i]);
        }
        printf("\n");
    }
    for (uint32_t w = 16; w <= 128; w *= 8) {
        whole_edges x = whole_edges_at(o, er, views, w, o->round);
        printf("    where the time of %u workers goes, rounds of %u: the edges %.0f%% (spread "
               "perfectly %.0f%%), applying the last round's commits %.0f%%, planning %.0f%%, "
               "handing out %.0f%%, merging %.0f%%, re-validating %.0f%%\n",
               w, o->round, 100 * x.edges / x.tw, 100 * x.balanced / x.tw, 100 * x.apply / x.tw,
               100 * x.plan / x.tw, 100 * x.hand_out / x.tw, 100 * x.merge / x.tw,
               100 * x.revalidate / x.tw);
    }
    uint32_t r16 = round_for(o, er, views, 16, 0.8), r128 = round_for(o, er, views, 128, 0.6);
    printf("    smallest round (a power of 2) for efficiency >= 0.8 on 16 workers: %u; >= 0.6 on "
           "128 workers: %u (0: none up to 65536; there, 16 workers %.0f%%, 128 workers %.0f%%)\n",
           r16, r128, 100 * whole_edges_speedup(o, er, views, 16, 65536) / 16,
           100 * whole_edges_speedup(o, er, views, 128, 65536) / 128);
}

static void print_whole_edges_json(const opts *o, const edges_run *er, uint32_t views)
{
    edge_stats s = edge_stats_of(er);
    whole_edges at = whole_edges_at(o, er, views, 1, o->round);
    printf(", \"round\": %u, \"coordinator_cpu_per_eval_us\": %.3f, \"whole_edge_costs\": "
           "{\"edges\": %zu, \"planned_edges\": %llu, \"evals\": %llu, \"mesh_edges\": %zu, "
           "\"evals_per_edge_mean\": %.1f, \"evals_per_edge_median\": %.0f, "
           "\"evals_per_edge_p90\": %.0f, \"evals_per_edge_p99\": %.0f, "
           "\"evals_per_edge_max\": %.0f, \"edge_ms_mean\": %.3f, \"edge_ms_max\": %.3f, "
           "\"costliest_1pc_share\": %.3f, \"views_cpu_per_wall\": %.2f, "
           "\"us_per_patch_view\": %.3f, \"ops_per_edge_mean\": %.3f, \"share_with_ops\": %.3f, "
           "\"commit_bytes_per_edge\": %.1f, \"replay_us_per_op\": %.2f, \"replay_mismatches\": "
           "%llu, \"planning_us_per_eval\": %.3f, \"merge_us_per_eval\": %.3f}, \"whole_edges\": [",
           o->round, 1e6 * (at.plan_s + at.merge_s) / at.evals, er->n,
           (unsigned long long)er->planned, (unsigned long long)er->evals, er->mesh_edges,
           s.evals_mean, s.evals_median, s.evals_p90, s.evals_p99, s.evals_max, s.ms_mean, s.ms_max,
           s.top_share, er->views_cpu_per_wall, er->per_patch_view_us, s.ops_mean, s.with_ops,
           s.bytes_mean, er->replays ? 1e6 * er->replay_s / (double)er->replays : 0,
           (unsigned long long)er->mismatches, 1e6 * at.plan_s / at.evals,
           1e6 * at.merge_s / at.evals);
    uint32_t rs[3], nr = report_rounds(o, rs);
    for (uint32_t k = 0; k < nr; k++)
        for (size_t i = 0; i < N_W; i++) {
            whole_edges x = whole_edges_at(o, er, views, workers[i], rs[k]);
            printf("%s{\"round\": %u, \"workers\": %u, \"speedup\": %.3f, \"efficiency\": %.3f, "
                   "\"coordinator_cpu_per_eval_us\": %.3f}",
                   k || i ? ", " : "", rs[k], workers[i], x.t1 / x.tw, x.t1 / x.tw / workers[i],
                   1e6 * (x.plan_s + x.merge_s) / x.evals);
        }
    printf("], \"round_for_efficiency_0_8_at_16\": %u, \"round_for_efficiency_0_6_at_128\": %u, "
           "\"efficiency_at_round_65536\": [%.3f, %.3f]",
           round_for(o, er, views, 16, 0.8), round_for(o, er, views, 128, 0.6),
           whole_edges_speedup(o, er, views, 16, 65536) / 16,
           whole_edges_speedup(o, er, views, 128, 65536) / 128);
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
        else if (v && !strcmp(a, "--device"))
            o->device = argv[++i];
        else if (a[0] != '-')
            o->model = a;
        else
            return fprintf(stderr, "bench_scaling: unknown argument '%s'\n", a), 1;
    }
    if (!o->model || !o->evals || !o->edge_evals || o->round < 1 || o->round > 65536 ||
        o->in_flight < 1 || o->in_flight > CO_MAX_EDGES_IN_FLIGHT || o->views < 1 ||
        o->views > LM_MAX_VIEWS || o->size < 16)
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

int main(int argc, char **argv)
{
    opts o = {.model = getenv("LUMESH_TEST_DATA") ? NULL : "tests/data/cache/meshes/bunny00.off",
              .device = "auto",
              .evals = 3000,
              .edge_evals = 30000,
              .round = 256,
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
    static meter m[3];
    static edges_run er;
    costs c[2];
    rtts t = {0, 0, 0, 0};
    lm_status st = setup(&o, &orig, &coarse, &vs);
    uint32_t ks[2] = {1, o.in_flight};
    for (int r = 0; r < 2 && st == LM_OK; r++)
        st = run_once(&o, orig, coarse, &vs, ks[r], &m[r], &c[r]);
    if (st == LM_OK)
        st = run_edges(&o, orig, coarse, &vs, &m[2], &er);
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
        print_json(&o, c, vs.count, &t, &er);
    else
        print_human(&o, c, vs.count, &t, &er);
    free(er.e);
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
