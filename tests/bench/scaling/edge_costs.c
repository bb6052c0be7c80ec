/* tests/bench/scaling/edge_costs.c — the whole-edge run: the costs of every edge, optimised one
 * at a time, that the whole-edge models (rounds.c, window.c) are made of.
 *
 * The third run, one edge at a time, one planned edge per lm_optimizer_step (the evaluation budget
 * stops a step between edges; a planned edge gone before its turn costs nothing and goes with the
 * next), until --edge-evals, records for every edge e: its evaluations; cost_e, its cost in process
 * on one worker (the views' time and all the edge's other CPU: simplex, moves, geometric term,
 * commits; not the meter's encoding); when an iteration began before it, the planning: plan_e, the
 * coordinator's CPU around the oracle's potentials, and pot_e, their views' work; apply_e, the
 * views' CPU of its commits (what every worker spends applying them); b_e, the bytes of its Commit
 * messages; and merge_e, the coordinator's merge: its accepted operations (the optimizer's move
 * observer) done again with lm_moves_replay on a copy of the mesh as lanes.c merges them, the patch
 * of the lot (checked against the optimizer's mesh: the mismatches are printed), encoded twice (the
 * re-validation's Evaluate, the Commit) with the replica it is encoded against.
 * With its operations it also records its footprint (the vertices of the triangles of its merged
 * patch: the one-rings of the vertices its operations moved, made or kept) and how many edges back
 * the last earlier edge with operations whose footprint meets it lies (edge_rec.near): an edge of
 * the window schedule is re-validated when that edge is one it did not see. */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/mesh_topology.h"
#include "common/optimizer/optimizer.h"
#include "common/optimizer/optimizer_internal.h" /* read only: the move observer, the plan */
#include "scaling.h"

/* The accepted operations of the step being run (the optimizer's move observer). */
typedef struct recorded {
    lm_move_record r;
    size_t x_at; /* its parameters in x */
} recorded;

typedef struct recorder {
    recorded *r;
    uint32_t n, cap;
    double *x;
    size_t nx, capx;
} recorder;

static void rec_accepted(void *ctx, const lm_move_record *r)
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
    lm_moves *mv;
    lm_patch patch;
} shadow;

static void shadow_free(shadow *s)
{
    lm_moves_destroy(s->mv);
    lm_mesh_destroy(s->mesh);
    s->mv = NULL, s->mesh = NULL;
}

static lm_status shadow_make(shadow *s, const lm_optimizer *opt, lm_views *v)
{
    shadow_free(s);
    lm_status st = lm_mesh_clone(opt->mesh, &s->mesh);
    return st == LM_OK ? lm_moves_create(s->mesh, v, &opt->moves_cfg, &s->mv) : st;
}

/* The step's operations again on the shadow, and the patch of the lot (as a merge does them:
 * common/optimizer/lanes.c); *ok = 0 when one no longer fits. */
static lm_status shadow_replay(shadow *s, const recorder *rc, int *ok)
{
    uint32_t from[64], to[64], nm = 0;
    size_t mark = lm_moves_mark(s->mv);
    *ok = 1;
    for (uint32_t i = 0; i < rc->n; i++) {
        lm_move_record r = rc->r[i].r;
        for (uint32_t k = 0; k < nm; k++) {
            r.a = r.a == from[k] ? to[k] : r.a;
            r.b = r.b == from[k] ? to[k] : r.b;
        }
        r.x = rc->x + rc->r[i].x_at;
        uint32_t v;
        lm_status st = lm_moves_replay(s->mv, &r, &v);
        if (st == LM_E_ILLEGAL) {
            lm_clear_error();
            *ok = 0;
            break;
        }
        if (st != LM_OK)
            return st;
        if (r.kind == LM_MOVE_SPLIT && nm < 64)
            from[nm] = rc->r[i].r.v, to[nm++] = v;
    }
    lm_status st =
        *ok ? lm_patch_from_journal(&s->patch, s->mesh, lm_moves_journal(s->mv), mark) : LM_OK;
    lm_moves_forget(s->mv);
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

/* Edges back to the last earlier edge whose footprint meets this one's (0: none), its footprint
 * the vertices of the triangles of p, the patch of its operations on `mesh`; the footprint then
 * marked as this edge's (the next edge's index is er->n). */
static lm_status footprint_near(edges_run *er, const lm_mesh *mesh, const lm_patch *p,
                                uint32_t *near)
{
    size_t old = er->cap_last;
    if (!LM_GROW(&er->last, &er->cap_last, mesh->n_verts, 4096))
        return lm_fail(LM_E_NOMEM, "out of memory for the edges' footprints");
    memset(er->last + old, 0, (er->cap_last - old) * sizeof *er->last);
    uint32_t self = (uint32_t)er->n + 1, latest = 0;
    for (int pass = 0; pass < 2; pass++)
        for (uint32_t j = 0; j < p->n_added; j++)
            for (int k = 0; k < 3; k++) {
                uint32_t v = lm_tri_vertex(mesh, p->added[j].id, k);
                if (pass)
                    er->last[v] = self;
                else
                    latest = er->last[v] > latest ? er->last[v] : latest;
            }
    *near = latest ? self - latest : 0;
    return LM_OK;
}

/* The step just run as an edge record; the coordinator's replay of its operations timed here. */
static lm_status record_edge(const tally *a, const tally *b, shadow *s, const recorder *rc,
                             const lm_optimizer *opt, uint32_t edges, uint32_t plans, edges_run *er)
{
    double r0 = sc_cpu();
    int ok = 1;
    lm_status st = rc->n ? shadow_replay(s, rc, &ok) : LM_OK;
    double replay = sc_cpu() - r0;
    if (st != LM_OK)
        return st;
    er->replays += rc->n;
    er->replay_s += replay;
    uint32_t near = 0;
    if (rc->n && ok && (st = footprint_near(er, s->mesh, &s->patch, &near)) != LM_OK)
        return st;
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
        .near = near,
        .cost_s = (float)(views + other),
        .views_s = (float)views,
        .plan_s = (float)plan,
        .pot_s = (float)pot,
        .apply_s = rc->n ? (float)(b->commit - a->commit) : 0,
        /* the merged patch encoded twice (the re-validation's Evaluate and the Commit) */
        .merge_s = rc->n ? (float)(replay + 2 * enc + replica) : 0,
        .bytes = rc->n ? (float)(b->bytes - a->bytes) : 0};
    return LM_OK;
}

static lm_status run_edge_steps(const opts *o, lm_optimizer *opt, meter *m, edges_run *er)
{
    recorder rc = {.n = 0};
    shadow s = {.mesh = NULL};
    lm_patch_init(&s.patch);
    lm_status st = shadow_make(&s, opt, opt->views);
    lm_moves_observe(opt->mv, &(lm_moves_observer){rec_accepted, rec_reverted, &rc});
    for (int guard = 0; st == LM_OK && guard < 10000000; guard++) {
        lm_progress p;
        lm_optimizer_progress(opt, &p);
        if (p.evals >= o->edge_evals)
            break;
        uint32_t pos0 = opt->it.active ? opt->it.pos : 0;
        uint64_t trips0 = m->round_trips;
        rc.n = 0, rc.nx = 0;
        double c0 = sc_cpu();
        m->step_c0 = c0;
        tally a = tally_of(m, c0);
        st = lm_optimizer_step(opt, p.evals + 1); /* one edge: the budget stops it between edges */
        sc_close_plan(m);
        tally b = tally_of(m, sc_cpu());
        if (st == LM_OK)
            st = record_edge(&a, &b, &s, &rc, opt, opt->it.pos - pos0,
                             (uint32_t)(m->round_trips - trips0), er);
    }
    lm_moves_observe(opt->mv, NULL);
    shadow_free(&s);
    lm_patch_free(&s.patch);
    free(rc.r), free(rc.x);
    return st;
}

/* One edge at a time, each optimiser step one edge, until --edge-evals: the costs per edge. */
lm_status sc_run_edges(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                       const lm_view_set *vs, meter *m, edges_run *er)
{
    lm_mesh *mesh = NULL;
    lm_optimizer *opt = NULL;
    memset(er, 0, sizeof *er);
    lm_status st = sc_meter_start(o, orig, coarse, vs, 1, m, &mesh);
    lm_params params = {.seed = 1, .edges_in_flight = 1, .surface = orig};
    if (st == LM_OK)
        st = lm_optimizer_create(mesh, &m->base, &params, &opt);
    uint32_t(*edges)[2] = NULL;
    if (st == LM_OK)
        st = lm_mesh_list_edges(lm_optimizer_mesh(opt), &edges, &er->mesh_edges);
    free(edges);
    m->views_s = m->views_cpu_s = m->overlap_cpu_s = 0;
    m->patches = 0;
    if (st == LM_OK)
        st = run_edge_steps(o, opt, m, er);
    lm_optimizer_destroy(opt);
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

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

edge_stats sc_edge_stats(const edges_run *er)
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
