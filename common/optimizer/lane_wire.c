/* common/optimizer/lane_wire.c — a lane's request and result to bytes and back, every count and
 * id checked on the way in (lane_wire.h). */
#include "common/optimizer/lane_wire.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh.h"

#define REQUEST_MAGIC 0x51524e4cu /* "LNRQ" */
#define RESULT_MAGIC 0x53524e4cu  /* "LNRS" */
#define MAX_DIM 65536u            /* parameters of one operation */

/* ---- streams over memory ----------------------------------------------------------------------
 */

typedef struct wire {
    lm_bin b;
    size_t len; /* bytes of the message being read (bounds every count) */
} wire;

static lm_status open_write(wire *w, uint8_t **buf, size_t *len, const char *what)
{
    *buf = NULL;
    *len = 0;
    lm_bin_init_writer(&w->b, what);
    return LM_OK;
}

static lm_status close_write(wire *w, uint8_t **buf, size_t *len)
{
    return lm_bin_take(&w->b, buf, len);
}

static lm_status open_read(wire *w, const uint8_t *buf, size_t len, const char *what)
{
    lm_bin_init_reader(&w->b, buf, len, what);
    w->len = len;
    if (!len)
        w->b.status = lm_fail(LM_E_FORMAT, "%s is empty", what);
    return LM_OK;
}

/* The read's status: trailing bytes are an error too. */
static lm_status close_read(wire *w)
{
    if (w->b.status == LM_OK && w->len && lm_bin_left(&w->b))
        lm_bin_bad(&w->b, "trailing bytes");
    return w->b.status;
}

/* A count of items of at least `size` bytes each: no more than the message can hold, nor cap. */
static uint32_t get_count(wire *w, size_t size, uint32_t cap, const char *what)
{
    uint32_t n = lm_get_u32(&w->b);
    if (w->b.status == LM_OK && (n > cap || (size_t)n > w->len / size))
        lm_bin_bad(&w->b, "%u %s is more than the message holds", n, what);
    return w->b.status ? 0 : n;
}

/* A buffer for n items (NULL with a status when out of memory). */
static void *get_array(wire *w, uint32_t n, size_t size)
{
    void *p = malloc(n ? (size_t)n * size : 1);
    if (!p && w->b.status == LM_OK)
        w->b.status = lm_fail(LM_E_NOMEM, "out of memory for %s", w->b.what);
    return p;
}

static void get_check(wire *w, int ok, const char *what, uint32_t i)
{
    if (w->b.status == LM_OK && !ok)
        lm_bin_bad(&w->b, "bad %s %u", what, i);
}

static void put_entry(lm_bin *b, const lm_cq_entry *e)
{
    lm_put_u32(b, e->a);
    lm_put_u32(b, e->b);
    lm_put_i64(b, e->est);
    lm_put_u32(b, (uint32_t)e->level);
    lm_put_u32(b, e->in_heap);
}

/* An entry whose vertices are below n_verts. */
static lm_cq_entry get_entry(wire *w, uint32_t n_verts, uint32_t i)
{
    lm_cq_entry e;
    e.a = lm_get_u32(&w->b);
    e.b = lm_get_u32(&w->b);
    e.est = lm_get_i64(&w->b);
    e.level = (int32_t)lm_get_u32(&w->b);
    e.in_heap = lm_get_u32(&w->b);
    get_check(w,
              e.a < e.b && e.b < n_verts && e.level >= -1 && e.level < LM_LEVELS && e.in_heap <= 1,
              "queue entry", i);
    return e;
}

/* ---- the request ------------------------------------------------------------------------------
 */

static void put_request(lm_bin *b, const lm_lane_request *q)
{
    lm_put_u32(b, REQUEST_MAGIC);
    lm_put_u32(b, LM_LANE_WIRE_VERSION);
    lm_put_u32(b, q->index);
    lm_put_u32(b, q->n_group);
    lm_put_u32(b, q->a);
    lm_put_u32(b, q->b);
    lm_put_u32(b, q->n_verts);
    lm_put_u64(b, q->clock);
    lm_put_u32(b, q->n_vetoed);
    for (uint32_t i = 0; i < q->n_vetoed; i++)
        lm_put_u32(b, q->vetoed[i]);
    lm_move_stats_save(b, &q->stats);
    lm_put_f64(b, q->tp_cfg.threshold_half_life);
    lm_put_f64(b, q->tp_cfg.stats_half_life);
    lm_put_u32(b, q->tp_cfg.max_search_evals);
    lm_put_i64(b, q->last_collapse);
    lm_put_u64(b, q->last_time);
    for (int l = 0; l < LM_LEVELS; l++)
        lm_stat_save(b, &q->improve[l]);
}

static void put_queue(lm_bin *b, const lm_cq_entry *e, uint32_t n)
{
    lm_put_u32(b, n);
    if (LM_BIN_HOST_LE && sizeof *e == 24) { /* put_entry's layout: the entries' bytes at once */
        lm_put_bytes(b, e, (size_t)n * sizeof *e);
        return;
    }
    for (uint32_t i = 0; i < n; i++)
        put_entry(b, &e[i]);
}

lm_status lm_lane_request_encode(const lm_lane_request *q, uint8_t **buf, size_t *len)
{
    wire w;
    lm_status st = open_write(&w, buf, len, "a lane request");
    if (st)
        return st;
    put_request(&w.b, q);
    put_queue(&w.b, q->queue, q->n_queue);
    return close_write(&w, buf, len);
}

lm_status lm_lane_request_encode_head(const lm_lane_request *q, uint8_t **buf, size_t *len)
{
    wire w;
    lm_status st = open_write(&w, buf, len, "a lane request's head");
    if (st)
        return st;
    put_request(&w.b, q);
    return close_write(&w, buf, len);
}

lm_status lm_lane_queue_encode(const lm_cq_entry *e, uint32_t n, uint8_t **buf, size_t *len)
{
    wire w;
    lm_status st = open_write(&w, buf, len, "a collapse queue");
    if (st)
        return st;
    put_queue(&w.b, e, n);
    return close_write(&w, buf, len);
}

static int finite_nonneg(double x)
{
    return isfinite(x) && x >= 0;
}

static void get_request_head(wire *w, lm_lane_request *q)
{
    if (lm_get_u32(&w->b) != REQUEST_MAGIC || lm_get_u32(&w->b) != LM_LANE_WIRE_VERSION)
        get_check(w, 0, "message kind or version", 0);
    q->index = lm_get_u32(&w->b);
    q->n_group = lm_get_u32(&w->b);
    q->a = lm_get_u32(&w->b);
    q->b = lm_get_u32(&w->b);
    q->n_verts = lm_get_u32(&w->b);
    q->clock = lm_get_u64(&w->b);
    get_check(w, q->n_group >= 1 && q->n_group <= LM_MAX_EDGES_IN_FLIGHT && q->index < q->n_group,
              "lane index", q->index);
    get_check(w, q->a != q->b && q->a < q->n_verts && q->b < q->n_verts, "edge vertex", q->a);
    q->n_vetoed = q->cap_vetoed = get_count(w, 4, q->n_verts, "vetoed vertices");
    q->vetoed = get_array(w, q->n_vetoed, sizeof *q->vetoed);
    for (uint32_t i = 0; i < q->n_vetoed && w->b.status == LM_OK; i++) {
        q->vetoed[i] = lm_get_u32(&w->b);
        get_check(w, q->vetoed[i] < q->n_verts && (i == 0 || q->vetoed[i] > q->vetoed[i - 1]),
                  "vetoed vertex", i);
    }
}

static void get_request_state(wire *w, lm_lane_request *q)
{
    lm_move_stats_load(&w->b, &q->stats);
    get_check(w, finite_nonneg(q->stats.half_life) && finite_nonneg(q->stats.min_weight),
              "statistics constant", 0);
    q->tp_cfg.threshold_half_life = lm_get_f64(&w->b);
    q->tp_cfg.stats_half_life = lm_get_f64(&w->b);
    q->tp_cfg.max_search_evals = lm_get_u32(&w->b);
    get_check(
        w, finite_nonneg(q->tp_cfg.threshold_half_life) && finite_nonneg(q->tp_cfg.stats_half_life),
        "teleport constant", 0);
    q->last_collapse = lm_get_i64(&w->b);
    q->last_time = lm_get_u64(&w->b);
    for (int l = 0; l < LM_LEVELS; l++)
        lm_stat_load(&w->b, &q->improve[l]);
}

/* The queue's section: entries below n_verts, strictly sorted by edge, into *e (*n). */
static void get_queue(wire *w, uint32_t n_verts, lm_cq_entry **e, uint32_t *n)
{
    *n = get_count(w, 24, UINT32_MAX, "queue entries");
    lm_cq_entry *q = *e = get_array(w, *n, sizeof *q);
    for (uint32_t i = 0; i < *n && w->b.status == LM_OK; i++) {
        q[i] = get_entry(w, n_verts, i);
        const lm_cq_entry *p = i ? &q[i - 1] : NULL;
        get_check(w, !p || p->a < q[i].a || (p->a == q[i].a && p->b < q[i].b),
                  "queue order at entry", i);
    }
}

/* The request (head, and its queue when with_queue) from buf. */
static lm_status decode_request(const uint8_t *buf, size_t len, int with_queue, lm_lane_request *q)
{
    lm_lane_request_free(q);
    wire w;
    lm_status st = open_read(&w, buf, len, with_queue ? "a lane request" : "a lane request's head");
    if (st)
        return st;
    get_request_head(&w, q);
    if (w.b.status == LM_OK)
        get_request_state(&w, q);
    if (w.b.status == LM_OK && with_queue)
        get_queue(&w, q->n_verts, &q->queue, &q->n_queue);
    st = close_read(&w);
    if (st)
        lm_lane_request_free(q);
    return st;
}

lm_status lm_lane_request_decode(const uint8_t *buf, size_t len, lm_lane_request *q)
{
    return decode_request(buf, len, 1, q);
}

lm_status lm_lane_request_decode_head(const uint8_t *buf, size_t len, lm_lane_request *q)
{
    return decode_request(buf, len, 0, q);
}

lm_status lm_lane_queue_decode(const uint8_t *buf, size_t len, uint32_t n_verts, lm_cq_entry **e,
                               uint32_t *n)
{
    *e = NULL;
    *n = 0;
    wire w;
    lm_status st = open_read(&w, buf, len, "a collapse queue");
    if (st)
        return st;
    get_queue(&w, n_verts, e, n);
    st = close_read(&w);
    if (st) {
        free(*e);
        *e = NULL;
        *n = 0;
    }
    return st;
}

/* ---- the result -------------------------------------------------------------------------------
 */

static void put_ops(lm_bin *b, const lm_lane_result *r)
{
    lm_put_u32(b, r->n_ops);
    for (uint32_t i = 0; i < r->n_ops; i++) {
        const lm_lane_op *op = &r->ops[i];
        lm_put_u32(b, (uint32_t)op->r.kind);
        lm_put_u32(b, (uint32_t)op->r.level);
        lm_put_u32(b, op->r.a);
        lm_put_u32(b, op->r.b);
        lm_put_u32(b, op->r.v);
        lm_put_u32(b, op->r.dim);
        lm_put_i64(b, op->r.delta);
    }
    lm_put_u32(b, r->n_xs);
    for (uint32_t i = 0; i < r->n_xs; i++)
        lm_put_f64(b, r->xs[i]);
}

static void put_counters(lm_bin *b, const lm_lane_result *r)
{
    lm_put_i64(b, r->d_acc);
    lm_put_u64(b, r->mesh_hash);
    lm_put_i64(b, r->total);
    lm_put_u64(b, r->evals);
    for (int k = 0; k < LM_MOVE_KINDS; k++) {
        lm_put_u64(b, r->attempted[k]);
        lm_put_u64(b, r->accepted[k]);
    }
    lm_put_u64(b, r->searches);
    lm_put_u64(b, r->searches_failed);
    lm_put_u64(b, r->collapses_tried);
    lm_put_i64(b, r->last_collapse);
    lm_put_u64(b, r->last_time);
}

static void put_logs(lm_bin *b, const lm_lane_result *r)
{
    lm_put_u32(b, r->log.n_adds);
    for (uint32_t i = 0; i < r->log.n_adds; i++) {
        const lm_lane_stat_add *a = &r->log.adds[i];
        lm_put_u32(b, a->kind);
        lm_put_u32(b, (uint32_t)a->level);
        lm_put_f64(b, a->x);
        lm_put_f64(b, a->t);
        lm_put_u64(b, a->now);
    }
    lm_put_u32(b, r->log.n_queue);
    for (uint32_t i = 0; i < r->log.n_queue; i++) {
        put_entry(b, &r->log.queue[i].e);
        lm_put_u32(b, (uint32_t)r->log.queue[i].present);
    }
    lm_put_u32(b, r->touched.n);
    for (uint32_t i = 0; i < r->touched.n; i++)
        lm_put_u32(b, r->touched.ids[i]);
}

lm_status lm_lane_result_encode(const lm_lane_result *r, uint8_t **buf, size_t *len)
{
    wire w;
    lm_status st = open_write(&w, buf, len, "a lane result");
    if (st)
        return st;
    lm_put_u32(&w.b, RESULT_MAGIC);
    lm_put_u32(&w.b, LM_LANE_WIRE_VERSION);
    lm_put_u32(&w.b, (uint32_t)r->status);
    uint32_t n_msg = (uint32_t)strnlen(r->msg, sizeof r->msg - 1);
    lm_put_u32(&w.b, n_msg);
    lm_put_bytes(&w.b, r->msg, n_msg);
    put_ops(&w.b, r);
    put_counters(&w.b, r);
    put_logs(&w.b, r);
    return close_write(&w, buf, len);
}

static void get_result_head(wire *w, lm_lane_result *r)
{
    if (lm_get_u32(&w->b) != RESULT_MAGIC || lm_get_u32(&w->b) != LM_LANE_WIRE_VERSION)
        get_check(w, 0, "message kind or version", 0);
    r->status = (lm_status)lm_get_u32(&w->b);
    get_check(w, (uint32_t)r->status < LM_E_COUNT_, "status", (uint32_t)r->status);
    uint32_t n_msg = get_count(w, 1, sizeof r->msg - 1, "message bytes");
    lm_get_bytes(&w->b, r->msg, n_msg);
    r->msg[n_msg] = 0;
    get_check(w, strlen(r->msg) == n_msg, "message text", 0);
}

/* An id of the lane's mesh: below the start's slots or among the few it may have created. */
static int lane_id(uint32_t v, uint32_t n_verts)
{
    return v < n_verts || v - n_verts < LM_LANE_MAX_NEW_VERTS;
}

static void get_ops(wire *w, uint32_t n_verts, lm_lane_result *r)
{
    r->n_ops = r->cap_ops = get_count(w, 32, UINT32_MAX, "operations");
    r->ops = get_array(w, r->n_ops, sizeof *r->ops);
    uint32_t x_at = 0;
    for (uint32_t i = 0; i < r->n_ops && w->b.status == LM_OK; i++) {
        lm_lane_op *op = &r->ops[i];
        memset(op, 0, sizeof *op);
        op->r.kind = (lm_move_kind)lm_get_u32(&w->b);
        op->r.level = (int32_t)lm_get_u32(&w->b);
        op->r.a = lm_get_u32(&w->b);
        op->r.b = lm_get_u32(&w->b);
        op->r.v = lm_get_u32(&w->b);
        op->r.dim = lm_get_u32(&w->b);
        op->r.delta = lm_get_i64(&w->b);
        op->x_at = x_at;
        get_check(w,
                  (uint32_t)op->r.kind < LM_MOVE_KINDS && op->r.level >= 0 &&
                      op->r.level < LM_LEVELS && op->r.a != op->r.b && lane_id(op->r.a, n_verts) &&
                      lane_id(op->r.b, n_verts) &&
                      (op->r.v == LM_NONE || lane_id(op->r.v, n_verts)) && op->r.dim <= MAX_DIM,
                  "operation", i);
        x_at += w->b.status ? 0 : op->r.dim;
        get_check(w, x_at <= w->len / 8, "operation's parameter count", i);
    }
    r->n_xs = r->cap_xs = get_count(w, 8, UINT32_MAX, "parameters");
    get_check(w, r->n_xs == x_at, "parameter count", r->n_xs);
    r->xs = get_array(w, r->n_xs, sizeof *r->xs);
    for (uint32_t i = 0; i < r->n_xs && w->b.status == LM_OK; i++) {
        r->xs[i] = lm_get_f64(&w->b);
        get_check(w, isfinite(r->xs[i]), "parameter", i);
    }
}

static void get_counters(wire *w, lm_lane_result *r)
{
    r->d_acc = lm_get_i64(&w->b);
    r->mesh_hash = lm_get_u64(&w->b);
    r->total = lm_get_i64(&w->b);
    r->evals = lm_get_u64(&w->b);
    for (int k = 0; k < LM_MOVE_KINDS; k++) {
        r->attempted[k] = lm_get_u64(&w->b);
        r->accepted[k] = lm_get_u64(&w->b);
    }
    r->searches = lm_get_u64(&w->b);
    r->searches_failed = lm_get_u64(&w->b);
    r->collapses_tried = lm_get_u64(&w->b);
    r->last_collapse = lm_get_i64(&w->b);
    r->last_time = lm_get_u64(&w->b);
}

static void get_logs(wire *w, uint32_t n_verts, lm_lane_result *r)
{
    lm_lane_log *log = &r->log;
    log->n_adds = log->cap_adds = get_count(w, 32, UINT32_MAX, "statistics adds");
    log->adds = get_array(w, log->n_adds, sizeof *log->adds);
    for (uint32_t i = 0; i < log->n_adds && w->b.status == LM_OK; i++) {
        lm_lane_stat_add *a = &log->adds[i];
        a->kind = lm_get_u32(&w->b);
        a->level = (int32_t)lm_get_u32(&w->b);
        a->x = lm_get_f64(&w->b);
        a->t = lm_get_f64(&w->b);
        a->now = lm_get_u64(&w->b);
        get_check(w,
                  a->kind <= LM_LANE_LOG_IMPROVE && a->level >= 0 && a->level < LM_LEVELS &&
                      isfinite(a->x) && isfinite(a->t),
                  "statistics add", i);
    }
    log->n_queue = log->cap_queue = get_count(w, 28, UINT32_MAX, "queue changes");
    log->queue = get_array(w, log->n_queue, sizeof *log->queue);
    for (uint32_t i = 0; i < log->n_queue && w->b.status == LM_OK; i++) {
        log->queue[i].e = get_entry(w, n_verts + LM_LANE_MAX_NEW_VERTS, i);
        log->queue[i].present = (int)lm_get_u32(&w->b);
        get_check(w, (uint32_t)log->queue[i].present <= 1, "queue change", i);
    }
    uint32_t n = get_count(w, 4, UINT32_MAX, "touched vertices");
    for (uint32_t i = 0; i < n && w->b.status == LM_OK; i++) {
        uint32_t v = lm_get_u32(&w->b);
        get_check(w, lane_id(v, n_verts) && !lm_idset_has(&r->touched, v), "touched vertex", i);
        if (w->b.status == LM_OK && lm_idset_add(&r->touched, v) != LM_OK)
            w->b.status = LM_E_NOMEM;
    }
}

lm_status lm_lane_result_decode(const uint8_t *buf, size_t len, uint32_t n_verts, lm_lane_result *r)
{
    lm_lane_result_free(r);
    wire w;
    lm_status st = open_read(&w, buf, len, "a lane result");
    if (st)
        return st;
    get_result_head(&w, r);
    if (w.b.status == LM_OK)
        get_ops(&w, n_verts, r);
    if (w.b.status == LM_OK)
        get_counters(&w, r);
    if (w.b.status == LM_OK)
        get_logs(&w, n_verts, r);
    st = close_read(&w);
    if (st)
        lm_lane_result_clear(r);
    return st;
}
