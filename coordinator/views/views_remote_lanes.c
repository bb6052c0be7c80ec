/* coordinator/views/views_remote_lanes.c — the isolated lanes of a group run on the workers
 * (--lanes remote; common/optimizer/lane_runner.h). Every worker of such views serves every view
 * (co_views_desc.whole) and receives every change of state, so its views are at the group's start
 * when a group begins; what it lacks is the optimizer's mesh itself (vertex ids, wedges) and the
 * collapse queue, which go with the first lane of each group a worker gets (RunLane.start and
 * .queue, or as deltas against the last group's when the worker took that), and the lane's
 * request (its head: the queue is the group's).
 *
 * Dispatch is first-free: each worker in the layout gets a lane, and the next one as soon as it
 * answers. A lane whose worker is lost, says Stale (it is sent the state again) or fails is sent
 * again, the same bytes, to the next free worker; a result that does not decode or fit fences the
 * worker (blocklisted for the job). A lane that fails CO_REMOTE_STRIKES times ends the run with the
 * worker's message. The results are the lanes' whoever ran them: the optimizer merges them in lane
 * order, so the output does not depend on the workers, their number or their timing. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/lane_delta.h"
#include "common/optimizer/lane_runner.h"
#include "common/optimizer/lane_start.h"
#include "common/optimizer/lane_wire.h"
#include "coordinator/views/views_remote_internal.h"

/* One group's run. */
typedef struct lane_run {
    co_remote *r;
    const lm_lane_batch *b;
    uint8_t *cfg, *mesh; /* encoded config; the start mesh */
    size_t n_cfg, n_mesh;
    uint8_t *delta; /* the start mesh against r->lane_base (made when a worker first needs it) */
    size_t n_delta;
    int no_delta;    /* 1: the delta would not pay (or failed): starts go whole */
    uint8_t *qdelta; /* the group's queue (b->queue) against r->lane_queue_base, made likewise */
    size_t n_qdelta;
    int no_qdelta;
    uint64_t hash;                          /* of the start mesh */
    uint32_t queue[LM_MAX_EDGES_IN_FLIGHT]; /* lanes waiting for a worker, in lane order */
    uint32_t n_queue, done;
    uint32_t strikes[LM_MAX_EDGES_IN_FLIGHT]; /* failures of each lane */
    uint32_t tries[LM_MAX_EDGES_IN_FLIGHT];   /* sends of each lane (lost, stale in between) */
    uint32_t *lane_of;                        /* [n_live] lane + 1 in flight on live[i], 0 none */
} lane_run;

static void requeue(lane_run *x, uint32_t lane)
{
    uint32_t at = x->n_queue++;
    while (at && x->queue[at - 1] > lane) { /* kept in lane order: the lowest goes first */
        x->queue[at] = x->queue[at - 1];
        at--;
    }
    x->queue[at] = lane;
}

/* The start as a delta for w, when w took the last group's start and the delta pays (at most
 * half the record); else nothing (the start goes whole). */
static int delta_for(lane_run *x, const co_worker *w)
{
    co_remote *r = x->r;
    if (x->no_delta || !r->lane_base || !r->lane_base_group || w->lane_group != r->lane_base_group)
        return 0;
    if (!x->delta) {
        lm_status st = lm_lane_delta_encode(r->lane_base, r->n_lane_base, x->mesh, x->n_mesh,
                                            &x->delta, &x->n_delta);
        x->no_delta = st != LM_OK || x->n_delta > x->n_mesh / 2;
        lm_clear_error();
    }
    return !x->no_delta;
}

/* The queue as a delta for w, on the same terms as the start's. */
static int qdelta_for(lane_run *x, const co_worker *w)
{
    co_remote *r = x->r;
    if (x->no_qdelta || !r->lane_queue_base || !r->lane_base_group ||
        w->lane_group != r->lane_base_group)
        return 0;
    if (!x->qdelta) {
        lm_status st =
            lm_lane_queue_delta_encode(r->lane_queue_base, r->n_lane_queue_base, x->b->queue,
                                       x->b->queue_len, &x->qdelta, &x->n_qdelta);
        x->no_qdelta = st != LM_OK || x->n_qdelta > x->b->queue_len / 2;
        lm_clear_error();
    }
    return !x->no_qdelta;
}

/* The group's start and queue for w, which has neither: each whole or as a delta against the
 * last group's (which w then holds). */
static void add_start(lane_run *x, co_worker *w, Lumesh__RunLane *m)
{
    co_remote *r = x->r;
    co_lane_stats *ls = &r->lane_stats;
    if (delta_for(x, w)) {
        m->base_group = r->lane_base_group;
        m->start_delta = (ProtobufCBinaryData){x->n_delta, x->delta};
        ls->starts_delta++;
        ls->start_bytes += x->n_delta;
    } else {
        m->start = (ProtobufCBinaryData){x->n_mesh, x->mesh};
        ls->starts_full++;
        ls->start_bytes += x->n_mesh;
    }
    if (qdelta_for(x, w)) {
        m->base_group = r->lane_base_group;
        m->queue_delta = (ProtobufCBinaryData){x->n_qdelta, x->qdelta};
        ls->queues_delta++;
        ls->queue_bytes += x->n_qdelta;
    } else {
        m->queue = (ProtobufCBinaryData){x->b->queue_len, (uint8_t *)x->b->queue};
        ls->queues_full++;
        ls->queue_bytes += x->b->queue_len;
    }
}

static lm_status send_lane(lane_run *x, co_worker *w, uint32_t lane)
{
    co_remote *r = x->r;
    const lm_lane_batch *b = x->b;
    Lumesh__RunLane m = LUMESH__RUN_LANE__INIT;
    m.job = r->job;
    m.group = r->lane_group;
    m.lane = lane;
    m.request = (ProtobufCBinaryData){b->req_len[lane], (uint8_t *)b->req[lane]};
    m.start_hash = x->hash;
    m.config = (ProtobufCBinaryData){x->n_cfg, x->cfg};
    m.surface = r->surface_k > 0;
    if (w->lane_group != r->lane_group)
        add_start(x, w, &m);
    r->lane_stats.request_bytes += b->req_len[lane];
    lm_status st =
        co_pool_send(r->pool, w, co_pool_arm(r->pool, w), r->seq, LUMESH__MSG__BODY_RUN_LANE, &m);
    if (st == LM_OK)
        w->lane_group = r->lane_group;
    return st;
}

/* Free workers of the layout get the lanes waiting, lowest first. */
static lm_status dispatch(lane_run *x)
{
    co_remote *r = x->r;
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < r->n_live && x->n_queue && st == LM_OK; i++) {
        co_worker *w = r->live[i];
        if (w->lost || x->lane_of[i] || w->job != r->job)
            continue;
        uint32_t lane = x->queue[0];
        if (++x->tries[lane] > CO_REMOTE_TRIES)
            return lm_fail(LM_E_IO,
                           "lane %u sent %u times: its workers keep being lost or "
                           "falling behind",
                           lane, CO_REMOTE_TRIES);
        memmove(x->queue, x->queue + 1, --x->n_queue * sizeof *x->queue);
        st = send_lane(x, w, lane);
        x->lane_of[i] = lane + 1;
    }
    return st;
}

/* The lane failed on w (a Failure, or a result that does not fit): again elsewhere, unless it
 * has failed too often (then the run fails with why). */
static lm_status strike(lane_run *x, co_worker *w, uint32_t lane, lm_status why)
{
    if (++x->strikes[lane] >= CO_REMOTE_STRIKES)
        return lm_fail(why ? why : LM_E_INTERNAL, "lane %u failed %u times, last: %s", lane,
                       x->strikes[lane], lm_last_error());
    w->lane_group = 0; /* send it the start again, in case that is what it lacked */
    requeue(x, lane);
    return LM_OK;
}

/* A LaneDone from w for lane: decoded into the lane's result, or w fenced and the lane again. */
static lm_status take_result(lane_run *x, co_worker *w, uint32_t lane)
{
    const Lumesh__LaneDone *d = w->reply.msg->lane_done;
    lm_lane_result *res = x->b->res[lane];
    lm_status st = d->group == x->r->lane_group && d->lane == lane
                       ? lm_lane_result_decode(d->result.data, d->result.len, x->b->n_verts, res)
                       : lm_fail(LM_E_FORMAT, "the result of lane %u of group %llu", d->lane,
                                 (unsigned long long)d->group);
    if (st == LM_OK && res->status != LM_OK)
        st = lm_fail(LM_E_FORMAT, "a result that says it failed");
    if (st != LM_OK) {
        char why[300];
        snprintf(why, sizeof why, "a lane's result that does not fit: %.200s", lm_last_error());
        co_pool_fence(x->r->pool, w, why);
        return strike(x, w, lane, st);
    }
    w->evals += res->evals;
    w->busy_s += 1e-6 * (double)d->busy_us;
    *x->b->result_bytes += d->result.len;
    x->done++;
    return LM_OK;
}

/* Replies and losses of the workers with a lane in flight. */
static lm_status collect(lane_run *x)
{
    co_remote *r = x->r;
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < r->n_live && st == LM_OK; i++) {
        co_worker *w = r->live[i];
        uint32_t lane = x->lane_of[i] - 1;
        if (!x->lane_of[i] || (!w->lost && !w->replied))
            continue;
        x->lane_of[i] = 0;
        if (w->lost) {
            requeue(x, lane);
            continue;
        }
        int stale = 0;
        lm_status why = co_remote_check_reply(r, w, LUMESH__MSG__BODY_LANE_DONE, &stale);
        if (why != LM_OK) {
            co_pool_disarm(w);
            co_pool_failed(r->pool, w, lm_last_error());
            st = strike(x, w, lane, why);
        } else if (stale) {
            co_pool_disarm(w);
            w->lane_group = 0; /* it may lack the start's base: sent whole next */
            requeue(x, lane);
            st = co_remote_send_state(r, w);
        } else {
            st = take_result(x, w, lane); /* reads the reply: disarmed after */
            co_pool_disarm(w);
        }
    }
    return st;
}

static int in_flight(const lane_run *x)
{
    for (uint32_t i = 0; i < x->r->n_live; i++)
        if (x->lane_of[i])
            return 1;
    return 0;
}

/* Until every lane has its result: a layout that uses every live worker between lanes (never
 * while one is in flight: the layout's own requests would take their slots), dispatch, replies. */
static lm_status run_lanes(lane_run *x)
{
    co_remote *r = x->r;
    lm_status st = LM_OK;
    double t0 = co_pool_now();
    while (st == LM_OK && x->done < x->b->n) {
        if (!in_flight(x) && co_remote_layout_stale(r)) {
            st = co_remote_layout(r);
            uint32_t *l = st == LM_OK ? realloc(x->lane_of, (r->n_live + 1) * sizeof *l) : NULL;
            if (st == LM_OK && !l)
                st = lm_fail(LM_E_NOMEM, "out of memory running lanes");
            if (l) {
                x->lane_of = l;
                memset(l, 0, (r->n_live + 1) * sizeof *l);
            }
        }
        if (st == LM_OK)
            st = dispatch(x);
        /* a signal ends the run after this group (the optimizer's next step); a group that
           outlasts the grace is given up, as the remote views' own waits are */
        if (st == LM_OK && co_pool_interrupted() &&
            co_pool_now() - t0 > CO_REMOTE_INTERRUPT_GRACE_S)
            st = lm_fail(LM_E_INVALID, "interrupted while lanes ran on the workers");
        if (st == LM_OK)
            st = co_pool_pump(r->pool, 200);
        if (st == LM_OK)
            st = collect(x);
    }
    return st;
}

static lm_status rl_run(void *ctx, const lm_lane_batch *b)
{
    co_remote *r = ctx;
    static uint64_t groups; /* numbers unique in this process: a worker's start mesh of an earlier
                               views object (a regrid's) is never taken for this one's */
    lane_run x = {.r = r, .b = b, .hash = lm_mesh_hash(b->start)};
    r->lane_group = ++groups;
    for (uint32_t i = 0; i < b->n; i++)
        x.queue[x.n_queue++] = i;
    lm_status st = co_remote_layout(r);
    if (st == LM_OK)
        st = lm_lane_config_encode(b->cfg, &x.cfg, &x.n_cfg);
    if (st == LM_OK)
        st = lm_lane_mesh_encode(b->start, &x.mesh, &x.n_mesh);
    if (st == LM_OK && !(x.lane_of = calloc(r->n_live + 1, sizeof *x.lane_of)))
        st = lm_fail(LM_E_NOMEM, "out of memory running lanes");
    if (st == LM_OK)
        st = run_lanes(&x);
    for (uint32_t i = 0; x.lane_of && i < r->n_live; i++)
        if (x.lane_of[i])
            co_pool_disarm(r->live[i]); /* a failed run: late answers are dropped */
    free(x.lane_of);
    free(x.cfg);
    free(x.delta);
    free(x.qdelta);
    uint8_t *queue = x.mesh ? malloc(b->queue_len ? b->queue_len : 1) : NULL;
    if (queue) { /* the base of the next group's deltas: the workers sent them hold them */
        memcpy(queue, b->queue, b->queue_len);
        r->lane_stats.groups++;
        r->lane_stats.start_record_bytes += x.n_mesh;
        r->lane_stats.queue_record_bytes += b->queue_len;
        free(r->lane_base);
        free(r->lane_queue_base);
        r->lane_base = x.mesh;
        r->n_lane_base = x.n_mesh;
        r->lane_queue_base = queue;
        r->n_lane_queue_base = b->queue_len;
        r->lane_base_group = r->lane_group;
    } else { /* no base: every start and queue goes whole next */
        free(x.mesh);
        r->lane_base_group = 0;
    }
    return st;
}

lm_status co_views_lane_runner(lm_views *v, lm_lane_runner *out)
{
    co_remote *r = co_remote_of(v);
    if (!r || !r->whole)
        return lm_fail(LM_E_UNSUPPORTED, "lanes run on workers only with remote views that "
                                         "serve every view on each worker");
    *out = (lm_lane_runner){rl_run, r};
    return LM_OK;
}

void co_views_lane_stats(lm_views *v, co_lane_stats *sum)
{
    co_remote *r = co_remote_of(v);
    if (!r)
        return;
    const co_lane_stats *a = &r->lane_stats;
    sum->groups += a->groups;
    sum->starts_full += a->starts_full;
    sum->starts_delta += a->starts_delta;
    sum->start_bytes += a->start_bytes;
    sum->request_bytes += a->request_bytes;
    sum->start_record_bytes += a->start_record_bytes;
    sum->queues_full += a->queues_full;
    sum->queues_delta += a->queues_delta;
    sum->queue_bytes += a->queue_bytes;
    sum->queue_record_bytes += a->queue_record_bytes;
}
