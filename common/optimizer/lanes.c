/* common/optimizer/lanes.c — edges in flight: lane fibers handing a baton, one batch of
 * evaluations per round, and the merge of the lanes' changes in order (lanes.h). */
#include "common/optimizer/lanes.h"
#include "common/optimizer/lane_runner.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/log.h"
#include "common/mesh_topology.h"
#include "common/optimizer/edge.h"
#include "common/optimizer/fiber.h"
#include "common/optimizer/lane_host.h"
#include "common/optimizer/lane_log.h"
#include "common/optimizer/lane_views.h"
#include "common/optimizer/lane_wire.h"

#define GROUP_RINGS 2  /* edges whose vertices lie within this many rings of each other wait */
#define GROUP_WINDOW 4 /* a group is chosen among the next GROUP_WINDOW x K planned edges */

enum { LANE_IDLE, LANE_RUNNING, LANE_WAITING, LANE_DONE };

struct lm_lane {
    lm_lanes *owner;
    uint32_t index;
    lm_fiber *fiber;
    int state;
    lm_status post_status; /* what the request in flight came back with */
    lm_mesh *mesh;
    lm_moves *mv;
    lm_lane_views views;
    lm_edge_ctx ctx;
    uint32_t a, b;
    lm_lane_result res; /* what the merge takes: its operations, ΔE, logs, counters */
    /* isolated lanes (lm_params.lane_isolation): the lane's own copies of what lanes otherwise
     * share, taken at the group's start (its logs and touched set are in res) */
    lm_move_stats stats;
    lm_teleport tp;   /* its own collapse queue, veto and log */
    lm_progress prog; /* its attempted[]/accepted[] */
    uint64_t clock;   /* the group's start + the lane's own evaluations */
    uint64_t evals0;  /* the lane's moves' evaluations at the group's start */
    int outcome;      /* the merge's: LM_LANE_* (lanes.h) */
};

struct lm_lanes {
    lm_optimizer *o;
    uint32_t k;
    lm_lane *lanes;
    lm_tri_data *start; /* the group's start, sorted by id */
    size_t n_start;
    lm_patch *batch; /* shallow copies of the lanes' requests */
    int64_t *deltas;
    uint32_t cap_batch;
    uint32_t *stamp; /* per vertex: the group member whose neighbourhood holds it */
    uint32_t cap_stamp, epoch;
    uint32_t base;   /* the current group's first tag: member i's is base + i */
    uint32_t *queue; /* breadth-first search */
    uint32_t cap_queue;
    lm_patch merged;
    int isolated;       /* lm_params.lane_isolation */
    lm_teleport tp0;    /* isolated: the optimizer's teleport state at the group's start */
    uint32_t n_verts0;  /* isolated: the mesh's vertex slots then (lanes' new ids are above) */
    uint32_t n_group;   /* isolated: the group's size */
    uint64_t run_order; /* lm_lanes_set_run_order */
    uint64_t groups;    /* groups run, for the shuffle */
    uint32_t *order;    /* [k] the order the lanes of the group run in */
    /* test only (lm_lanes_set_detached): isolated lanes run on a host of their own through
     * their wire messages */
    lm_lane_host *host;
    lm_lane_traffic traffic;
    lm_lane_runner runner; /* lm_lanes_set_runner (run NULL: in process) */
    lm_lanes_probe probe;  /* lm_lanes_set_probe (phase NULL: none) */
    /* a runner's group (run_by_runner), [k] each: the lanes' encoded requests, their lengths and
     * their results */
    uint8_t **req;
    size_t *req_len;
    lm_lane_result **res;
};

/* ---- the baton ------------------------------------------------------------------------------- */

/* Scheduler side: the lane about to run gets the collapse search's veto. */
static void hand_veto(lm_lanes *l, lm_lane *lane);

/* Scheduler side: let lane go on (its first edge, its next one, or its answer), until it waits
 * again or is done. */
static void resume(lm_lanes *l, lm_lane *lane)
{
    if (!l->isolated)
        hand_veto(l, lane);
    lane->state = LANE_RUNNING;
    lm_fiber_resume(lane->fiber);
}

lm_status lm_lane_post(lm_lane *lane)
{
    lane->state = LANE_WAITING;
    lm_fiber_yield(lane->fiber);
    lm_status st = lane->post_status;
    return st ? lm_fail(st, "the lanes' batch failed") : LM_OK;
}

/* The lane's result besides its operations and logs (kept as they came). */
static void finish_edge(lm_lane *lane)
{
    lm_lane_result *res = &lane->res;
    const lm_lanes *l = lane->owner;
    res->d_acc = lane->views.d_acc;
    res->mesh_hash = res->n_ops ? lm_mesh_hash(lane->mesh) : 0;
    memcpy(res->accepted, lane->ctx.accepted, sizeof res->accepted);
    if (!l->isolated)
        return;
    res->evals = lm_moves_evals(lane->mv) - lane->evals0;
    memcpy(res->attempted, lane->prog.attempted, sizeof res->attempted);
    res->searches = lane->tp.searches - l->tp0.searches;
    res->searches_failed = lane->tp.searches_failed - l->tp0.searches_failed;
    res->collapses_tried = lane->tp.collapses_tried - l->tp0.collapses_tried;
    res->last_collapse = lane->tp.last_collapse;
    res->last_time = lane->tp.last_time;
}

static void run_edge(lm_lane *lane)
{
    lm_lane_result *res = &lane->res;
    res->total = 0;
    res->status = lm_edge_optimise(&lane->ctx, lane->a, lane->b, &res->total);
    if (res->status != LM_OK)
        snprintf(res->msg, sizeof res->msg, "%s", lm_last_error());
    finish_edge(lane);
}

/* A lane's fiber: one edge each time the scheduler starts it (it never returns). */
static void lane_main(void *arg)
{
    lm_lane *lane = arg;
    for (;;) {
        run_edge(lane);
        lane->state = LANE_DONE;
        lm_fiber_yield(lane->fiber);
    }
}

/* ---- keeping lanes apart ----------------------------------------------------------------------
 */

static uint32_t tag_of(const lm_lane *lane)
{
    return lane->owner->base + lane->index;
}

/* Vertex v is another member's: within its neighbourhood or its collapses. */
static int others(const lm_lane *lane, uint32_t v)
{
    const lm_lanes *l = lane->owner;
    return v < l->cap_stamp && l->stamp[v] >= l->base && l->stamp[v] != tag_of(lane);
}

/* The collapse search of a lane leaves the other members' vertices alone. */
static int lane_veto(void *ctx, uint32_t a, uint32_t b)
{
    const lm_lane *lane = ctx;
    return others(lane, a) || others(lane, b);
}

/* An isolated lane's collapse search: the other members' start neighbourhoods as above, and the
 * edges of the other lanes' share. Lanes that copied the same queue would otherwise pick the same
 * cheapest collapse, and every lane after the first to merge it would be dropped whole. The share
 * of edge (a, b) is a hash of it modulo the group's size: scattered over the mesh, and the same
 * whichever order (or process) runs the lanes. */
static int isolated_veto(void *ctx, uint32_t a, uint32_t b)
{
    const lm_lane *lane = ctx;
    return lane_veto(ctx, a, b) || !lm_lane_share(a, b, lane->owner->n_group, lane->index);
}

/* A collapse the lane accepted: its vertices and the ring around them become the lane's (where no
 * other member holds them), so that no other lane collapses there too. */
static void claim_collapse(lm_lane *lane, uint32_t a, uint32_t b)
{
    lm_lanes *l = lane->owner;
    uint32_t nb[1024], v[2] = {a, b};
    for (int i = 0; i < 2; i++) {
        if (v[i] >= lane->mesh->n_verts || !lane->mesh->vert_alive[v[i]])
            continue;
        uint32_t n = lm_mesh_vertex_neighbors(lane->mesh, v[i], nb, 1024);
        for (uint32_t k = 0; k <= n && k <= 1024; k++) {
            uint32_t x = k < n && k < 1024 ? nb[k] : v[i];
            if (x < l->cap_stamp && l->stamp[x] < l->base)
                l->stamp[x] = tag_of(lane);
        }
    }
}

/* The lane about to run gets the collapse search's veto. */
static void hand_veto(lm_lanes *l, lm_lane *lane)
{
    l->o->tp.veto = lane_veto;
    l->o->tp.veto_ctx = lane;
}

/* ---- records (the lane's observer) ----------------------------------------------------------- */

static void on_accepted(void *ctx, const lm_move_record *r)
{
    lm_lane *lane = ctx;
    lane->views.pending = r->delta;
    if (r->kind == LM_MOVE_COLLAPSE && !lane->owner->isolated)
        claim_collapse(lane, r->a, r->b);
    lm_status st = lm_lane_result_accepted(&lane->res, r, lane->views.d_acc);
    LM_ASSERT(st == LM_OK);
}

/* A revert to journal position mark: the operations after it are forgotten with their ΔE. */
static void on_reverted(void *ctx, size_t mark)
{
    lm_lane *lane = ctx;
    lane->views.d_acc = lm_lane_result_reverted(&lane->res, mark, lane->views.d_acc);
}

/* ---- creation -------------------------------------------------------------------------------- */

/* An isolated lane: its own clock, statistics, teleport state (queue, veto, log), touched set,
 * progress counters. */
static lm_status isolate(lm_lanes *l, lm_lane *lane)
{
    lm_status st = lm_teleport_init(&lane->tp, &l->o->tp.cfg, NULL);
    if (st)
        return st;
    lm_cq_observe(lane->tp.queue, lm_lane_log_queue, &lane->res.log);
    lm_moves_share_clock(lane->mv, &lane->clock);
    lane->ctx.stats = &lane->stats;
    lane->ctx.tp = &lane->tp;
    lane->ctx.touched = &lane->res.touched;
    lane->ctx.log = &lane->res.log;
    lane->ctx.prog = &lane->prog;
    return LM_OK;
}

static lm_status lane_init(lm_lanes *l, lm_lane *lane)
{
    lane->owner = l;
    lane->index = (uint32_t)(lane - l->lanes);
    lm_lane_result_init(&lane->res);
    lm_lane_views_init(&lane->views, lane, l->o->views);
    lm_status st = lm_mesh_create(&lane->mesh);
    if (st == LM_OK)
        st = lm_moves_create(lane->mesh, &lane->views.base, &l->o->moves_cfg, &lane->mv);
    if (st != LM_OK)
        return st;
    lm_moves_observe(lane->mv, &(lm_moves_observer){on_accepted, on_reverted, lane});
    lane->ctx = (lm_edge_ctx){.o = l->o, .mesh = lane->mesh, .mv = lane->mv, .deferred = 1};
    if (l->isolated)
        st = isolate(l, lane);
    else
        lm_moves_share_clock(lane->mv, lm_moves_clock_ptr(l->o->mv));
    return st ? st : lm_fiber_create(LM_FIBER_STACK_BYTES, lane_main, lane, &lane->fiber);
}

void lm_lanes_set_views(lm_lanes *l, lm_views *views)
{
    for (uint32_t i = 0; i < l->k; i++)
        l->lanes[i].views.real = views;
}

lm_status lm_lanes_create(lm_optimizer *o, uint32_t k, lm_lanes **out)
{
    *out = NULL;
    lm_lanes *l = calloc(1, sizeof *l);
    if (!l)
        return lm_fail(LM_E_NOMEM, "out of memory for lanes");
    l->o = o;
    l->k = k;
    l->isolated = o->params.lane_isolation != 0;
    lm_patch_init(&l->merged);
    l->lanes = calloc(k, sizeof *l->lanes);
    l->order = calloc(k, sizeof *l->order);
    l->req = calloc(k, sizeof *l->req);
    l->req_len = calloc(k, sizeof *l->req_len);
    l->res = calloc(k, sizeof *l->res);
    l->cap_queue = 65536;
    l->queue = malloc(l->cap_queue * sizeof *l->queue);
    lm_status st = l->lanes && l->queue && l->order && l->req && l->req_len && l->res
                       ? LM_OK
                       : lm_fail(LM_E_NOMEM, "out of memory for %u lanes", k);
    for (uint32_t i = 0; i < k && st == LM_OK; i++)
        st = lane_init(l, &l->lanes[i]);
    if (st != LM_OK) {
        lm_lanes_destroy(l);
        return st;
    }
    *out = l;
    return LM_OK;
}

static void lane_free(lm_lanes *l, lm_lane *lane)
{
    (void)l;
    lm_fiber_destroy(lane->fiber); /* suspended between edges: its stack holds nothing */
    lm_moves_destroy(lane->mv);
    lm_mesh_destroy(lane->mesh);
    lm_lane_views_free(&lane->views);
    lm_lane_result_free(&lane->res);
    if (lane->tp.queue)
        lm_teleport_free(&lane->tp);
}

void lm_lanes_destroy(lm_lanes *l)
{
    if (!l)
        return;
    for (uint32_t i = 0; l->lanes && i < l->k; i++)
        if (l->lanes[i].owner)
            lane_free(l, &l->lanes[i]);
    free(l->lanes);
    free(l->order);
    free(l->req);
    free(l->req_len);
    free(l->res);
    free(l->start);
    free(l->batch);
    free(l->deltas);
    free(l->stamp);
    free(l->queue);
    lm_patch_free(&l->merged);
    lm_lane_host_destroy(l->host);
    free(l);
}

/* ---- groups ---------------------------------------------------------------------------------- */

/* stamp[] for n vertices, new entries zero (below every group's base). */
static int reserve_stamps(lm_lanes *l, uint32_t n)
{
    if (n <= l->cap_stamp)
        return 1;
    uint32_t *p = realloc(l->stamp, (size_t)n * sizeof *p);
    if (!p)
        return 0;
    memset(p + l->cap_stamp, 0, (size_t)(n - l->cap_stamp) * sizeof *p);
    l->stamp = p;
    l->cap_stamp = n;
    return 1;
}

/* Breadth-first over GROUP_RINGS rings from {a, b}: 1 if a vertex carries another member's stamp
 * (then nothing is stamped), else every vertex reached gets `tag`. */
static int meets(lm_lanes *l, uint32_t a, uint32_t b, uint32_t tag, uint32_t base)
{
    const lm_mesh *m = l->o->mesh;
    uint32_t n = 0, head = 0, nb[1024];
    l->queue[n++] = a;
    l->queue[n++] = b;
    for (int ring = 0; ring <= GROUP_RINGS; ring++) {
        uint32_t end = n;
        for (; head < end; head++) {
            uint32_t v = l->queue[head];
            if (l->stamp[v] >= base && l->stamp[v] != tag)
                return 1;
            if (ring == GROUP_RINGS)
                continue;
            uint32_t k = lm_mesh_vertex_neighbors(m, v, nb, 1024);
            for (uint32_t i = 0; i < k && i < 1024 && n < l->cap_queue; i++)
                l->queue[n++] = nb[i];
        }
    }
    for (uint32_t i = 0; i < n; i++)
        l->stamp[l->queue[i]] = tag;
    return 0;
}

/* 1 when planned edge e can no longer be optimised (a vertex gone): it goes in any group. */
static int gone(const lm_mesh *m, const lm_planned_edge *e)
{
    return e->a >= m->n_verts || e->b >= m->n_verts || !m->vert_alive[e->a] || !m->vert_alive[e->b];
}

uint32_t lm_lanes_group(lm_lanes *l, lm_planned_edge *plan, uint32_t n)
{
    const lm_mesh *m = l->o->mesh;
    if (!reserve_stamps(l, m->n_verts + 1))
        return 1;
    if (l->epoch > UINT32_MAX - 2 * l->k - 2) {
        memset(l->stamp, 0, (size_t)l->cap_stamp * sizeof *l->stamp);
        l->epoch = 0;
    }
    uint32_t base = l->base = l->epoch + 1, g = 0,
             window = n < GROUP_WINDOW * l->k ? n : GROUP_WINDOW * l->k;
    /* in plan order, every edge of the window that meets no member joins; members move to the
     * front, the others keep their order behind them */
    for (uint32_t i = 0; i < window && g < l->k; i++) {
        if (!gone(m, &plan[i]) && meets(l, plan[i].a, plan[i].b, base + g, base))
            continue;
        lm_planned_edge e = plan[i];
        memmove(plan + g + 1, plan + g, (size_t)(i - g) * sizeof *plan);
        plan[g++] = e;
    }
    l->epoch = base + l->k;
    return g ? g : 1;
}

/* ---- a group --------------------------------------------------------------------------------- */

/* An isolated lane starts from the optimizer's state at the group's start: its statistics, its
 * teleport state (the queue copied), its clock; empty logs and touched set. */
static lm_status snapshot(lm_lanes *l, lm_lane *lane)
{
    lm_optimizer *o = l->o;
    lm_cq *q = lane->tp.queue;
    lane->tp = o->tp;
    lane->tp.queue = q;
    lane->tp.veto = isolated_veto;
    lane->tp.veto_ctx = lane;
    lane->tp.log = &lane->res.log;
    lane->stats = o->stats;
    lane->clock = lm_moves_clock(o->mv);
    lane->evals0 = lm_moves_evals(lane->mv);
    memset(&lane->prog, 0, sizeof lane->prog);
    return lm_cq_copy(q, o->tp.queue);
}

/* The order the lanes of a group of n run in (and their requests go in each batch): lane order,
 * reversed, or a shuffle seeded by the run order and the group's number. */
static void make_order(lm_lanes *l, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        l->order[i] = l->run_order == 1 ? n - 1 - i : i;
    uint64_t x = l->run_order ^ (l->groups++ * 0x9e3779b97f4a7c15ull);
    for (uint32_t i = n; l->run_order > 1 && i > 1; i--) {
        x += 0x9e3779b97f4a7c15ull; /* splitmix64 */
        uint64_t z = x;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        uint32_t j = (uint32_t)(z % i), t = l->order[i - 1];
        l->order[i - 1] = l->order[j];
        l->order[j] = t;
    }
}

void lm_lanes_set_run_order(lm_lanes *l, uint64_t order)
{
    l->run_order = order;
}

void lm_lanes_set_probe(lm_lanes *l, const lm_lanes_probe *probe)
{
    l->probe = probe ? *probe : (lm_lanes_probe){NULL, NULL, NULL};
}

static void probe_phase(const lm_lanes *l, int phase, uint32_t n)
{
    if (l->probe.phase)
        l->probe.phase(l->probe.ctx, phase, n);
}

/* The lane's report to the probe, after its merge. */
static void probe_lane(const lm_lanes *l, const lm_lane *lane)
{
    if (!l->probe.lane)
        return;
    const lm_lane_result *res = &lane->res;
    lm_lane_report r = {.index = lane->index,
                        .outcome = res->n_ops ? lane->outcome : LM_LANE_NOTHING,
                        .evals = l->isolated ? res->evals : 0,
                        .ops = res->n_ops,
                        .x_values = res->n_xs,
                        .stat_adds = l->isolated ? res->log.n_adds : 0,
                        .queue_changes = l->isolated ? res->log.n_queue : 0,
                        .touched = l->isolated ? res->touched.n : 0};
    l->probe.lane(l->probe.ctx, &r);
}

/* The group's start: the optimizer's mesh as records; every lane's copy and views start there. */
static lm_status begin_group(lm_lanes *l, const lm_planned_edge *plan, uint32_t n)
{
    make_order(l, n);
    l->n_group = n;
    l->tp0 = l->o->tp;
    l->n_verts0 = l->o->mesh->n_verts;
    free(l->start);
    l->start = NULL;
    lm_status st = lm_mesh_export_tris(l->o->mesh, &l->start, &l->n_start);
    for (uint32_t i = 0; i < n && st == LM_OK; i++) {
        lm_lane *lane = &l->lanes[i];
        lm_lane_result_clear(&lane->res);
        lane->a = plan[i].a;
        lane->b = plan[i].b;
        if (l->host || (l->isolated && l->runner.run))
            continue; /* run detached or by the runner: the lane's fiber, mesh and copies stay idle
                       */
        st = lm_mesh_copy_geometry(lane->mesh, l->o->mesh);
        lm_lane_views_reset(&lane->views, l->start, l->n_start);
        lm_moves_forget(lane->mv);
        memset(lane->ctx.accepted, 0, sizeof lane->ctx.accepted);
        lane->post_status = LM_OK;
        if (st == LM_OK && l->isolated)
            st = snapshot(l, lane);
    }
    return st;
}

static lm_status reserve_batch(lm_lanes *l, uint32_t n)
{
    if (n <= l->cap_batch)
        return LM_OK;
    lm_patch *b = realloc(l->batch, n * sizeof *b);
    int64_t *d = realloc(l->deltas, n * sizeof *d);
    if (b)
        l->batch = b;
    if (d)
        l->deltas = d;
    if (!b || !d)
        return lm_fail(LM_E_NOMEM, "out of memory for a batch of %u patches", n);
    l->cap_batch = n;
    return LM_OK;
}

/* The waiting lanes' requests as one batch to the real views, in lane order. */
static lm_status evaluate_round(lm_lanes *l, uint32_t n, uint32_t *total)
{
    *total = 0;
    for (uint32_t i = 0; i < n; i++)
        if (l->lanes[i].state == LANE_WAITING)
            *total += l->lanes[i].views.n_req;
    lm_status st = *total ? reserve_batch(l, *total) : LM_OK;
    uint32_t at = 0;
    for (uint32_t j = 0; j < n && st == LM_OK; j++) {
        uint32_t i = l->order[j];
        const lm_lane_views *v = &l->lanes[i].views;
        if (l->lanes[i].state == LANE_WAITING) {
            memcpy(l->batch + at, v->req, v->n_req * sizeof *v->req);
            at += v->n_req;
        }
    }
    if (st == LM_OK && *total)
        st = l->o->views->ops->evaluate(l->o->views, l->batch, *total, l->deltas);
    at = 0;
    for (uint32_t j = 0; j < n && st == LM_OK; j++) {
        uint32_t i = l->order[j];
        lm_lane_views *v = &l->lanes[i].views;
        if (l->lanes[i].state == LANE_WAITING) {
            memcpy(v->res, l->deltas + at, v->n_req * sizeof *v->res);
            at += v->n_req;
        }
    }
    return st;
}

/* Rounds until every lane is done; a failure of the views is handed to every waiting lane (its
 * moves fail and end) and returned. */
static lm_status run_rounds(lm_lanes *l, uint32_t n)
{
    lm_status failed = LM_OK;
    char msg[512] = "";
    for (;;) {
        uint32_t waiting = 0;
        lm_status st = failed ? LM_OK : evaluate_round(l, n, &waiting);
        lm_status answer = st == LM_E_POISON ? st : LM_OK; /* poison: the lanes' moves refused */
        if (st != LM_OK && st != LM_E_POISON) {
            failed = st;
            snprintf(msg, sizeof msg, "%s", lm_last_error());
        }
        int any = 0;
        for (uint32_t j = 0; j < n; j++) {
            uint32_t i = l->order[j];
            if (l->lanes[i].state == LANE_WAITING) {
                l->lanes[i].post_status = failed ? failed : answer;
                resume(l, &l->lanes[i]);
                any = 1;
            }
        }
        if (!any)
            break;
    }
    return failed ? lm_fail(failed, "%s", msg) : LM_OK;
}

/* ---- lanes run detached (lm_lanes_set_detached) --------------------------------------------- */

lm_status lm_lanes_set_detached(lm_lanes *l, int on)
{
    if (!on || !l->isolated) {
        lm_lane_host_destroy(l->host);
        l->host = NULL;
        return LM_OK;
    }
    return l->host ? LM_OK : lm_lane_host_create(&l->o->moves_cfg, &l->host);
}

void lm_lanes_traffic(const lm_lanes *l, lm_lane_traffic *out)
{
    *out = l->traffic;
}

/* The collapse queue exported once at a group's start, for every lane's request. */
typedef struct shared_queue {
    lm_cq_entry *e;
    uint32_t n;
} shared_queue;

/* Lane i of the group of n as a request: what it reads of the optimizer's state at the start.
 * shared: the group's queue (borrowed into q->queue: every lane's is the same), or NULL: exported
 * here into q->queue (the caller frees it). */
static lm_status make_request(lm_lanes *l, uint32_t i, uint32_t n, const shared_queue *shared,
                              lm_lane_request *q)
{
    const lm_optimizer *o = l->o;
    const lm_lane *lane = &l->lanes[i];
    *q = (lm_lane_request){.index = i,
                           .n_group = n,
                           .a = lane->a,
                           .b = lane->b,
                           .n_verts = o->mesh->n_verts,
                           .clock = lm_moves_clock(o->mv),
                           .vetoed = q->vetoed,
                           .cap_vetoed = q->cap_vetoed,
                           .stats = o->stats,
                           .tp_cfg = o->tp.cfg,
                           .last_collapse = o->tp.last_collapse,
                           .last_time = o->tp.last_time};
    memcpy(q->improve, o->tp.improve, sizeof q->improve);
    lm_status st = LM_OK;
    for (uint32_t v = 0; v < q->n_verts && st == LM_OK; v++)
        if (others(lane, v))
            st = lm_lane_request_veto(q, v);
    if (st != LM_OK || !shared)
        return st ? st : lm_cq_export(o->tp.queue, &q->queue, &q->n_queue);
    q->queue = shared->e;
    q->n_queue = shared->n;
    return LM_OK;
}

static void count_traffic(lm_lane_traffic *t, size_t request, size_t result, uint64_t evals)
{
    t->lanes++;
    t->request_bytes += request;
    t->result_bytes += result;
    t->request_max = request > t->request_max ? request : t->request_max;
    t->result_max = result > t->result_max ? result : t->result_max;
    t->evals += evals;
}

/* Lane i: request -> bytes -> request -> the host's run -> result -> bytes -> the lane's result. */
static lm_status run_one_detached(lm_lanes *l, uint32_t i, uint32_t n, lm_lane_request *q,
                                  lm_lane_request *wq, lm_lane_result *wr)
{
    uint8_t *buf = NULL, *back = NULL;
    size_t len = 0, len_back = 0;
    lm_status st = make_request(l, i, n, NULL, q);
    if (st == LM_OK)
        st = lm_lane_request_encode(q, &buf, &len);
    free(q->queue);
    q->queue = NULL;
    if (st == LM_OK)
        st = lm_lane_request_decode(buf, len, wq);
    if (st == LM_OK) {
        lm_lane_host_run(l->host, l->o->mesh, l->o->views, wq, 0, wr); /* failure: in wr */
        st = lm_lane_result_encode(wr, &back, &len_back);
    }
    if (st == LM_OK)
        st = lm_lane_result_decode(back, len_back, wq->n_verts, &l->lanes[i].res);
    if (st == LM_OK)
        count_traffic(&l->traffic, len, len_back, l->lanes[i].res.evals);
    free(buf);
    free(back);
    return st;
}

static lm_status run_detached(lm_lanes *l, uint32_t n)
{
    lm_lane_request q, wq;
    lm_lane_result wr;
    lm_lane_request_init(&q);
    lm_lane_request_init(&wq);
    lm_lane_result_init(&wr);
    lm_status st = LM_OK;
    for (uint32_t j = 0; j < n && st == LM_OK; j++)
        st = run_one_detached(l, l->order[j], n, &q, &wq, &wr);
    lm_lane_request_free(&q);
    lm_lane_request_free(&wq);
    lm_lane_result_free(&wr);
    return st;
}

/* ---- lanes run by a runner (lm_lanes_set_runner) -------------------------------------------- */

void lm_lanes_set_runner(lm_lanes *l, const lm_lane_runner *runner)
{
    l->runner = runner ? *runner : (lm_lane_runner){NULL, NULL};
}

/* Every lane of the group as a request, handed to the runner; its results are the lanes'. */
static lm_status run_by_runner(lm_lanes *l, uint32_t n)
{
    uint8_t **req = l->req;
    size_t *len = l->req_len;
    lm_lane_result **res = l->res;
    memset(req, 0, n * sizeof *req);
    memset(len, 0, n * sizeof *len);
    lm_lane_request q;
    lm_lane_request_init(&q);
    shared_queue queue = {NULL, 0}; /* the group's, sorted and encoded once for all its lanes */
    uint8_t *qbuf = NULL;
    size_t qlen = 0;
    lm_status st = lm_cq_export(l->o->tp.queue, &queue.e, &queue.n);
    if (st == LM_OK)
        st = lm_lane_queue_encode(queue.e, queue.n, &qbuf, &qlen);
    for (uint32_t i = 0; i < n && st == LM_OK; i++) {
        res[i] = &l->lanes[i].res;
        st = make_request(l, i, n, &queue, &q);
        if (st == LM_OK)
            st = lm_lane_request_encode_head(&q, &req[i], &len[i]);
        q.queue = NULL; /* borrowed */
        q.n_vetoed = 0;
    }
    free(queue.e);
    lm_lane_request_free(&q);
    uint64_t back = 0;
    lm_lane_batch b = {.start = l->o->mesh,
                       .cfg = &l->o->moves_cfg,
                       .n = n,
                       .n_verts = l->o->mesh->n_verts,
                       .req = (const uint8_t *const *)req,
                       .req_len = len,
                       .queue = qbuf,
                       .queue_len = qlen,
                       .res = res,
                       .result_bytes = &back};
    if (st == LM_OK)
        st = l->runner.run(l->runner.ctx, &b);
    for (uint32_t i = 0; i < n; i++) { /* the queue counted once, with lane 0 */
        if (st == LM_OK)
            count_traffic(&l->traffic, len[i] + (i ? 0 : qlen), i ? 0 : back,
                          l->lanes[i].res.evals);
        free(req[i]);
        req[i] = NULL;
    }
    free(qbuf);
    return st;
}

/* ---- the merge ------------------------------------------------------------------------------- */

/* Vertex ids a lane created (splits) and the ids their replays got. */
typedef struct vmap {
    uint32_t from[64], to[64];
    uint32_t n;
} vmap;

/* v's id after the replay: to[i] when a split made it as from[i], else v itself (*found 0). */
static uint32_t mapped_found(const vmap *m, uint32_t v, int *found)
{
    *found = 1;
    for (uint32_t i = 0; i < m->n; i++)
        if (m->from[i] == v)
            return m->to[i];
    *found = 0;
    return v;
}

static uint32_t mapped(const vmap *m, uint32_t v)
{
    int found;
    return mapped_found(m, v, &found);
}

/* The lane's accepted operations again on the optimizer's mesh; *ok = 0 (mesh as it was) when
 * one of them no longer fits. map: the ids the lane's splits created and the ids they got. */
static lm_status replay_lane(lm_lanes *l, const lm_lane_result *res, size_t mark, int *ok,
                             vmap *map_out)
{
    vmap map = {.n = 0};
    *ok = 1;
    for (uint32_t i = 0; i < res->n_ops; i++) {
        lm_move_record r = res->ops[i].r;
        r.a = mapped(&map, r.a);
        r.b = mapped(&map, r.b);
        r.x = res->xs + res->ops[i].x_at;
        uint32_t v;
        lm_status st = lm_moves_replay(l->o->mv, &r, &v);
        if (st == LM_E_ILLEGAL || (st == LM_OK && r.kind == LM_MOVE_SPLIT && map.n == 64)) {
            lm_clear_error();
            lm_moves_rollback(l->o->mv, mark);
            *ok = 0;
            return LM_OK;
        }
        if (st != LM_OK)
            return st;
        if (r.kind == LM_MOVE_SPLIT) {
            map.from[map.n] = res->ops[i].r.v;
            map.to[map.n++] = v;
        }
    }
    *map_out = map;
    return LM_OK;
}

/* The collapse queue around the triangles the merge added. */
static lm_status note_merged(lm_lanes *l)
{
    uint32_t ids[4096];
    const lm_patch *p = &l->merged;
    lm_status st = LM_OK;
    for (uint32_t at = 0; at < p->n_added && st == LM_OK; at += 4096) {
        uint32_t k = p->n_added - at < 4096 ? p->n_added - at : 4096;
        for (uint32_t i = 0; i < k; i++)
            ids[i] = p->added[at + i].id;
        st = lm_teleport_note_change(&l->o->tp, l->o->mesh, ids, k);
    }
    return st;
}

/* Lane's changes onto the optimizer's mesh and views (the caller then notes them in the collapse
 * queue). *delta the ΔE committed; *kept 0 when they were rolled back (they no longer fit, or no
 * longer pay); *map the vertex ids the lane's splits created and the ids the replay gave them. The
 * first lane to change anything commits with its own exact ΔE when the replay rebuilt its mesh bit
 * for bit; every other one is evaluated again against the views as the merges before it left them.
 */
static lm_status merge_lane(lm_lanes *l, const lm_lane_result *res, int first, int *kept,
                            int64_t *delta, vmap *map, int *outcome)
{
    lm_optimizer *o = l->o;
    size_t mark = lm_moves_mark(o->mv);
    lm_status st = replay_lane(l, res, mark, kept, map);
    *outcome = LM_LANE_DROPPED_REPLAY;
    if (st != LM_OK || !*kept)
        return st;
    st = lm_patch_from_journal(&l->merged, o->mesh, lm_moves_journal(o->mv), mark);
    if (st != LM_OK)
        return st;
    int64_t d_lane = res->d_acc;
    if (first && lm_mesh_hash(o->mesh) == res->mesh_hash) {
        *delta = d_lane;
        *outcome = LM_LANE_KEPT_EXACT;
    } else {
        *outcome = LM_LANE_DROPPED_REVALIDATION;
        st = o->views->ops->evaluate(o->views, &l->merged, 1, delta);
        if (st == LM_E_POISON) { /* the re-validation failed everywhere: not merged */
            lm_clear_error();
            lm_moves_rollback(o->mv, mark);
            *kept = 0;
            return LM_OK;
        }
        if (st != LM_OK)
            return st;
        lm_moves_set_evals(o->mv, lm_moves_evals(o->mv) + 1); /* the re-validation counts */
        if (!(*delta < 0 || *delta <= d_lane)) {
            lm_moves_rollback(o->mv, mark);
            *kept = 0;
            return LM_OK;
        }
        *outcome = LM_LANE_KEPT_REVALIDATED;
    }
    return o->views->ops->commit(o->views, &l->merged);
}

/* The lane's accepted moves no longer count (its changes were rolled back). */
static void forget_accepted(lm_optimizer *o, const lm_lane_result *res)
{
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        o->prog.accepted[k] -= res->accepted[k];
}

/* ---- an isolated lane's own state, merged -------------------------------------------------- */

/* A lane's vertex as the optimizer's mesh has it after the lane's merge: ids below the group's
 * start count are the same; the ids its splits created are those their replays got (none when its
 * changes were not kept). */
typedef struct lane_ids {
    const vmap *map; /* NULL: not kept */
    uint32_t n_verts0;
} lane_ids;

static uint32_t lane_vertex(const void *ctx, uint32_t v)
{
    const lane_ids *ids = ctx;
    int found = 0;
    if (v < ids->n_verts0)
        return v;
    uint32_t m = ids->map ? mapped_found(ids->map, v, &found) : v;
    return found ? m : UINT32_MAX;
}

/* The lane's counters (teleport, progress) added to the optimizer's; its last collapse when it
 * completed a teleport. */
static void merge_counters(lm_lanes *l, const lm_lane_result *res)
{
    lm_teleport *tp = &l->o->tp;
    tp->searches += res->searches;
    tp->searches_failed += res->searches_failed;
    tp->collapses_tried += res->collapses_tried;
    if (res->accepted[LM_MOVE_COLLAPSE]) {
        tp->last_collapse = res->last_collapse;
        tp->last_time = res->last_time;
    }
    for (int k = 0; k < LM_MOVE_KINDS; k++) {
        l->o->prog.attempted[k] += res->attempted[k];
        l->o->prog.accepted[k] += res->accepted[k];
    }
}

/* What an isolated lane did to its own copies, onto the optimizer's state (in lane order, after
 * the lane's changes were replayed or rolled back, before the queue notes the merged patch): its
 * statistics adds and queue changes replayed, its teleport counters, its touched vertices, its
 * evaluations. map: the split map of its kept changes (NULL: not kept). */
static lm_status merge_isolated(lm_lanes *l, const lm_lane_result *res, const vmap *map)
{
    lm_optimizer *o = l->o;
    lane_ids ids = {map, l->n_verts0};
    lm_lane_log_replay_stats(&res->log, &o->stats, o->tp.improve, o->tp.cfg.stats_half_life);
    lm_status st = lm_lane_log_replay_queue(&res->log, o->tp.queue, o->mesh, lane_vertex, &ids);
    merge_counters(l, res);
    for (uint32_t i = 0; i < res->touched.n && st == LM_OK; i++) {
        uint32_t v = lane_vertex(&ids, res->touched.ids[i]);
        if (v != UINT32_MAX)
            st = lm_idset_add(&o->it.touched, v);
    }
    lm_moves_set_evals(o->mv, lm_moves_evals(o->mv) + res->evals);
    return st;
}

/* merge_lane with its debug line and its bookkeeping: *total and the energy when kept (the first
 * lane kept clears *first), the lane's accepted moves taken back when not. */
static lm_status merge_lane_logged(lm_lanes *l, uint32_t index, const lm_lane_result *res,
                                   int *first, int *kept, vmap *map, int64_t *total)
{
    lm_optimizer *o = l->o;
    int64_t delta = 0;
    lm_status st = merge_lane(l, res, *first, kept, &delta, map, &l->lanes[index].outcome);
    char kinds[64] = "";
    for (uint32_t q = 0; q < res->n_ops && q < 60; q++)
        kinds[q] = "nstc"[res->ops[q].r.kind], kinds[q + 1] = 0;
    lm_debug("merge lane %u: %u operations (%s), lane dE %lld, %s dE %lld", index, res->n_ops,
             kinds, (long long)res->d_acc, *kept ? "kept" : "dropped", (long long)delta);
    if (st == LM_OK && *kept) {
        *total = delta;
        o->prog.energy += delta;
        *first = 0;
    } else if (st == LM_OK) {
        forget_accepted(o, res);
    }
    return st;
}

static lm_status merge(lm_lanes *l, uint32_t n, int64_t *totals)
{
    lm_optimizer *o = l->o;
    lm_status st = LM_OK;
    int first = 1;
    for (uint32_t i = 0; i < n && st == LM_OK; i++) {
        const lm_lane_result *res = &l->lanes[i].res;
        totals[i] = 0;
        int kept = 0;
        vmap map = {.n = 0};
        if (res->n_ops)
            st = merge_lane_logged(l, i, res, &first, &kept, &map, &totals[i]);
        if (st == LM_OK && l->isolated)
            st = merge_isolated(l, res, kept ? &map : NULL);
        if (st == LM_OK && kept)
            st = note_merged(l);
        if (st == LM_OK)
            probe_lane(l, &l->lanes[i]);
    }
    lm_moves_forget(o->mv);
    return st;
}

lm_status lm_lanes_run(lm_lanes *l, const lm_planned_edge *plan, uint32_t n, int64_t *totals)
{
    LM_ASSERT(n >= 1 && n <= l->k);
    probe_phase(l, LM_LANES_BEGIN, n);
    lm_status st = begin_group(l, plan, n);
    if (st == LM_OK && l->isolated && l->runner.run) {
        probe_phase(l, LM_LANES_RUN, n);
        st = run_by_runner(l, n);
    } else if (st == LM_OK && l->host) {
        probe_phase(l, LM_LANES_RUN, n);
        st = run_detached(l, n);
    } else {
        probe_phase(l, LM_LANES_RUN, n);
        for (uint32_t j = 0; j < n && st == LM_OK; j++)
            resume(l, &l->lanes[l->order[j]]);
        if (st == LM_OK)
            st = run_rounds(l, n);
    }
    l->o->tp.veto = NULL;
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        if (l->lanes[i].res.status != LM_OK)
            st = lm_fail(l->lanes[i].res.status, "%s", l->lanes[i].res.msg);
    probe_phase(l, LM_LANES_MERGE, n);
    st = st == LM_OK ? merge(l, n, totals) : st;
    probe_phase(l, LM_LANES_MERGED, n);
    return st;
}
