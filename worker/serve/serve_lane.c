/* worker/serve/serve_lane.c — RunLane (--lanes remote): an isolated lane of a group of edges in
 * flight, run here with lm_lane_host_run against the group's start mesh (sent with the first lane
 * of each group this worker gets, whole or as a delta against the last group's record, which this
 * worker keeps; kept for the group's other lanes) and this worker's views, which serve every
 * view of the job and are at the group's start (the request's seq), the geometric term added where
 * the request asks for it. The group's collapse queue comes the same way (whole or as a delta
 * against the last group's, kept here) and every lane's request borrows it: a request carries only
 * its head (lane_wire.h). Everything decoded is checked (lane_wire.h, lane_start.h); a failure is
 * answered, never fatal. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/optimizer/lane_delta.h"
#include "common/optimizer/lane_host.h"
#include "common/optimizer/lane_start.h"
#include "common/optimizer/lane_wire.h"
#include "worker/serve/serve_internal.h"

#define CFG_MAX 128 /* bytes of an encoded moves config */

struct wk_lanes {
    lm_views base; /* the views a lane is priced with: the worker's, plus the geometric term */
    wk_server *s;
    int surface;
    lm_lane_host *host;
    uint8_t cfg[CFG_MAX]; /* the config the host was made with */
    size_t n_cfg;
    lm_mesh *start; /* the start mesh of (job, group) */
    uint64_t job, group;
    uint8_t *record; /* its encoded record: the base of the next group's delta */
    size_t n_record;
    lm_cq_entry *queue; /* the collapse queue of (qjob, qgroup): every lane of it borrows it */
    uint32_t n_queue;
    uint64_t qjob, qgroup;
    uint8_t *qrecord; /* its encoded section: the base of the next group's queue delta */
    size_t n_qrecord;
    uint64_t lanes_run; /* lanes taken (for the test hooks crash-lanes-as and lie-lanes) */
    int lying;          /* the test hook lie-lanes: this lane's ΔE are corrupted */
    uint64_t epoch;     /* counts the starts and queues taken: names the pair for the host */
    lm_lane_request req;
    lm_lane_result res;
};

static wk_lanes *of(lm_views *v)
{
    return (wk_lanes *)v;
}

static lm_status lv_evaluate(lm_views *v, const lm_patch *p, uint32_t n, int64_t *delta)
{
    wk_lanes *l = of(v);
    wk_server *s = l->s;
    lm_status st = s->v->ops->evaluate(s->v, p, n, delta);
    for (uint32_t i = 0; i < n && st == LM_OK && l->surface; i++)
        delta[i] += lm_surface_table_delta(s->geo, &p[i]);
    for (uint32_t i = 0; i < n && st == LM_OK && l->lying; i++)
        delta[i] = -delta[i] - 1; /* a worker gone wrong: what costs seems to pay */
    return st;
}

static void lv_info(lm_views *v, lm_views_info *out)
{
    wk_server *s = of(v)->s;
    s->v->ops->info(s->v, out);
}

static void lv_destroy(lm_views *v)
{
    (void)v; /* owned by wk_lanes */
}

static const lm_views_ops lane_views_ops = {
    .evaluate = lv_evaluate,
    .info = lv_info,
    .destroy = lv_destroy,
};

void wk_serve_lanes_free(wk_server *s)
{
    wk_lanes *l = s->lanes;
    if (!l)
        return;
    lm_lane_host_destroy(l->host);
    lm_mesh_destroy(l->start);
    free(l->record);
    free(l->queue);
    free(l->qrecord);
    l->req.queue = NULL; /* borrowed */
    lm_lane_request_free(&l->req);
    lm_lane_result_free(&l->res);
    free(l);
    s->lanes = NULL;
}

static lm_status lanes_get(wk_server *s, wk_lanes **out)
{
    if (!s->lanes) {
        wk_lanes *l = calloc(1, sizeof *l);
        if (!l)
            return lm_fail(LM_E_NOMEM, "out of memory for lanes");
        l->base.ops = &lane_views_ops;
        l->s = s;
        lm_lane_request_init(&l->req);
        lm_lane_result_init(&l->res);
        s->lanes = l;
    }
    *out = s->lanes;
    return LM_OK;
}

/* Drops the start (and the base it gives deltas). */
static void drop_start(wk_lanes *l)
{
    lm_mesh_destroy(l->start);
    l->start = NULL;
    free(l->record);
    l->record = NULL;
    l->n_record = 0;
    l->group = 0;
}

/* The start record the request carries: its `start` (copied), or its delta applied to the record
 * kept for base_group (*missing = 1 and nothing made when that is not the one kept). */
static lm_status start_record(const wk_server *s, const wk_lanes *l, const Lumesh__RunLane *q,
                              uint8_t **rec, size_t *n, int *missing)
{
    *rec = NULL;
    *n = 0;
    if (q->start.len && q->start_delta.len)
        return lm_fail(LM_E_FORMAT, "a lane with both a start mesh and a delta");
    if (q->start_delta.len) {
        *missing = !l->record || l->job != s->job || l->group != q->base_group;
        return *missing ? LM_OK
                        : lm_lane_delta_apply(l->record, l->n_record, q->start_delta.data,
                                              q->start_delta.len, rec, n);
    }
    if (!(*rec = malloc(q->start.len)))
        return lm_fail(LM_E_NOMEM, "out of memory for a start mesh");
    memcpy(*rec, q->start.data, q->start.len);
    *n = q->start.len;
    return LM_OK;
}

/* The group's start: the one sent with this request (whole or as a delta against the last
 * group's), else the one kept for its group. *missing = 1: the delta's base is not the one kept
 * (the coordinator is told Stale and sends the start whole). */
static lm_status take_start(wk_server *s, wk_lanes *l, const Lumesh__RunLane *q, int *missing)
{
    *missing = 0;
    if (!q->start.len && !q->start_delta.len) {
        if (!l->start || l->job != s->job || l->group != q->group)
            return lm_fail(LM_E_INVALID, "a lane of group %llu without its start mesh",
                           (unsigned long long)q->group);
        return LM_OK;
    }
    uint8_t *rec = NULL;
    size_t n = 0;
    lm_status st = start_record(s, l, q, &rec, &n, missing);
    if (st != LM_OK || *missing) {
        free(rec);
        if (st != LM_OK)
            drop_start(l);
        return st;
    }
    drop_start(l);
    lm_mesh *m = NULL;
    st = lm_mesh_create(&m);
    if (st == LM_OK)
        st = lm_lane_mesh_decode(rec, n, m);
    if (st == LM_OK && lm_mesh_hash(m) != q->start_hash)
        st = lm_fail(LM_E_FORMAT, "a start mesh whose hash is not the one named");
    if (st != LM_OK) {
        lm_mesh_destroy(m);
        free(rec);
        return st;
    }
    l->start = m;
    l->epoch++;
    l->record = rec;
    l->n_record = n;
    l->job = s->job;
    l->group = q->group;
    return LM_OK;
}

/* Drops the queue (and the base it gives deltas). */
static void drop_queue(wk_lanes *l)
{
    free(l->queue);
    l->queue = NULL;
    l->n_queue = 0;
    free(l->qrecord);
    l->qrecord = NULL;
    l->n_qrecord = 0;
    l->qgroup = 0;
}

/* The queue section the request carries: its `queue` (copied), or its delta applied to the one
 * kept for base_group (*missing = 1 and nothing made when that is not the one kept). */
static lm_status queue_record(const wk_server *s, const wk_lanes *l, const Lumesh__RunLane *q,
                              uint8_t **rec, size_t *n, int *missing)
{
    *rec = NULL;
    *n = 0;
    if (q->queue.len && q->queue_delta.len)
        return lm_fail(LM_E_FORMAT, "a lane with both a collapse queue and its delta");
    if (q->queue_delta.len) {
        *missing = !l->qrecord || l->qjob != s->job || l->qgroup != q->base_group;
        return *missing ? LM_OK
                        : lm_lane_delta_apply(l->qrecord, l->n_qrecord, q->queue_delta.data,
                                              q->queue_delta.len, rec, n);
    }
    if (!(*rec = malloc(q->queue.len)))
        return lm_fail(LM_E_NOMEM, "out of memory for a collapse queue");
    memcpy(*rec, q->queue.data, q->queue.len);
    *n = q->queue.len;
    return LM_OK;
}

/* The group's queue, after its start (take_start): the one sent with this request (whole or as a
 * delta against the last group's), else the one kept for its group. *missing as take_start's. */
static lm_status take_queue(wk_server *s, wk_lanes *l, const Lumesh__RunLane *q, int *missing)
{
    *missing = 0;
    if (!q->queue.len && !q->queue_delta.len) {
        if (!l->qrecord || l->qjob != s->job || l->qgroup != q->group)
            return lm_fail(LM_E_INVALID, "a lane of group %llu without its collapse queue",
                           (unsigned long long)q->group);
        return LM_OK;
    }
    uint8_t *rec = NULL;
    size_t n = 0;
    lm_status st = queue_record(s, l, q, &rec, &n, missing);
    if (st != LM_OK || *missing) {
        free(rec);
        if (st != LM_OK)
            drop_queue(l);
        return st;
    }
    drop_queue(l);
    lm_cq_entry *e = NULL;
    uint32_t n_e = 0;
    st = lm_lane_queue_decode(rec, n, l->start->n_verts, &e, &n_e);
    if (st != LM_OK) {
        free(rec);
        return st;
    }
    l->queue = e;
    l->n_queue = n_e;
    l->epoch++;
    l->qrecord = rec;
    l->n_qrecord = n;
    l->qjob = s->job;
    l->qgroup = q->group;
    return LM_OK;
}

/* A host made with the request's config (kept while the config stays). */
static lm_status take_config(wk_lanes *l, const Lumesh__RunLane *q)
{
    if (l->host && q->config.len == l->n_cfg && !memcmp(q->config.data, l->cfg, l->n_cfg))
        return LM_OK;
    lm_moves_config cfg;
    lm_status st = q->config.len <= CFG_MAX
                       ? lm_lane_config_decode(q->config.data, q->config.len, &cfg)
                       : lm_fail(LM_E_FORMAT, "a moves config of %zu bytes", q->config.len);
    lm_lane_host_destroy(l->host);
    l->host = NULL;
    l->n_cfg = 0;
    if (st == LM_OK)
        st = lm_lane_host_create(&cfg, &l->host);
    if (st == LM_OK) {
        memcpy(l->cfg, q->config.data, q->config.len);
        l->n_cfg = q->config.len;
    }
    return st;
}

/* Why this worker cannot price the lane now: 1 stale (its views are not at seq, or lack the
 * term); LM_OK with 0 when it can; a failure when it never could (not every view). */
static lm_status check_views(wk_server *s, const lm_msg *m, int *stale)
{
    *stale = !s->v || s->stale || m->seq != s->seq || (m->run_lane->surface && !s->geo);
    if (*stale)
        return LM_OK;
    if (s->deal.first != 0 || s->deal.stride != 1 || s->deal.count != s->views->count)
        return lm_fail(LM_E_INVALID, "a lane asked of a worker that serves %u of %u views",
                       s->deal.count, s->views->count);
    return LM_OK;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Fault injection for tests (LUMESH_WORKER_FAULT, read only by builds with LUMESH_TEST_HOOKS):
 * "lie-lanes-as=N" makes the worker the coordinator welcomed as worker N answer every lane with a
 * result cut short by a byte (a worker gone wrong: the coordinator must fence it). */
static int lies(const wk_server *s)
{
    static const char kind[] = "lie-lanes-as=";
    return s->fault && !strncmp(s->fault, kind, sizeof kind - 1) &&
           strtoul(s->fault + sizeof kind - 1, NULL, 10) == s->worker_id;
}

/* "lie-lanes=N" (or "lie-lanes=N@W": only the worker the coordinator welcomed as W): from the
 * N-th lane this worker takes on, the ΔE of every evaluation of its lanes is corrupted (negated,
 * less one: a broken driver, a flipped sign), its answers well formed. 0 without the hook. The
 * coordinator's audits must catch it (coordinator/views/lane_audit.h). */
static uint64_t lie_from(const wk_server *s)
{
    static const char kind[] = "lie-lanes=";
    if (!s->fault || strncmp(s->fault, kind, sizeof kind - 1))
        return 0;
    char *end = NULL;
    uint64_t n = strtoull(s->fault + sizeof kind - 1, &end, 10);
    if (*end == '@' && strtoul(end + 1, NULL, 10) != s->worker_id)
        return 0;
    return n;
}

/* "crash-lanes-as=N:M": the worker welcomed as N dies (abort) when its M-th lane comes, after
 * taking that lane's start (a worker lost mid-run: its replacement starts without a base). */
static void maybe_crash(const wk_server *s, uint64_t lanes)
{
    static const char kind[] = "crash-lanes-as=";
    if (!s->fault || strncmp(s->fault, kind, sizeof kind - 1))
        return;
    char *end = NULL;
    unsigned long id = strtoul(s->fault + sizeof kind - 1, &end, 10);
    if (id == s->worker_id && *end == ':' && strtoull(end + 1, NULL, 10) == lanes)
        abort();
}

static lm_status run_lane(wk_server *s, wk_lanes *l, const lm_msg *m)
{
    const Lumesh__RunLane *q = m->run_lane;
    double t0 = now_s();
    l->req.queue = NULL; /* borrowed from l->queue */
    lm_status st = lm_lane_request_decode_head(q->request.data, q->request.len, &l->req);
    l->req.queue = st == LM_OK ? l->queue : NULL;
    l->req.n_queue = st == LM_OK ? l->n_queue : 0;
    if (st == LM_OK && l->req.n_verts != l->start->n_verts)
        st = lm_fail(LM_E_FORMAT, "a lane's request for %u vertex slots, the start has %u",
                     l->req.n_verts, l->start->n_verts);
    if (st == LM_OK && (l->req.index != q->lane || l->req.index >= l->req.n_group))
        st = lm_fail(LM_E_FORMAT, "lane %u of a group of %u named lane %u", l->req.index,
                     l->req.n_group, q->lane);
    l->surface = q->surface;
    if (st == LM_OK &&
        lm_lane_host_run(l->host, l->start, &l->base, &l->req, l->epoch, &l->res) != LM_OK)
        st = lm_fail(l->res.status, "%s", l->res.msg);
    uint8_t *buf = NULL;
    size_t len = 0;
    l->req.queue = NULL;
    l->req.n_queue = 0;
    if (st == LM_OK)
        st = lm_lane_result_encode(&l->res, &buf, &len);
    if (st != LM_OK)
        return wk_serve_fail(s, m->req, st, lm_last_error());
    Lumesh__LaneDone d = LUMESH__LANE_DONE__INIT;
    d.group = q->group;
    d.lane = q->lane;
    d.result = (ProtobufCBinaryData){len - (len && lies(s)), buf};
    d.busy_us = (uint64_t)((now_s() - t0) * 1e6);
    st = wk_serve_send(s, m->req, LUMESH__MSG__BODY_LANE_DONE, &d);
    free(buf);
    return st;
}

lm_status wk_serve_lane(wk_server *s, const lm_msg *m)
{
    const Lumesh__RunLane *q = m->run_lane;
    wk_lanes *l = NULL;
    int stale = 0, missing = 0;
    lm_status st = s->original && q->job == s->job
                       ? LM_OK
                       : lm_fail(LM_E_INVALID, "a lane of job %llu, but the job is %llu",
                                 (unsigned long long)q->job, (unsigned long long)s->job);
    if (st == LM_OK)
        st = lanes_get(s, &l);
    if (st == LM_OK)
        st = take_start(s, l, q, &missing); /* kept even when the views are stale */
    if (st == LM_OK && !missing)
        st = take_queue(s, l, q, &missing); /* decoded against the start's vertex slots */
    if (st == LM_OK)
        st = check_views(s, m, &stale);
    stale = stale || missing;
    if (st == LM_OK && !stale)
        st = take_config(l, q);
    if (st != LM_OK)
        return wk_serve_fail(s, m->req, st, lm_last_error());
    if (stale) {
        Lumesh__Stale r = LUMESH__STALE__INIT;
        return wk_serve_send(s, m->req, LUMESH__MSG__BODY_STALE, &r);
    }
    maybe_crash(s, ++l->lanes_run);
    l->lying = lie_from(s) && l->lanes_run >= lie_from(s);
    return run_lane(s, l, m);
}
