/* coordinator/pool/pool_peers.c — the peers of the pool: the handshake (protocol version, renderer
 * identity, blocklist), heartbeats (each worker's own and its beat thread's, "<id>#hb"), losses
 * (a local process exited, silence, a request unanswered too long, a malformed message, a send to
 * a peer that is gone), replacements of lost local workers, Rejoin for peers the pool does not
 * know (a restarted coordinator, a worker presumed dead that comes back), and status queries. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/log.h"
#include "coordinator/pool/pool_internal.h"

void co_pool_lose(co_pool *p, co_worker *w, const char *why)
{
    if (w->lost)
        return;
    w->lost = 1;
    co_pool_note(p, "worker %u (%s, pid %u) lost: %s", w->id, w->host, w->pid, why);
}

/* The newest worker with this routing id (a worker that rejoins keeps its id: the entries of its
 * earlier lives are lost ones). */
static co_worker *find_id(co_pool *p, const uint8_t *id, size_t len)
{
    for (uint32_t i = p->n; i-- > 0;)
        if (p->w[i]->rid_len == len && !memcmp(p->w[i]->rid, id, len))
            return p->w[i];
    return NULL;
}

/* The worker whose heartbeat thread this is ("<its id>#hb"), or NULL. */
static co_worker *beat_of(co_pool *p, const lm_wire_frame *f)
{
    if (f->id_len < 4 || memcmp(f->id + f->id_len - 3, "#hb", 3))
        return NULL;
    co_worker *w = find_id(p, f->id, f->id_len - 3);
    return w ? w : (co_worker *)p; /* a beat of a worker we do not know */
}

/* A reply to a peer that is not (or no longer) a worker of the pool; lost on the way is fine. */
static void reply_to(co_pool *p, const lm_wire_frame *f, Lumesh__Msg__BodyCase c, void *body)
{
    lm_msg m;
    lm_wire_msg_init(&m, 0, 0, c, body);
    if (co_pool_send_msg(p, f->id, f->id_len, &m) != LM_OK)
        lm_clear_error();
}

static void refuse(co_pool *p, const lm_wire_frame *f, const char *why)
{
    Lumesh__Refuse r = LUMESH__REFUSE__INIT;
    r.reason = (char *)why;
    reply_to(p, f, LUMESH__MSG__BODY_REFUSE, &r);
    co_pool_note(p, "refused a worker: %s", why);
}

static lm_status add_worker(co_pool *p, co_worker **out)
{
    if (p->n == p->cap && !LM_GROW32(&p->w, &p->cap, (size_t)p->n + 1, 8))
        return lm_fail(LM_E_NOMEM, "out of memory for workers");
    *out = p->w[p->n] = calloc(1, sizeof **out);
    if (!*out)
        return lm_fail(LM_E_NOMEM, "out of memory for a worker");
    p->w[p->n]->id = p->n + 1;
    p->n++;
    return LM_OK;
}

static void copy_str(char *dst, size_t cap, const char *src)
{
    snprintf(dst, cap, "%s", src ? src : "");
}

static int blocked(const co_pool *p, const char *host, uint32_t pid)
{
    char who[160];
    snprintf(who, sizeof who, "%.127s:%u", host, pid);
    for (uint32_t i = 0; i < p->n_blocked; i++)
        if (!strcmp(p->blocked[i], who))
            return 1;
    return 0;
}

/* Why a Hello is refused, or NULL. */
static const char *refusal(co_pool *p, const Lumesh__Hello *h, char *why, size_t cap)
{
    if (h->version != LM_WIRE_VERSION)
        snprintf(why, cap, "protocol version %u, the coordinator speaks %u", h->version,
                 LM_WIRE_VERSION);
    else if (p->renderer_id[0] && strcmp(p->renderer_id, h->renderer_id ? h->renderer_id : ""))
        snprintf(why, cap,
                 "renderer %.16s (%.200s) draws other pixels than this job's renderer %s: a job "
                 "never mixes renderers",
                 h->renderer_id, h->renderer, p->renderer_id);
    else if (blocked(p, h->host ? h->host : "", h->pid))
        snprintf(why, cap, "worker %.127s pid %u failed %d times in this job", h->host, h->pid,
                 CO_POOL_MAX_FAILURES);
    else
        return NULL;
    return why;
}

/* A Hello: welcome it (pinning the renderer on the first) or refuse it, saying why. A known
 * worker repeating the Hello of the join it was welcomed for (its retries queued while the
 * coordinator was busy or not yet listening) gets the same Welcome again; one with another join
 * number dropped its state: it is a new worker. */
static lm_status on_hello(co_pool *p, const lm_wire_frame *f, const Lumesh__Hello *h, co_worker *w)
{
    char why[512];
    if (refusal(p, h, why, sizeof why)) {
        refuse(p, f, why);
        return LM_OK;
    }
    if (w && !w->lost && h->join == w->join) {
        Lumesh__Welcome again = LUMESH__WELCOME__INIT;
        again.worker = w->id;
        again.join = w->join;
        return co_pool_send(p, w, 0, 0, LUMESH__MSG__BODY_WELCOME, &again);
    }
    if (w)
        co_pool_lose(p, w, "it said hello again (restarted or rejoining)");
    lm_status st = add_worker(p, &w);
    if (st != LM_OK)
        return st;
    w->rid_len = f->id_len;
    memcpy(w->rid, f->id, f->id_len);
    copy_str(w->host, sizeof w->host, h->host);
    copy_str(w->device, sizeof w->device, h->device);
    copy_str(w->renderer, sizeof w->renderer, h->renderer);
    copy_str(w->renderer_id, sizeof w->renderer_id, h->renderer_id);
    w->pid = h->pid;
    w->join = h->join;
    w->joined = w->last_heard = co_pool_now();
    w->loop_from = p->loop_t0 > 0 ? w->joined : 0.0; /* joined in the loop: counts from now */
    if (!p->renderer_id[0])
        copy_str(p->renderer_id, sizeof p->renderer_id, w->renderer_id);
    Lumesh__Welcome wel = LUMESH__WELCOME__INIT;
    wel.worker = w->id;
    wel.join = w->join;
    co_pool_note(p, "worker %u joined: %s, pid %u, %s", w->id, w->host, w->pid, w->renderer);
    return co_pool_send(p, w, 0, 0, LUMESH__MSG__BODY_WELCOME, &wel);
}

/* A reply for the armed request lands in the slot; other messages are forgotten. */
static void on_reply(co_worker *w, lm_wire_in *in)
{
    if (!w->want || in->msg->req != w->want || w->replied) {
        lm_wire_in_free(in);
        return;
    }
    w->reply = *in;
    /* the allocator points into the struct: re-seat it at its new home */
    w->reply.alloc_.allocator_data = &w->reply.budget_left_;
    w->replied = 1;
}

static void answer_status(co_pool *p, const lm_wire_frame *f);

/* A message from a peer the pool does not know (or no longer trusts): tell it to join again. */
static void stranger(co_pool *p, const lm_wire_frame *f, const lm_msg *m)
{
    if (m->body_case == LUMESH__MSG__BODY_STATUS) {
        answer_status(p, f);
        return;
    }
    Lumesh__Rejoin r = LUMESH__REJOIN__INIT;
    r.reason = "this coordinator does not know the worker (it restarted, or presumed the worker "
               "dead)";
    reply_to(p, f, LUMESH__MSG__BODY_REJOIN, &r);
}

static lm_status dispatch(co_pool *p, const lm_wire_frame *f, co_worker *w, lm_wire_in *in)
{
    if (in->msg->body_case == LUMESH__MSG__BODY_HELLO) {
        lm_status st = on_hello(p, f, in->msg->hello, w);
        lm_wire_in_free(in);
        return st;
    }
    if (!w || w->lost) {
        stranger(p, f, in->msg);
        lm_wire_in_free(in);
        return LM_OK;
    }
    w->last_heard = co_pool_now();
    if (in->msg->body_case == LUMESH__MSG__BODY_HEARTBEAT ||
        in->msg->body_case == LUMESH__MSG__BODY_STATUS) {
        if (in->msg->body_case == LUMESH__MSG__BODY_STATUS)
            answer_status(p, f);
        lm_wire_in_free(in);
        return LM_OK;
    }
    on_reply(w, in);
    return LM_OK;
}

/* The beat of a worker the pool does not know (a coordinator that restarted at its address, or
 * a worker presumed dead): its main socket is told to join again, at once. */
static void stranger_beat(co_pool *p, const lm_wire_frame *f)
{
    lm_wire_frame main = *f;
    main.id_len = f->id_len - 3;
    Lumesh__Rejoin r = LUMESH__REJOIN__INIT;
    r.reason = "this coordinator does not know the worker (it restarted, or presumed the worker "
               "dead)";
    reply_to(p, &main, LUMESH__MSG__BODY_REJOIN, &r);
}

lm_status co_pool_on_frame(co_pool *p, const lm_wire_frame *f)
{
    co_worker *hb = beat_of(p, f);
    if (hb) { /* a worker's beat thread: it lives (and may be busy) */
        if (hb == (co_worker *)p || hb->lost)
            stranger_beat(p, f);
        else
            hb->last_heard = co_pool_now();
        return LM_OK;
    }
    co_worker *w = find_id(p, f->id, f->id_len);
    lm_wire_in in;
    if (lm_wire_decode(f->data, f->size, &in) != LM_OK) {
        lm_warn("dropped a malformed message from %s: %s", w ? w->host : "an unknown peer",
                lm_last_error());
        lm_clear_error();
        if (w)
            co_pool_lose(p, w, "it sent a malformed message");
        lm_wire_in_free(&in);
        return LM_OK;
    }
    return dispatch(p, f, w, &in);
}

/* ---- losses ---------------------------------------------------------------------------------- */

uint32_t co_pool_respawns_left(co_pool *p, double now)
{
    uint32_t k = 0, limit = 3 * p->o.local_workers + 8;
    for (uint32_t i = 0; i < p->n_respawns; i++)
        if (now - p->respawns[i] < CO_POOL_RESPAWN_WINDOW_S)
            p->respawns[k++] = p->respawns[i];
    p->n_respawns = k;
    return k < limit ? limit - k : 0;
}

static void note_respawns(co_pool *p, uint32_t n, double now)
{
    if (!LM_GROW32(&p->respawns, &p->cap_respawns, (size_t)p->n_respawns + n, 8))
        return;
    for (uint32_t i = 0; i < n; i++)
        p->respawns[p->n_respawns++] = now;
}

/* Local workers whose process exited are lost, and replaced (at most 3N + 8 in a minute). */
static void notice_exits(co_pool *p, double now)
{
    pid_t gone[64];
    uint32_t n = co_spawn_reap(&p->spawned, gone, 64);
    for (uint32_t k = 0; k < n && k < 64; k++)
        for (uint32_t i = 0; i < p->n; i++)
            if (!p->w[i]->lost && p->w[i]->pid == (uint32_t)gone[k])
                co_pool_lose(p, p->w[i], "its process exited");
    uint32_t left = co_pool_respawns_left(p, now), again = n < left ? n : left;
    if (again && p->o.local_workers && co_pool_spawn(p, again) == LM_OK) {
        note_respawns(p, again, now);
        co_pool_note(p, "started %u worker%s in place of %s that exited", again,
                     again == 1 ? "" : "s", n == 1 ? "one" : "those");
    }
}

void co_pool_notice_losses(co_pool *p, double now)
{
    notice_exits(p, now);
    for (uint32_t i = 0; i < p->n; i++) {
        co_worker *w = p->w[i];
        if (w->lost)
            continue;
        int loading = w->loading && w->want && !w->replied; /* a set-up request in flight */
        if (now - w->last_heard > (loading ? CO_POOL_LOAD_SILENCE_S : CO_POOL_SILENCE_S))
            co_pool_lose(p, w,
                         loading ? "silent for too long while loading the job (presumed dead)"
                                 : "silent for too long (presumed dead)");
        else if (w->want && !w->replied &&
                 now - w->armed_at > (loading ? CO_POOL_LOAD_REQUEST_S : CO_POOL_REQUEST_S))
            co_pool_lose(p, w, "no answer to a request for too long (presumed stuck)");
    }
}

void co_pool_failed(co_pool *p, co_worker *w, const char *what)
{
    if (++w->failures < CO_POOL_MAX_FAILURES || w->lost)
        return;
    char(*b)[160] = realloc(p->blocked, (p->n_blocked + 1) * sizeof *b);
    if (b) {
        p->blocked = b;
        snprintf(b[p->n_blocked++], sizeof *b, "%.127s:%u", w->host, w->pid);
    }
    char why[256];
    snprintf(why, sizeof why, "failed %d times (last: %.150s): blocklisted for the job",
             CO_POOL_MAX_FAILURES, what);
    co_pool_lose(p, w, why);
}

void co_pool_fence(co_pool *p, co_worker *w, const char *what)
{
    if (w->failures < CO_POOL_MAX_FAILURES - 1)
        w->failures = CO_POOL_MAX_FAILURES - 1;
    co_pool_failed(p, w, what);
}

/* ---- status ---------------------------------------------------------------------------------- */

static void answer_status(co_pool *p, const lm_wire_frame *f)
{
    double now = co_pool_now();
    Lumesh__WorkerStatus *ws = calloc(p->n + 1, sizeof *ws);
    Lumesh__WorkerStatus **wp = calloc(p->n + 1, sizeof *wp);
    if (!ws || !wp) {
        free(ws);
        free(wp);
        return;
    }
    for (uint32_t i = 0; i < p->n; i++) {
        const co_worker *w = p->w[i];
        lumesh__worker_status__init(&ws[i]);
        ws[i].id = w->id, ws[i].host = (char *)w->host, ws[i].pid = w->pid;
        ws[i].device = (char *)w->device, ws[i].renderer_id = (char *)w->renderer_id;
        ws[i].first = w->first, ws[i].count = w->count, ws[i].stride = w->stride;
        ws[i].evals = w->evals;
        ws[i].busy_s = w->busy_s, ws[i].joined_s = now - w->joined;
        ws[i].last_heard_s = now - w->last_heard, ws[i].lost = w->lost != 0;
        ws[i].in_job = w->job != 0;
        wp[i] = &ws[i];
    }
    Lumesh__StatusResult r = LUMESH__STATUS_RESULT__INIT;
    r.endpoint = p->endpoint, r.renderer_id = p->renderer_id;
    r.n_workers = p->n, r.workers = wp, r.job_evals = p->job_evals;
    reply_to(p, f, LUMESH__MSG__BODY_STATUS_RESULT, &r);
    free(ws);
    free(wp);
}
