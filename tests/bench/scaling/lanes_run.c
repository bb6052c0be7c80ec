/* tests/bench/scaling/lanes_run.c — the whole-lane schedule's costs, measured on the real
 * isolated-lane engine (lm_params.lane_isolation, common/optimizer/lanes.h) on the job's own
 * set-up (co_job_setup_make; its regrids done as the job's loop does them, their CPU apart) in
 * process: a run at K edges in flight until --edge-evals, the views behind the meter (meter.c,
 * light), the engine's probe (lm_lanes_set_probe) cutting the time into, per group (and, in the
 * same job run as --lanes remote on local workers, sc_run_lanes_remote, the coordinator's whole
 * CPU in each phase):
 * Every cost is CPU time (the process's, the views' threads included), not wall time: this
 * machine is shared, and its wall time is mostly waiting for a core (the lanes' wall time is kept
 * beside, for comparison).
 *     planning (from the last merge to the group's start: the oracle's ranking, the plan; the
 *               coordinator's CPU, and apart the views' potentials, the workers' work),
 *     snapshots (the lanes' copies of the group's start: a worker's, from its replica),
 *     the lanes (the views' time and the lanes' own CPU: simplex, moves, the geometric term: what
 *               workers holding all views do; a worker's time per evaluation is their sum over
 *               the lanes' evaluations),
 *     the merge (the coordinator's CPU: replays, log replays, the queue notes, encoding the
 *               commits; apart the views' re-validations and their commits, the workers' work),
 * and per lane its evaluations, operations, how the merge took it (kept exact, re-validated and
 * kept, dropped) and the size of its result message: raw sizes of what the merge reads (a header
 * of RESULT_HEADER bytes: status, ΔE, mesh hash, evaluations, counters; each operation as
 * OP_BYTES plus its parameters as doubles; the statistics and queue logs as lane_log.h's
 * records; the touched vertices as 32-bit ids), not a wire encoding. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/optimizer/lane_log.h"
#include "common/optimizer/lane_runner.h"
#include "common/optimizer/lanes.h"
#include "common/optimizer/optimizer.h"
#include "common/optimizer/optimizer_internal.h" /* the lanes, for their probe */
#include "coordinator/job/regrid.h"
#include "coordinator/pool/pool.h"
#include "scaling.h"

#define RESULT_HEADER 96.0
#define OP_BYTES 32.0

/* What the meter has counted at a probe's point. */
typedef struct mark {
    double wall, cpu, views_cpu, state_cpu, commit_bytes;
    uint64_t patches;
} mark;

typedef struct probe_ctx {
    meter *m;
    lanes_run *r;
    mark at; /* at the last point */
    lm_status st;
    const opts *o;
    const co_job_setup *js;
    co_pool *pool;         /* the remote run's workers; NULL in process */
    uint32_t draw;         /* the regrid draw of the views in force */
    co_original_pack pack; /* the original's asset, kept across the regrids as the job keeps it */
} probe_ctx;

static mark mark_now(const meter *m)
{
    return (mark){sc_wall(), sc_cpu(), m->views_cpu_s, m->state_cpu_s, (double)m->commit_bytes,
                  m->patches};
}

/* The process CPU between a and b outside the views (the coordinator's own, in process). */
static double own_cpu(const mark *a, const mark *b)
{
    return (b->cpu - a->cpu) - (b->views_cpu - a->views_cpu) - (b->state_cpu - a->state_cpu);
}

static void on_phase(void *ctx, int phase, uint32_t n)
{
    probe_ctx *p = ctx;
    lanes_run *r = p->r;
    mark b = mark_now(p->m), *a = &p->at;
    group_rec *g = r->n_g ? &r->g[r->n_g - 1] : NULL;
    if (phase == LM_LANES_BEGIN) {
        if (!LM_GROW(&r->g, &r->cap_g, r->n_g + 1, 256)) {
            p->st = lm_fail(LM_E_NOMEM, "out of memory for the lanes' groups");
            return;
        }
        g = &r->g[r->n_g++];
        memset(g, 0, sizeof *g);
        g->first = (uint32_t)r->n_l;
        g->n = n;
        g->plan_s = (float)own_cpu(a, &b);
        g->cpu_plan = (float)(b.cpu - a->cpu);
        g->pot_s = (float)(b.state_cpu - a->state_cpu);
    } else if (g && phase == LM_LANES_RUN) {
        g->snap_s = (float)own_cpu(a, &b);
        g->cpu_lanes = (float)(b.cpu - a->cpu);
    } else if (g && phase == LM_LANES_MERGE) {
        g->lanes_s = (float)(b.cpu - a->cpu);
        g->cpu_lanes += (float)(b.cpu - a->cpu);
        r->lanes_wall_s += b.wall - a->wall;
        r->lanes_views_cpu_s += b.views_cpu - a->views_cpu;
        r->evals += b.patches - a->patches;
    } else if (g && phase == LM_LANES_MERGED) {
        g->merge_s = (float)own_cpu(a, &b);
        g->cpu_merge = (float)(b.cpu - a->cpu);
        g->reval_s = (float)(b.views_cpu - a->views_cpu);
        g->revals = (uint32_t)(b.patches - a->patches);
        g->apply_s = (float)(b.state_cpu - a->state_cpu);
        g->commit_bytes = (float)(b.commit_bytes - a->commit_bytes);
    }
    p->at = mark_now(p->m); /* the probe's own time is nobody's */
}

static void on_lane(void *ctx, const lm_lane_report *x)
{
    probe_ctx *p = ctx;
    lanes_run *r = p->r;
    if (!LM_GROW(&r->l, &r->cap_l, r->n_l + 1, 1024)) {
        p->st = lm_fail(LM_E_NOMEM, "out of memory for the lanes");
        return;
    }
    double bytes = RESULT_HEADER + OP_BYTES * x->ops + 8.0 * x->x_values +
                   (double)sizeof(lm_lane_stat_add) * x->stat_adds +
                   (double)sizeof(lm_lane_queue_change) * x->queue_changes + 4.0 * x->touched;
    r->l[r->n_l++] = (lane_rec){(uint32_t)x->evals, x->ops, x->outcome, (float)bytes};
}

/* --lanes remote: the optimizer's lanes on the workers of the meter's views. */
static lm_status use_runner(probe_ctx *p, lm_optimizer *opt)
{
    lm_lane_runner runner;
    lm_status st = p->pool ? co_views_lane_runner(p->m->in, &runner) : LM_OK;
    if (st == LM_OK && p->pool)
        lm_optimizer_set_lane_runner(opt, &runner);
    return st;
}

/* The job's regrid (job.c, regrid_if_due): the views of the new draw in place of the meter's (the
 * original's targets rendered again, on every worker with --lanes remote), the energies on them;
 * its process CPU and wall time counted in the run, apart from the groups'. */
static lm_status regrid(probe_ctx *p, lm_optimizer *opt, uint32_t draw)
{
    static lm_view_set vs;
    meter *m = p->m;
    double c0 = sc_cpu(), t0 = sc_wall();
    lm_status st = co_job_setup_view_set(p->js, draw, &vs);
    const lm_mesh *mesh = lm_optimizer_mesh(opt);
    co_views_desc d = {.kind = p->pool ? CO_VIEWS_REMOTE : CO_VIEWS_LOCAL,
                       .pool = p->pool,
                       .whole = p->pool != NULL,
                       .audit = p->pool ? p->js->o.audit : (co_audit_rule){0, 0},
                       .original = p->js->original,
                       .views = &vs,
                       .materials = mesh->materials,
                       .n_materials = mesh->n_materials,
                       .device = p->o->device,
                       .pack = &p->pack};
    lm_views *in = NULL, *old = m->in;
    double c1 = sc_cpu();
    if (st == LM_OK)
        st = co_views_create(&d, &in);
    p->r->regrid_target_cpu_s += sc_cpu() - c1;
    if (st == LM_OK)
        p->r->target_bytes = 20.0 + (double)vs.count * vs.views[0].width * vs.views[0].height;
    if (st == LM_OK) {
        m->in = in;
        st = lm_optimizer_replace_views(opt, &m->base, 1);
    }
    if (st == LM_OK) {
        co_views_lane_stats(old, &p->r->lane_stats);
        lm_views_destroy(old);
        st = use_runner(p, opt);
    }
    p->r->regrids++;
    p->r->regrid_cpu_s += sc_cpu() - c0;
    p->r->regrid_wall_s += sc_wall() - t0;
    p->draw = draw;
    p->at = mark_now(m); /* the regrid is nobody's group's */
    return st;
}

/* The optimizer's steps until --edge-evals, each ending at the job's next regrid, as the job's
 * loop bounds them (job.c, run_loop). */
static lm_status run_steps(const opts *o, lm_optimizer *opt, probe_ctx *p)
{
    lm_status st = LM_OK;
    uint64_t every = p->js->regrid_every;
    for (int guard = 0; st == LM_OK && p->st == LM_OK && guard < 1000000; guard++) {
        lm_progress pr;
        lm_optimizer_progress(opt, &pr);
        if (pr.evals >= o->edge_evals)
            break;
        uint32_t draw = co_regrid_draw(pr.evals, every);
        if (draw != p->draw)
            st = regrid(p, opt, draw);
        uint64_t next = co_regrid_next(p->draw, every);
        p->m->step_c0 = sc_cpu();
        if (st == LM_OK)
            st = lm_optimizer_step(opt, next < o->edge_evals ? next : o->edge_evals);
    }
    return st != LM_OK ? st : p->st;
}

lm_status sc_job_setup(const opts *o, co_job_setup *js)
{
    co_job_options jo = {.original_path = o->model,
                         .initial_path = o->initial,
                         .start = o->initial ? CO_JOB_START_DEFAULT : o->start,
                         .target_verts = o->initial ? 0 : o->target_verts,
                         .views = {.count = o->views},
                         .size = (int)o->size,
                         .seed = 1,
                         .device_spec = o->device,
                         .edges_in_flight = 2,
                         .edges_per_iteration = o->plan,
                         .lane_isolation = 1,
                         .regrid_every = !o->regrid_set    ? 0
                                         : o->regrid_every ? o->regrid_every
                                                           : (uint64_t)CO_JOB_NONE,
                         .quiet = 1};
    return co_job_setup_make(&jo, js);
}

/* The job's optimizer on the metered views at K lanes, isolated (the caller destroys *opt). */
static lm_status lane_optimizer_create(const co_job_setup *js, uint32_t k, lm_mesh *mesh, meter *m,
                                       lm_optimizer **opt)
{
    lm_params params = js->params;
    params.edges_in_flight = k;
    params.lane_isolation = 1;
    return lm_optimizer_create_tuned(mesh, &m->base, &params, &js->tuning, opt);
}

lm_status sc_run_lanes(const opts *o, const co_job_setup *js, uint32_t k, lanes_run *out)
{
    static meter m;
    lm_mesh *mesh = NULL;
    lm_optimizer *opt = NULL;
    memset(out, 0, sizeof *out);
    out->k = k;
    const lm_view_set *vs = js->views;
    lm_status st = sc_meter_start_on(o, js->original, js->coarse, vs, 1, NULL, NULL, &m, &mesh);
    if (st == LM_OK)
        st = lane_optimizer_create(js, k, mesh, &m, &opt);
    probe_ctx p = {&m, out, mark_now(&m), LM_OK, o, js, NULL, 0, {0}};
    if (st == LM_OK && k > 1)
        lm_lanes_set_probe(opt->lanes, &(lm_lanes_probe){on_phase, on_lane, &p});
    if (st == LM_OK && k > 1 && o->lanes_detached)
        st = lm_optimizer_set_lanes_detached(opt, 1);
    double t0 = sc_wall();
    p.at = mark_now(&m);
    if (st == LM_OK)
        st = run_steps(o, opt, &p);
    out->wall_s = sc_wall() - t0;
    lm_progress pr;
    if (st == LM_OK) {
        lm_optimizer_progress(opt, &pr);
        out->energy_rel =
            (double)(pr.energy + pr.geometric) / (double)(pr.energy_start + pr.geometric_start);
    }
    lm_optimizer_destroy(opt);
    lm_views_destroy(m.in);
    lm_replica_free(&m.rep);
    lm_wire_arena_free(&m.arena);
    if (st == LM_OK && (!out->n_g || !out->evals))
        st = lm_fail(LM_E_RANGE, "the lanes' run at K = %u evaluated nothing", k);
    double lanes_s = 0;
    for (size_t i = 0; i < out->n_g; i++)
        lanes_s += out->g[i].lanes_s;
    if (st == LM_OK) {
        out->eval_s = lanes_s / (double)out->evals;
        out->eval_wall_s = out->lanes_wall_s / (double)out->evals;
        out->per_patch_view_us = 1e6 * out->lanes_views_cpu_s / ((double)out->evals * vs->count);
    }
    return st;
}

/* The worker program: LUMESH_WORKER (the pool's own search takes it: NULL here), else the
 * lumesh-worker built beside this bench (its path from CMake). */
static const char *worker_program(void)
{
    const char *env = getenv("LUMESH_WORKER");
    return env && *env ? NULL : LUMESH_WORKER_BUILT;
}

lm_status sc_run_lanes_remote(const opts *o, const co_job_setup *js, uint32_t k, uint32_t workers,
                              lanes_run *out)
{
    static meter m;
    lm_mesh *mesh = NULL;
    lm_optimizer *opt = NULL;
    co_pool *pool = NULL;
    memset(out, 0, sizeof *out);
    out->k = k;
    out->workers = workers;
    co_pool_options po = {.local_workers = workers,
                          .worker_path = worker_program(),
                          .device = o->device,
                          .quiet = 1,
                          .spin_us = -1,
                          .await_spin_us = -1};
    lm_status st = co_pool_create(&po, &pool);
    if (st == LM_OK)
        st = co_pool_wait(pool, workers, CO_JOB_WORKER_START_S);
    if (st == LM_OK)
        st = sc_meter_start_on(o, js->original, js->coarse, js->views, 1, pool, &js->o.audit, &m,
                               &mesh);
    if (st == LM_OK)
        st = lane_optimizer_create(js, k, mesh, &m, &opt);
    probe_ctx p = {&m, out, mark_now(&m), LM_OK, o, js, pool, 0, {0}};
    if (st == LM_OK)
        st = use_runner(&p, opt);
    if (st == LM_OK)
        lm_lanes_set_probe(opt->lanes, &(lm_lanes_probe){on_phase, on_lane, &p});
    double t0 = sc_wall(), c0 = sc_cpu();
    p.at = mark_now(&m);
    if (st == LM_OK)
        st = run_steps(o, opt, &p);
    out->wall_s = sc_wall() - t0;
    out->coord_cpu_s = sc_cpu() - c0;
    if (m.in)
        co_views_lane_stats(m.in, &out->lane_stats);
    out->audits = out->lane_stats.audits;
    lm_optimizer_destroy(opt);
    lm_views_destroy(m.in);
    co_original_pack_free(&p.pack);
    co_pool_destroy(pool);
    lm_replica_free(&m.rep);
    lm_wire_arena_free(&m.arena);
    for (size_t i = 0; i < out->n_l; i++)
        out->evals += out->l[i].evals;
    out->lane_runs = out->n_l + out->audits;
    if (st == LM_OK && (!out->n_g || !out->evals))
        st = lm_fail(LM_E_RANGE, "the remote lanes' run at K = %u evaluated nothing", k);
    return st;
}

void sc_lanes_free(lanes_run *r)
{
    free(r->g);
    free(r->l);
    memset(r, 0, sizeof *r);
}
