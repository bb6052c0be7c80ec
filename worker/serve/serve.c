/* worker/serve/serve.c — the worker's connection: a DEALER socket, or the socketpair a coordinator
 * that started the worker gave it (proto/stream.h); Hello until welcomed (again after a job ends or
 * the coordinator falls silent), heartbeats, signals, and the dispatch of every message. */
#include "worker/serve/serve.h"

#include <errno.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#include "common/log.h"
#include "proto/keys.h"
#include "worker/serve/serve_internal.h"

#define WK_HELLO_EVERY_S 1.0
/* A coordinator silent this long is presumed gone. Generous: a coordinator beats from its main
 * loop, which a long step (a checkpoint of a big mesh, a loaded machine) can hold up for
 * seconds, and dropping a live job costs a re-send of everything; a coordinator that really died
 * is replaced by one that sends Rejoin at once, whatever this says. */
#define WK_COORDINATOR_SILENCE_S 30.0
#define WK_UNHEARD_NOTE_S 10.0   /* unwelcomed this long: say so once */
#define WK_RECONNECT_MS 100      /* ZeroMQ's reconnection backoff: from this ... */
#define WK_RECONNECT_MAX_MS 2000 /* ... doubling up to this */

static volatile sig_atomic_t stop_signal;

static void on_signal(int sig)
{
    stop_signal = sig;
}

double wk_serve_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Until everything queued on the link is written (the coordinator always reads); LM_E_IO when
 * the link has closed. */
static lm_status link_drain(wk_server *s)
{
    lm_status st = LM_OK;
    while (st == LM_OK && lm_stream_pending(&s->link)) {
        struct pollfd pf = {.fd = s->link.fd, .events = POLLOUT};
        if (poll(&pf, 1, 1000) < 0 && errno != EINTR)
            st = lm_fail(LM_E_IO, "waiting to write to the coordinator: %s", strerror(errno));
        if (st == LM_OK)
            st = lm_stream_flush(&s->link);
    }
    return st;
}

static lm_status link_send(wk_server *s, const lm_msg *m)
{
    lm_status st = lm_stream_put_msg(&s->link, m);
    if (st == LM_OK)
        st = link_drain(s);
    s->spin_until = s->o.spin_s > 0 ? wk_serve_now() + s->o.spin_s : 0;
    if (st == LM_E_IO)
        s->link_closed = 1;
    return st;
}

lm_status wk_serve_send(wk_server *s, uint64_t req, Lumesh__Msg__BodyCase c, void *body)
{
    lm_msg m;
    lm_wire_msg_init(&m, req, s->seq, c, body);
    lm_status st = s->linked ? link_send(s, &m) : lm_wire_send(s->sock, NULL, 0, &m);
    lm_wire_arena_reset(&s->arena);
    return st;
}

/* Whether the link has something to read within timeout_ms (> 0 for its socket, or 0 with a
 * frame in its shared-memory lane): looked for without sleeping until spin_until (sched_yield lets
 * anything else runnable here go first), then slept on, the coordinator told so. */
static int link_wait(wk_server *s, int timeout_ms)
{
    struct pollfd pf = {.fd = s->link.fd, .events = POLLIN};
    int rc = 0;
    while (!lm_stream_ready(&s->link) && (rc = poll(&pf, 1, 0)) == 0 && timeout_ms != 0 &&
           wk_serve_now() < s->spin_until)
        sched_yield();
    if (rc != 0 || timeout_ms == 0 || lm_stream_ready(&s->link))
        return rc;
    rc = lm_stream_sleep(&s->link) ? 0 : poll(&pf, 1, timeout_ms);
    lm_stream_awake(&s->link);
    return rc;
}

/* A frame from the link within timeout_ms (as lm_wire_recv); at its end, link_closed. */
static lm_status link_recv(wk_server *s, int timeout_ms, lm_wire_frame *f)
{
    lm_status st = lm_stream_next(&s->link, f);
    if (st != LM_OK || f->data)
        return st;
    int rc = link_wait(s, timeout_ms);
    if (rc < 0)
        return errno == EINTR ? LM_OK : lm_fail(LM_E_IO, "waiting: %s", strerror(errno));
    if (rc == 0)
        return lm_stream_next(&s->link, f);  /* the lane's, if it was that */
    if (lm_stream_fill(&s->link) != LM_OK) { /* the frames before the end are still taken */
        lm_clear_error();
        s->link_closed = 1;
    }
    return lm_stream_next(&s->link, f);
}

static lm_status serve_recv(wk_server *s, int timeout_ms, lm_wire_frame *f)
{
    if (s->linked)
        return link_recv(s, timeout_ms, f);
    return lm_wire_recv(s->sock, 0, timeout_ms, f);
}

lm_status wk_serve_fail(wk_server *s, uint64_t req, lm_status code, const char *message)
{
    lm_warn("refused a request: %s", message);
    Lumesh__Failure f = LUMESH__FAILURE__INIT;
    f.code = (uint32_t)code;
    f.message = (char *)message;
    return wk_serve_send(s, req, LUMESH__MSG__BODY_FAILURE, &f);
}

static lm_status say_hello(wk_server *s)
{
    Lumesh__Hello h = LUMESH__HELLO__INIT;
    h.version = LM_WIRE_VERSION;
    h.host = s->host;
    h.pid = (uint32_t)getpid();
    h.device = (char *)s->o.device;
    h.renderer = s->renderer;
    h.renderer_id = s->renderer_id;
    h.join = s->join;
    s->last_hello = wk_serve_now();
    return wk_serve_send(s, 0, LUMESH__MSG__BODY_HELLO, &h);
}

lm_status wk_serve_secure(wk_server *s, void *sock)
{
    int ivl = WK_RECONNECT_MS, max = WK_RECONNECT_MAX_MS;
    if (zmq_setsockopt(sock, ZMQ_RECONNECT_IVL, &ivl, sizeof ivl) != 0 ||
        zmq_setsockopt(sock, ZMQ_RECONNECT_IVL_MAX, &max, sizeof max) != 0)
        return lm_fail(LM_E_INTERNAL, "setting reconnection: %s", zmq_strerror(zmq_errno()));
    return s->o.keys ? lm_keys_client(sock, s->o.keys) : LM_OK;
}

/* A link given by the coordinator that started us: its routing id is the link's. */
static lm_status open_link(wk_server *s)
{
    s->zctx = zmq_ctx_new(); /* for the heartbeat and health sockets */
    if (!s->zctx)
        return lm_fail(LM_E_INTERNAL, "creating a ZeroMQ context: %s", zmq_strerror(zmq_errno()));
    snprintf(s->id, sizeof s->id, "%s", s->o.link_id);
    s->linked = 1;
    lm_status st = lm_stream_open(&s->link, s->o.link_fd);
    if (s->o.link_shm > 0) {
        if (st == LM_OK)
            st = lm_stream_share(&s->link, s->o.link_shm, 1); /* closes it */
        else
            close(s->o.link_shm);
    }
    return st;
}

/* A stable routing id: host, pid and a random tag (a restarted worker is a new peer). */
static lm_status connect_socket(wk_server *s)
{
    if (s->o.link_id)
        return open_link(s);
    s->zctx = zmq_ctx_new();
    s->sock = s->zctx ? zmq_socket(s->zctx, ZMQ_DEALER) : NULL;
    if (!s->sock)
        return lm_fail(LM_E_INTERNAL, "creating a ZeroMQ socket: %s", zmq_strerror(zmq_errno()));
    snprintf(s->id, sizeof s->id, "%.200s:%d:%08x", s->host, (int)getpid(),
             (unsigned)(wk_serve_now() * 1e6));
    lm_status st = lm_wire_socket_setup(s->sock, 0);
    if (st == LM_OK)
        st = wk_serve_secure(s, s->sock);
    if (st == LM_OK && zmq_setsockopt(s->sock, ZMQ_ROUTING_ID, s->id, strlen(s->id)) != 0)
        st = lm_fail(LM_E_INTERNAL, "setting the worker's id: %s", zmq_strerror(zmq_errno()));
    if (st == LM_OK && zmq_connect(s->sock, s->o.endpoint) != 0)
        st = lm_fail(LM_E_INVALID, "cannot connect to '%s': %s", s->o.endpoint,
                     zmq_strerror(zmq_errno()));
    return st;
}

/* The worker no longer counts as welcomed (its job, if any, was ended): its next Hello is a new
 * join, said at once. */
static void drop_welcome(wk_server *s)
{
    s->welcomed = 0;
    s->join++;
    s->last_hello = 0;
}

static lm_status server_init(wk_server *s, const wk_serve_options *o)
{
    memset(s, 0, sizeof *s);
    s->link.fd = -1;
    s->o = *o;
    if (!s->o.device)
        s->o.device = "auto";
    if (!(s->o.silence_s > 0))
        s->o.silence_s = WK_COORDINATOR_SILENCE_S;
    lm_asset_set_init(&s->cache);
    lm_wire_arena_init(&s->arena);
#ifdef LUMESH_TEST_HOOKS
    s->fault = getenv("LUMESH_WORKER_FAULT");
#endif
    if (gethostname(s->host, sizeof s->host - 1) != 0)
        snprintf(s->host, sizeof s->host, "unknown");
    lm_status st = wk_probe_renderer(s->o.device, s->renderer_id, s->renderer);
    if (st == LM_OK)
        st = connect_socket(s);
    if (st == LM_OK)
        st = wk_beat_start(s, s->id);
    if (st == LM_OK && s->o.health)
        st = wk_health_open(s);
    return st;
}

static void server_free(wk_server *s)
{
    wk_beat_stop(s);
    if (s->health)
        zmq_close(s->health);
    wk_serve_end_job(s);
    lm_replica_free(&s->rep);
    lm_bvh_destroy(s->bvh);
    wk_serve_assets_free(s);
    for (uint32_t i = 0; i < s->cap_patches; i++)
        lm_patch_free(&s->patches[i]);
    free(s->patches);
    free(s->deltas);
    lm_wire_arena_free(&s->arena);
    if (s->linked)
        lm_stream_close(&s->link);
    if (s->sock)
        zmq_close(s->sock);
    if (s->zctx)
        zmq_ctx_term(s->zctx);
}

/* What a message asks; LM_E_INVALID ends the worker (refused), other failures were answered. */
static lm_status dispatch(wk_server *s, const lm_msg *m, int *job_ended)
{
    switch (m->body_case) {
    case LUMESH__MSG__BODY_WELCOME:
        if (s->welcomed || m->welcome->join != s->join)
            return LM_OK; /* the answer to a repeated Hello, or to an older join */
        s->welcomed = 1;
        s->worker_id = m->welcome->worker;
        s->unheard_noted = 0;
        lm_info("welcomed by %s as worker %u", s->o.endpoint, m->welcome->worker);
        return LM_OK;
    case LUMESH__MSG__BODY_REFUSE:
        return lm_fail(LM_E_INVALID, "refused by the coordinator: %s", m->refuse->reason);
    case LUMESH__MSG__BODY_REJOIN:
        /* Not welcomed yet: this join's Hello is on its way (the Rejoin answered a beat that
         * overtook it), and a new join would only make the coordinator drop the one it welcomes. */
        if (!s->welcomed)
            return LM_OK;
        lm_warn("the coordinator does not know this worker (%s): joining again", m->rejoin->reason);
        wk_serve_end_job(s);
        drop_welcome(s);
        return LM_OK;
    case LUMESH__MSG__BODY_HEARTBEAT:
        return LM_OK;
    case LUMESH__MSG__BODY_OFFER:
        return wk_serve_offer(s, m);
    case LUMESH__MSG__BODY_ASSET:
        return wk_serve_asset(s, m);
    case LUMESH__MSG__BODY_JOB:
        return wk_serve_job(s, m);
    case LUMESH__MSG__BODY_ASSIGN:
        return wk_serve_assign(s, m);
    case LUMESH__MSG__BODY_SET_MATERIALS:
    case LUMESH__MSG__BODY_SET_SURFACE:
    case LUMESH__MSG__BODY_SET_MESH:
    case LUMESH__MSG__BODY_COMMIT:
        return wk_serve_change(s, m);
    case LUMESH__MSG__BODY_EVALUATE:
    case LUMESH__MSG__BODY_ENERGY:
    case LUMESH__MSG__BODY_POTENTIALS:
    case LUMESH__MSG__BODY_READ_IMAGE:
        return wk_serve_request(s, m);
    case LUMESH__MSG__BODY_RUN_LANE:
        return wk_serve_lane(s, m);
    case LUMESH__MSG__BODY_END_JOB:
        wk_serve_end_job(s);
        drop_welcome(s); /* the next job may come from another coordinator */
        *job_ended = 1;
        return LM_OK;
    default:
        return wk_serve_fail(s, m->req, LM_E_INVALID, "a message a worker does not take");
    }
}

/* One frame: decode, dispatch. Malformed frames are answered and forgotten. */
static lm_status handle(wk_server *s, const lm_wire_frame *f, int *job_ended)
{
    lm_wire_in in;
    lm_status st = lm_wire_decode(f->data, f->size, &in);
    if (st != LM_OK) {
        lm_wire_in_free(&in);
        return wk_serve_fail(s, 0, st, lm_last_error());
    }
    wk_beat_busy(s, 1);
    st = dispatch(s, in.msg, job_ended);
    wk_beat_busy(s, 0);
    lm_wire_in_free(&in);
    return st;
}

/* Hello while not welcomed; silence means the coordinator is gone. */
static lm_status keep_alive(wk_server *s, double now)
{
    if (s->welcomed && now - s->last_heard > s->o.silence_s) {
        lm_warn("the coordinator at %s has been silent for %.0f s: waiting for one", s->o.endpoint,
                now - s->last_heard);
        wk_serve_end_job(s);
        drop_welcome(s);
    }
    if (!s->welcomed && now - s->last_heard > WK_UNHEARD_NOTE_S && !s->unheard_noted) {
        lm_warn("no coordinator has answered at %s for %.0f s (none there yet, or keys that do "
                "not match): still trying",
                s->o.endpoint, now - s->last_heard);
        s->unheard_noted = 1;
    }
    if (!s->welcomed && now - s->last_hello >= WK_HELLO_EVERY_S)
        return say_hello(s);
    return LM_OK;
}

static lm_status serve_loop(wk_server *s)
{
    lm_status st = say_hello(s);
    s->last_heard = wk_serve_now();
    while (st == LM_OK && !stop_signal && !s->link_closed) {
        lm_wire_frame f;
        if (s->health) {
            zmq_pollitem_t hp = {.socket = s->health, .events = ZMQ_POLLIN};
            if (zmq_poll(&hp, 1, 0) > 0)
                wk_health_answer(s);
        }
        st = serve_recv(s, s->health ? 100 : 250, &f);
        int ended = 0;
        if (st == LM_OK && f.data) {
            s->last_heard = wk_serve_now();
            st = handle(s, &f, &ended);
            /* The coordinator's silence counts from here: while a message is handled (loading
             * the original, rendering targets: minutes on a large asset and a loaded machine)
             * nothing is read, so that time says nothing of the coordinator. */
            s->last_heard = wk_serve_now();
        }
        lm_wire_frame_release(&f);
        if (st == LM_OK && ended && s->o.once)
            break;
        if (st == LM_OK)
            st = keep_alive(s, wk_serve_now());
        if (st == LM_E_IO) { /* a send to a coordinator that went: wait for the next */
            lm_clear_error();
            st = LM_OK;
        }
    }
    if (s->link_closed)
        lm_info("the coordinator that started this worker closed its connection: exiting");
    return st;
}

lm_status wk_serve(const wk_serve_options *opts)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    wk_server *s = malloc(sizeof *s);
    if (!s)
        return lm_fail(LM_E_NOMEM, "out of memory starting the worker");
    lm_status st = server_init(s, opts);
    if (st == LM_OK)
        st = serve_loop(s);
    server_free(s);
    free(s);
    return st;
}
