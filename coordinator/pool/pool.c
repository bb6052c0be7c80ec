/* coordinator/pool/pool.c — the ROUTER socket, the handshake (version, renderer identity), reply
 * slots, heartbeats, losses, and waiting for workers. */
#include "coordinator/pool/pool.h"

#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#include "common/log.h"
#include "coordinator/pool/spawn.h"

#define BEAT_EVERY_S 1.0
#define WAIT_NOTE_EVERY_S 5.0

struct co_pool {
    co_pool_options o;
    void *zctx, *sock;
    char endpoint[512];
    char ipc_dir[256]; /* the private folder of an ipc endpoint ("" for tcp) */
    char renderer_id[WK_RENDERER_ID_CHARS + 1];
    co_worker **w;
    uint32_t n, cap;
    uint64_t next_req;
    double last_beat;
    co_spawned spawned;
};

static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    interrupted = sig;
}

void co_pool_catch_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

int co_pool_interrupted(void)
{
    return interrupted != 0;
}

double co_pool_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void note(const co_pool *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void note(const co_pool *p, const char *fmt, ...)
{
    if (p->o.quiet)
        return;
    va_list ap;
    va_start(ap, fmt);
    fputs("lumesh: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

/* ---- creation ------------------------------------------------------------------------------ */

static lm_status bind_socket(co_pool *p)
{
    p->zctx = zmq_ctx_new();
    p->sock = p->zctx ? zmq_socket(p->zctx, ZMQ_ROUTER) : NULL;
    if (!p->sock)
        return lm_fail(LM_E_INTERNAL, "creating a ZeroMQ socket: %s", zmq_strerror(zmq_errno()));
    lm_status st = lm_wire_socket_setup(p->sock, 1);
    if (st != LM_OK)
        return st;
    if (p->o.listen) {
        snprintf(p->endpoint, sizeof p->endpoint, "%s", p->o.listen);
    } else {
        snprintf(p->ipc_dir, sizeof p->ipc_dir, "%s/lumesh-XXXXXX",
                 getenv("TMPDIR") && *getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
        if (!mkdtemp(p->ipc_dir))
            return lm_fail(LM_E_IO, "cannot make a private folder for the workers' socket: %s",
                           strerror(errno));
        snprintf(p->endpoint, sizeof p->endpoint, "ipc://%s/pool", p->ipc_dir);
    }
    if (zmq_bind(p->sock, p->endpoint) != 0)
        return lm_fail(LM_E_INVALID, "cannot listen on '%s': %s", p->endpoint,
                       zmq_strerror(zmq_errno()));
    /* a tcp port of 0 or "*": the one the system chose */
    size_t len = sizeof p->endpoint;
    zmq_getsockopt(p->sock, ZMQ_LAST_ENDPOINT, p->endpoint, &len);
    return LM_OK;
}

lm_status co_pool_create(const co_pool_options *o, co_pool **out)
{
    *out = NULL;
    co_pool *p = calloc(1, sizeof *p);
    if (!p)
        return lm_fail(LM_E_NOMEM, "out of memory creating the worker pool");
    p->o = *o;
    if (o->renderer_id)
        snprintf(p->renderer_id, sizeof p->renderer_id, "%s", o->renderer_id);
    lm_status st = bind_socket(p);
    char buf[4096];
    if (st == LM_OK && o->local_workers)
        st = co_spawn_workers(&p->spawned, co_spawn_find_worker(o->worker_path, buf), p->endpoint,
                              o->device, o->local_workers);
    if (st != LM_OK) {
        co_pool_destroy(p);
        return st;
    }
    *out = p;
    return LM_OK;
}

static void end_jobs(co_pool *p)
{
    Lumesh__EndJob e = LUMESH__END_JOB__INIT;
    for (uint32_t i = 0; i < p->n; i++)
        if (!p->w[i]->lost)
            co_pool_send(p, p->w[i], 0, 0, LUMESH__MSG__BODY_END_JOB, &e);
}

void co_pool_destroy(co_pool *p)
{
    if (!p)
        return;
    if (p->sock)
        end_jobs(p);
    co_spawn_stop_all(&p->spawned);
    for (uint32_t i = 0; i < p->n; i++) {
        co_pool_disarm(p->w[i]);
        free(p->w[i]);
    }
    free(p->w);
    if (p->sock)
        zmq_close(p->sock);
    if (p->zctx)
        zmq_ctx_term(p->zctx);
    if (p->ipc_dir[0]) {
        char sock[300];
        snprintf(sock, sizeof sock, "%s/pool", p->ipc_dir);
        unlink(sock);
        rmdir(p->ipc_dir);
    }
    free(p);
}

const char *co_pool_endpoint(const co_pool *p)
{
    return p->endpoint;
}

const char *co_pool_renderer_id(const co_pool *p)
{
    return p->renderer_id;
}

uint32_t co_pool_size(const co_pool *p)
{
    return p->n;
}

co_worker *co_pool_worker(co_pool *p, uint32_t i)
{
    return i < p->n ? p->w[i] : NULL;
}

uint32_t co_pool_alive(const co_pool *p)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < p->n; i++)
        k += !p->w[i]->lost;
    return k;
}

/* ---- sending --------------------------------------------------------------------------------- */

static void lose(co_pool *p, co_worker *w, const char *why)
{
    if (w->lost)
        return;
    w->lost = 1;
    note(p, "worker %u (%s, pid %u) lost: %s", w->id, w->host, w->pid, why);
}

lm_status co_pool_send(co_pool *p, co_worker *w, uint64_t req, uint64_t seq,
                       Lumesh__Msg__BodyCase body_case, void *body)
{
    if (w->lost)
        return LM_OK;
    lm_msg m;
    lm_wire_msg_init(&m, req, seq, body_case, body);
    lm_status st = lm_wire_send(p->sock, w->rid, w->rid_len, &m);
    if (st == LM_E_IO) {
        lose(p, w, lm_last_error());
        lm_clear_error();
        return LM_OK;
    }
    return st;
}

lm_status co_pool_send_packed(co_pool *p, co_worker *w, const uint8_t *data, size_t size)
{
    if (w->lost)
        return LM_OK;
    if (zmq_send(p->sock, w->rid, w->rid_len, ZMQ_SNDMORE) < 0 ||
        zmq_send(p->sock, data, size, 0) < 0) {
        if (errno == EHOSTUNREACH) {
            lose(p, w, "it disconnected");
            return LM_OK;
        }
        return lm_fail(LM_E_IO, "sending to worker %u: %s", w->id, zmq_strerror(errno));
    }
    return LM_OK;
}

uint64_t co_pool_next_req(co_pool *p)
{
    return ++p->next_req;
}

void co_pool_arm_req(co_worker *w, uint64_t req)
{
    co_pool_disarm(w);
    w->want = req;
}

uint64_t co_pool_arm(co_pool *p, co_worker *w)
{
    co_pool_arm_req(w, co_pool_next_req(p));
    return w->want;
}

void co_pool_disarm(co_worker *w)
{
    if (w->replied)
        lm_wire_in_free(&w->reply);
    w->replied = 0;
    w->want = 0;
}

/* ---- receiving ------------------------------------------------------------------------------- */

static co_worker *find(co_pool *p, const lm_wire_frame *f)
{
    for (uint32_t i = 0; i < p->n; i++)
        if (p->w[i]->rid_len == f->id_len && !memcmp(p->w[i]->rid, f->id, f->id_len))
            return p->w[i];
    return NULL;
}

static void refuse(co_pool *p, const lm_wire_frame *f, const char *why)
{
    co_worker tmp = {.rid_len = f->id_len};
    memcpy(tmp.rid, f->id, f->id_len);
    Lumesh__Refuse r = LUMESH__REFUSE__INIT;
    r.reason = (char *)why;
    co_pool_send(p, &tmp, 0, 0, LUMESH__MSG__BODY_REFUSE, &r);
    note(p, "refused a worker: %s", why);
}

static lm_status add_worker(co_pool *p, co_worker **out)
{
    if (p->n == p->cap) {
        uint32_t cap = p->cap ? p->cap * 2 : 8;
        co_worker **w = realloc(p->w, cap * sizeof *w);
        if (!w)
            return lm_fail(LM_E_NOMEM, "out of memory for workers");
        p->w = w;
        p->cap = cap;
    }
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

/* A Hello: welcome it (pinning the renderer on the first) or refuse it, saying why. A known
 * worker that says Hello again lost its state: it is a new worker. */
static lm_status on_hello(co_pool *p, const lm_wire_frame *f, const Lumesh__Hello *h, co_worker *w)
{
    char why[400];
    if (h->version != LM_WIRE_VERSION) {
        snprintf(why, sizeof why, "protocol version %u, the coordinator speaks %u", h->version,
                 LM_WIRE_VERSION);
        refuse(p, f, why);
        return LM_OK;
    }
    if (p->renderer_id[0] && strcmp(p->renderer_id, h->renderer_id ? h->renderer_id : "")) {
        snprintf(why, sizeof why,
                 "renderer %s (%s) draws other pixels than this job's renderer %s: a job never "
                 "mixes renderers",
                 h->renderer_id, h->renderer, p->renderer_id);
        refuse(p, f, why);
        return LM_OK;
    }
    if (w)
        lose(p, w, "it said hello again (restarted)");
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
    w->joined = w->last_heard = co_pool_now();
    if (!p->renderer_id[0])
        copy_str(p->renderer_id, sizeof p->renderer_id, w->renderer_id);
    Lumesh__Welcome wel = LUMESH__WELCOME__INIT;
    wel.worker = w->id;
    note(p, "worker %u joined: %s, pid %u, %s", w->id, w->host, w->pid, w->renderer);
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

static lm_status on_frame(co_pool *p, const lm_wire_frame *f)
{
    co_worker *w = find(p, f);
    lm_wire_in in;
    if (lm_wire_decode(f->data, f->size, &in) != LM_OK) {
        lm_warn("dropped a malformed message from %s: %s", w ? w->host : "an unknown peer",
                lm_last_error());
        lm_clear_error();
        if (w)
            lose(p, w, "it sent a malformed message");
        return LM_OK;
    }
    lm_status st = LM_OK;
    if (in.msg->body_case == LUMESH__MSG__BODY_HELLO) {
        st = on_hello(p, f, in.msg->hello, w);
        lm_wire_in_free(&in);
    } else if (!w || w->lost) {
        lm_wire_in_free(&in); /* not (or no longer) ours: it will say hello */
    } else {
        w->last_heard = co_pool_now();
        if (in.msg->body_case == LUMESH__MSG__BODY_HEARTBEAT)
            lm_wire_in_free(&in);
        else
            on_reply(w, &in);
    }
    return st;
}

/* Local workers whose process exited, and workers silent too long, are lost. */
static void notice_losses(co_pool *p, double now)
{
    pid_t gone[64];
    uint32_t n = co_spawn_reap(&p->spawned, gone, 64);
    for (uint32_t k = 0; k < n && k < 64; k++)
        for (uint32_t i = 0; i < p->n; i++)
            if (!p->w[i]->lost && p->w[i]->pid == (uint32_t)gone[k])
                lose(p, p->w[i], "its process exited");
    for (uint32_t i = 0; i < p->n; i++)
        if (!p->w[i]->lost && now - p->w[i]->last_heard > CO_POOL_SILENCE_S)
            lose(p, p->w[i], "silent for too long");
}

static lm_status beat(co_pool *p, double now)
{
    if (now - p->last_beat < BEAT_EVERY_S)
        return LM_OK;
    p->last_beat = now;
    Lumesh__Heartbeat h = LUMESH__HEARTBEAT__INIT;
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < p->n && st == LM_OK; i++)
        st = co_pool_send(p, p->w[i], 0, 0, LUMESH__MSG__BODY_HEARTBEAT, &h);
    return st;
}

lm_status co_pool_pump(co_pool *p, int timeout_ms)
{
    lm_status st = LM_OK;
    int wait = timeout_ms;
    for (;;) {
        lm_wire_frame f;
        st = lm_wire_recv(p->sock, 1, wait, &f);
        if (st == LM_OK && f.data)
            st = on_frame(p, &f);
        int got = f.data != NULL;
        lm_wire_frame_release(&f);
        if (st != LM_OK || !got)
            break;
        wait = 0; /* take in everything that is there, then return */
    }
    double now = co_pool_now();
    notice_losses(p, now);
    return st == LM_OK ? beat(p, now) : st;
}

lm_status co_pool_wait(co_pool *p, uint32_t n, double timeout_s)
{
    double t0 = co_pool_now(), last_note = t0;
    while (co_pool_alive(p) < n) {
        if (co_pool_interrupted())
            return lm_fail(LM_E_INVALID, "interrupted while waiting for workers");
        double now = co_pool_now();
        if (timeout_s > 0 && now - t0 > timeout_s)
            return lm_fail(LM_E_IO, "%u of %u workers came within %.0f s (at %s)", co_pool_alive(p),
                           n, timeout_s, p->endpoint);
        if (now - last_note >= WAIT_NOTE_EVERY_S) {
            note(p, "waiting for workers at %s (%u of %u so far)", p->endpoint, co_pool_alive(p),
                 n);
            last_note = now;
        }
        lm_status st = co_pool_pump(p, 100);
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}
