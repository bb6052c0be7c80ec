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
 * order, so the output does not depend on the workers, their number or their timing.
 *
 * Audits (lane_audit.h, r->audit): a lane the rule picks at its first send is also run, at the
 * same time, by another free worker, and the result bytes compared; a mismatch goes to a third
 * worker, the result two agree on is kept and the odd worker fenced (with its unaudited results of
 * the group, which run again); two workers that disagree with no third to arbitrate, or three
 * different results, end the run with one line (a result that may be wrong is never merged). A
 * group's results go to the merge only once every lane's audit is settled. Who audits what depends
 * on timing; the bytes merged do not. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/lane_delta.h"
#include "common/optimizer/lane_runner.h"
#include "common/optimizer/lane_start.h"
#include "common/optimizer/lane_wire.h"
#include "coordinator/views/lane_audit.h"
#include "coordinator/views/views_remote_internal.h"

/* The results of one lane so far (bytes owned), for the audit. */
typedef struct lane_votes {
    co_audit_vote v[CO_AUDIT_MAX_VOTES];
    uint32_t n;
    uint32_t decoded; /* the vote whose bytes are in the lane's lm_lane_result */
    uint32_t want;    /* results wanted: 0 not yet decided (at its first send), 1, 2 (audited),
                         3 (two disagree: a third arbitrates) */
    int accepted;     /* the lane's result is settled (counted in done) */
} lane_votes;

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
    uint64_t hash; /* of the start mesh */
    /* per lane of the group, allocated for its b->n lanes (group_alloc) */
    uint32_t *queue; /* [CO_AUDIT_MAX_VOTES * n] runs of lanes waiting for a worker, lane order */
    uint32_t n_queue, done;
    uint32_t *strikes; /* [n] failures of each lane */
    uint32_t *tries;   /* [n] sends of each lane (lost, stale in between) */
    uint32_t *lane_of; /* [n_live] lane + 1 in flight on live[i], 0 none */
    lane_votes *votes; /* [n] */
} lane_run;

/* The group's per-lane arrays, zeroed, for its b->n lanes (at most LM_MAX_EDGES_IN_FLIGHT). */
static lm_status group_alloc(lane_run *x)
{
    uint32_t n = x->b->n;
    x->queue = calloc((size_t)CO_AUDIT_MAX_VOTES * n, sizeof *x->queue);
    x->strikes = calloc(n, sizeof *x->strikes);
    x->tries = calloc(n, sizeof *x->tries);
    x->votes = calloc(n, sizeof *x->votes);
    if (!x->queue || !x->strikes || !x->tries || !x->votes)
        return lm_fail(LM_E_NOMEM, "out of memory for a group of %u lanes", n);
    return LM_OK;
}

static void group_free(lane_run *x)
{
    free(x->queue);
    free(x->strikes);
    free(x->tries);
    free(x->votes);
}

static void requeue(lane_run *x, uint32_t lane)
{
    uint32_t at = x->n_queue++;
    while (at && x->queue[at - 1] > lane) { /* kept in lane order: the lowest goes first */
        x->queue[at] = x->queue[at - 1];
        at--;
    }
    x->queue[at] = lane;
}

/* Runs of lane queued or in flight. */
static uint32_t pending(const lane_run *x, uint32_t lane)
{
    uint32_t n = 0;
    for (uint32_t k = 0; k < x->n_queue; k++)
        n += x->queue[k] == lane;
    for (uint32_t i = 0; i < x->r->n_live; i++)
        n += x->lane_of[i] == lane + 1;
    return n;
}

/* Queue runs of lane until its results and its runs cover what it wants. */
static void top_up(lane_run *x, uint32_t lane)
{
    const lane_votes *lv = &x->votes[lane];
    uint32_t want = lv->want ? lv->want : 1;
    if (lv->accepted)
        return;
    for (uint32_t have = lv->n + pending(x, lane); have < want; have++)
        requeue(x, lane);
}

/* Drops the queued runs of lane (settled). */
static void unqueue(lane_run *x, uint32_t lane)
{
    uint32_t n = 0;
    for (uint32_t k = 0; k < x->n_queue; k++)
        if (x->queue[k] != lane)
            x->queue[n++] = x->queue[k];
    x->n_queue = n;
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

/* 1: worker id gave one of the lane's results so far (it may not audit it). */
static int voted(const lane_run *x, uint32_t lane, uint32_t id)
{
    const lane_votes *lv = &x->votes[lane];
    for (uint32_t i = 0; i < lv->n; i++)
        if (lv->v[i].worker == id)
            return 1;
    return 0;
}

/* Workers of the layout, not lost, that gave none of the lane's results (auditors); 0 none. */
static uint32_t other_worker(const lane_run *x, uint32_t lane)
{
    const co_remote *r = x->r;
    uint32_t n = 0;
    for (uint32_t i = 0; i < r->n_live; i++)
        n += !r->live[i]->lost && r->live[i]->job == r->job && !voted(x, lane, r->live[i]->id);
    return n;
}

/* The place in the queue of the first lane w may run (one it gave no result of), or n_queue. */
static uint32_t first_for(const lane_run *x, const co_worker *w)
{
    uint32_t k = 0;
    while (k < x->n_queue && voted(x, x->queue[k], w->id))
        k++;
    return k;
}

/* Free workers of the layout get the lanes waiting, lowest first (an audit never goes to a
 * worker that gave one of the lane's results). */
static lm_status dispatch(lane_run *x)
{
    co_remote *r = x->r;
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < r->n_live && x->n_queue && st == LM_OK; i++) {
        co_worker *w = r->live[i];
        if (w->lost || x->lane_of[i] || w->job != r->job)
            continue;
        uint32_t k = first_for(x, w);
        if (k == x->n_queue)
            continue;
        uint32_t lane = x->queue[k];
        if (++x->tries[lane] > CO_REMOTE_TRIES)
            return lm_fail(LM_E_IO,
                           "lane %u sent %u times: its workers keep being lost or "
                           "falling behind",
                           lane, CO_REMOTE_TRIES);
        x->n_queue--;
        memmove(x->queue + k, x->queue + k + 1, (x->n_queue - k) * sizeof *x->queue);
        st = send_lane(x, w, lane);
        x->lane_of[i] = lane + 1;
        lane_votes *lv = &x->votes[lane];
        if (!lv->want) { /* its first send: audited or not, by the worker it goes to (not with
                            no other worker to audit it) */
            lv->want = co_audit_wanted(r->audit, w->lanes_confirmed, x->hash, lane) &&
                               other_worker(x, lane) > 1
                           ? 2
                           : 1;
            r->lane_stats.audits += lv->want == 2;
            top_up(x, lane); /* the audit's run goes to the next free other worker */
        }
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
    top_up(x, lane);
    return LM_OK;
}

static co_worker *live_worker(const lane_run *x, uint32_t id)
{
    for (uint32_t i = 0; i < x->r->n_live; i++)
        if (x->r->live[i]->id == id && !x->r->live[i]->lost)
            return x->r->live[i];
    return NULL;
}

static void votes_clear(lane_votes *lv)
{
    for (uint32_t i = 0; i < lv->n; i++)
        free((void *)lv->v[i].bytes);
    memset(lv, 0, sizeof *lv);
}

static void accept(lane_run *x, uint32_t lane)
{
    x->votes[lane].accepted = 1;
    x->done++;
    unqueue(x, lane); /* runs still in flight are answered and dropped */
}

/* A worker fenced for a wrong result: its results of this group that no one checked are dropped
 * and those lanes run again (a settled one is queued again; one waiting for its audit takes the
 * audit's result as its first). */
static void forget_worker(lane_run *x, uint32_t id)
{
    for (uint32_t lane = 0; lane < x->b->n; lane++) {
        lane_votes *lv = &x->votes[lane];
        if (lv->n != 1 || lv->v[0].worker != id)
            continue;
        int was = lv->accepted;
        uint32_t want = lv->want;
        votes_clear(lv);
        lv->want = was ? 0 : want; /* a settled lane is decided again at its next send */
        if (was)
            x->done--;
        top_up(x, lane);
    }
}

/* The lane's result decoded from vote i's bytes (again only when the last decoded differ). */
static lm_status use_vote(lane_run *x, uint32_t lane, uint32_t i)
{
    lane_votes *lv = &x->votes[lane];
    if (lv->decoded < lv->n && co_audit_same(&lv->v[lv->decoded], &lv->v[i]))
        return LM_OK;
    lv->decoded = i;
    return lm_lane_result_decode(lv->v[i].bytes, lv->v[i].len, x->b->n_verts, x->b->res[lane]);
}

/* Two results agree (vote win and another): the lane's result is theirs, the workers that agree
 * have one more confirmed result, the others are fenced. */
static lm_status settle(lane_run *x, uint32_t lane, uint32_t win)
{
    lane_votes *lv = &x->votes[lane];
    const co_audit_vote *v = lv->v;
    lm_status st = use_vote(x, lane, win);
    uint32_t odd[CO_AUDIT_MAX_VOTES], n_odd = 0, peer = 0;
    for (uint32_t i = 0; i < lv->n; i++) {
        co_worker *w = live_worker(x, v[i].worker);
        if (!co_audit_same(&v[i], &v[win]))
            odd[n_odd++] = v[i].worker;
        else if (w)
            w->lanes_confirmed++;
        if (i != win && co_audit_same(&v[i], &v[win]))
            peer = v[i].worker;
    }
    for (uint32_t k = 0; k < n_odd; k++) {
        co_worker *w = live_worker(x, odd[k]);
        char why[200];
        snprintf(why, sizeof why,
                 "a wrong lane result (lane %u of group %llu: workers %u and %u agree on another)",
                 lane, (unsigned long long)x->r->lane_group, v[win].worker, peer);
        if (w) { /* fenced once: a worker already lost is not counted again */
            x->r->lane_stats.audit_fenced++;
            co_pool_fence(x->r->pool, w, why);
        }
        forget_worker(x, odd[k]);
    }
    if (st == LM_OK)
        accept(x, lane);
    return st;
}

/* Lanes waiting with no worker left that may run them (nothing in flight): a first result whose
 * audit no one can run is taken as it is; a mismatch no one can arbitrate stops the run. */
static lm_status settle_stuck(lane_run *x)
{
    for (uint32_t k = 0; k < x->n_queue;) {
        uint32_t lane = x->queue[k];
        lane_votes *lv = &x->votes[lane];
        if (!lv->n || other_worker(x, lane)) {
            k++;
            continue;
        }
        k = 0; /* the queue changes: from its start again */
        if (lv->n > 1)
            return lm_fail(
                LM_E_INTERNAL,
                "lane %u of group %llu: workers %u and %u returned different results and no third "
                "worker can arbitrate: stopping (a result that may be wrong is never "
                "merged)",
                lane, (unsigned long long)x->r->lane_group, lv->v[0].worker, lv->v[1].worker);
        lm_status st = use_vote(x, lane, 0);
        if (st != LM_OK)
            return st;
        x->r->lane_stats.audits_skipped++;
        accept(x, lane); /* unqueued */
    }
    return LM_OK;
}

/* The result bytes of lane from w, the lane's vote: accepted, compared with the audit's,
 * arbitrated by a third worker, or the run stopped (lane_audit.h). */
static lm_status vote(lane_run *x, co_worker *w, uint32_t lane, const uint8_t *bytes, size_t len)
{
    lane_votes *lv = &x->votes[lane];
    co_lane_stats *ls = &x->r->lane_stats;
    uint8_t *copy = malloc(len ? len : 1);
    if (!copy)
        return lm_fail(LM_E_NOMEM, "out of memory for a lane's result");
    if (len)
        memcpy(copy, bytes, len);
    lv->decoded = lv->n;
    lv->v[lv->n++] = (co_audit_vote){w->id, copy, len};
    if (lv->n == 1 && lv->want <= 1) {
        accept(x, lane);
        return LM_OK;
    }
    if (lv->n == 1) { /* the audit's run is queued or in flight */
        top_up(x, lane);
        return LM_OK;
    }
    uint32_t win = 0;
    co_audit_verdict vd = co_audit_tally(lv->v, lv->n, &win);
    if (vd == CO_AUDIT_AGREED)
        return settle(x, lane, win);
    if (vd == CO_AUDIT_SPLIT)
        return lm_fail(LM_E_INTERNAL,
                       "lane %u of group %llu: workers %u, %u and %u returned three different "
                       "results: stopping (a result that may be wrong is never merged)",
                       lane, (unsigned long long)x->r->lane_group, lv->v[0].worker, lv->v[1].worker,
                       lv->v[2].worker);
    ls->audit_mismatches++;
    if (!other_worker(x, lane))
        return lm_fail(LM_E_INTERNAL,
                       "lane %u of group %llu: workers %u and %u returned different results and "
                       "no third worker can arbitrate: stopping (a result that may be wrong is "
                       "never merged)",
                       lane, (unsigned long long)x->r->lane_group, lv->v[0].worker,
                       lv->v[1].worker);
    ls->audits++;
    lv->want = CO_AUDIT_MAX_VOTES;
    top_up(x, lane);
    return LM_OK;
}

/* A LaneDone from w for lane: decoded into the lane's result, or w fenced and the lane again. */
static lm_status take_result(lane_run *x, co_worker *w, uint32_t lane)
{
    const Lumesh__LaneDone *d = w->reply.msg->lane_done;
    if (x->votes[lane].accepted)
        return LM_OK; /* an extra run of a settled lane (a lost worker's run sent again) */
    lm_lane_result *res = x->b->res[lane];
    lm_status st = d->group == x->r->lane_group && d->lane == lane
                       ? lm_lane_result_decode(d->result.data, d->result.len, x->b->n_verts, res)
                       : lm_fail(LM_E_FORMAT, "the result of lane %u of group %llu", d->lane,
                                 (unsigned long long)d->group);
    if (st == LM_OK && res->status != LM_OK)
        st = lm_fail(LM_E_FORMAT, "a result that says it failed");
    if (st != LM_OK) {
        char why[300];
        x->votes[lane].decoded = CO_AUDIT_MAX_VOTES; /* the lane's result holds none of its votes */
        snprintf(why, sizeof why, "a lane's result that does not fit: %.200s", lm_last_error());
        co_pool_fence(x->r->pool, w, why);
        return strike(x, w, lane, st);
    }
    w->evals += res->evals;
    w->busy_s += 1e-6 * (double)d->busy_us;
    *x->b->result_bytes += d->result.len;
    return vote(x, w, lane, d->result.data, d->result.len);
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
            top_up(x, lane);
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
            top_up(x, lane);
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
        if (st == LM_OK && x->n_queue && !in_flight(x))
            st = settle_stuck(x);
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
    lm_status st = group_alloc(&x);
    for (uint32_t i = 0; i < b->n && st == LM_OK; i++)
        x.queue[x.n_queue++] = i;
    if (st == LM_OK)
        st = co_remote_layout(r);
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
    for (uint32_t i = 0; x.votes && i < b->n; i++)
        votes_clear(&x.votes[i]);
    group_free(&x);
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
    sum->audits += a->audits;
    sum->audit_mismatches += a->audit_mismatches;
    sum->audit_fenced += a->audit_fenced;
    sum->audits_skipped += a->audits_skipped;
}
