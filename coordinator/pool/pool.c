/* coordinator/pool/pool.c — the ROUTER socket (with CURVE when keys are given), sending to a
 * worker, reply slots, pumping and waiting. The handshake, heartbeats and losses (and replacing
 * local workers that die, within a budget) are in pool_peers.c; the local workers' socketpairs and
 * the frames' way in and out in pool_links.c; keys and the ZAP handler in pool_security.c. */
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
#include "coordinator/pool/pool_internal.h"

static volatile sig_atomic_t interrupted; /* the last of SIGINT, SIGTERM, SIGUSR1 seen */

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
    sigaction(SIGUSR1, &sa, NULL);
}

int co_pool_interrupted(void)
{
    return interrupted != 0;
}

int co_pool_interrupt_signal(void)
{
    return (int)interrupted;
}

double co_pool_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void co_pool_note(const co_pool *p, const char *fmt, ...)
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

static lm_status choose_endpoint(co_pool *p)
{
    if (p->o.listen) {
        snprintf(p->endpoint, sizeof p->endpoint, "%s", p->o.listen);
        if (co_pool_endpoint_is_public(p->endpoint) && !p->o.keys)
            return lm_fail(LM_E_INVALID,
                           "listening on '%s' (beyond this machine) needs --keys DIR: make keys "
                           "with `lumesh keygen -o DIR` (workers use the same folder)",
                           p->endpoint);
        return LM_OK;
    }
    snprintf(p->ipc_dir, sizeof p->ipc_dir, "%s/lumesh-XXXXXX",
             getenv("TMPDIR") && *getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    if (!mkdtemp(p->ipc_dir))
        return lm_fail(LM_E_IO, "cannot make a private folder for the workers' socket: %s",
                       strerror(errno));
    snprintf(p->endpoint, sizeof p->endpoint, "ipc://%s/pool", p->ipc_dir);
    return LM_OK;
}

static lm_status bind_socket(co_pool *p)
{
    p->zctx = zmq_ctx_new();
    p->sock = p->zctx ? zmq_socket(p->zctx, ZMQ_ROUTER) : NULL;
    if (!p->sock)
        return lm_fail(LM_E_INTERNAL, "creating a ZeroMQ socket: %s", zmq_strerror(zmq_errno()));
    lm_status st = lm_wire_socket_setup(p->sock, 1);
    if (st == LM_OK)
        st = choose_endpoint(p);
    if (st == LM_OK)
        st = co_pool_secure(p);
    if (st == LM_OK && zmq_bind(p->sock, p->endpoint) != 0)
        st = lm_fail(LM_E_INVALID, "cannot listen on '%s': %s", p->endpoint,
                     zmq_strerror(zmq_errno()));
    if (st != LM_OK)
        return st;
    /* a tcp port of 0 or "*": the one the system chose */
    size_t len = sizeof p->endpoint;
    zmq_getsockopt(p->sock, ZMQ_LAST_ENDPOINT, p->endpoint, &len);
    len = sizeof p->sock_fd;
    if (zmq_getsockopt(p->sock, ZMQ_FD, &p->sock_fd, &len) != 0)
        return lm_fail(LM_E_INTERNAL, "the socket's descriptor: %s", zmq_strerror(zmq_errno()));
    p->sock_unsure = 1;
    return LM_OK;
}

lm_status co_pool_create(const co_pool_options *o, co_pool **out)
{
    *out = NULL;
    co_pool *p = calloc(1, sizeof *p);
    if (!p)
        return lm_fail(LM_E_NOMEM, "out of memory creating the worker pool");
    p->o = *o;
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    int fit = cpus > 0 && o->local_workers <= (uint32_t)cpus;
    p->cores_full = cpus > 0 && o->local_workers >= (uint32_t)cpus;
    if (p->o.spin_us == 0)
        p->o.spin_us = fit ? (int)CO_POOL_SPIN_US : -1;
    if (p->o.await_spin_us == 0)
        p->o.await_spin_us = fit ? (int)CO_POOL_AWAIT_SPIN_US : -1;
    if (o->renderer_id)
        snprintf(p->renderer_id, sizeof p->renderer_id, "%s", o->renderer_id);
    lm_status st = bind_socket(p);
    if (st == LM_OK && o->local_workers)
        st = co_pool_spawn(p, o->local_workers);
    if (st != LM_OK) {
        co_pool_destroy(p);
        return st;
    }
    *out = p;
    return LM_OK;
}

int co_pool_cores_full(const co_pool *p)
{
    return p->cores_full;
}

/* EndJob to every worker. The socket lingers for up to CO_POOL_END_LINGER_MS on close so that
 * the messages go out: with no linger (the sockets' setting) a close could drop them before a
 * slow connection took them, and a --once worker would wait for its job's end forever. */
static void end_jobs(co_pool *p)
{
    Lumesh__EndJob e = LUMESH__END_JOB__INIT;
    for (uint32_t i = 0; i < p->n; i++)
        if (!p->w[i]->lost)
            co_pool_send(p, p->w[i], 0, 0, LUMESH__MSG__BODY_END_JOB, &e);
    int linger = CO_POOL_END_LINGER_MS;
    zmq_setsockopt(p->sock, ZMQ_LINGER, &linger, sizeof linger); /* on failure: as before */
    co_pool_links_flush(p, CO_POOL_END_LINGER_MS);
}

void co_pool_destroy(co_pool *p)
{
    if (!p)
        return;
    if (p->sock)
        end_jobs(p);
    co_pool_links_close(p); /* a --once worker that missed its EndJob ends with its link */
    co_spawn_stop_all(&p->spawned);
    for (uint32_t i = 0; i < p->n; i++) {
        co_pool_disarm(p->w[i]);
        free(p->w[i]);
    }
    free(p->w);
    free(p->blocked);
    free(p->respawns);
    if (p->sock)
        zmq_close(p->sock);
    co_pool_security_free(p);
    if (p->zctx)
        zmq_ctx_term(p->zctx);
    co_pool_security_join(p);
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

void co_pool_set_job_evals(co_pool *p, uint64_t evals)
{
    p->job_evals = evals;
}

void co_pool_mark_loop(co_pool *p)
{
    p->loop_t0 = co_pool_now();
    for (uint32_t i = 0; i < p->n; i++) {
        p->w[i]->loop_busy0 = p->w[i]->busy_s;
        p->w[i]->loop_from = p->loop_t0;
    }
}

void co_pool_mark_loop_end(co_pool *p)
{
    p->loop_t1 = co_pool_now();
}

double co_pool_loop_busy(const co_pool *p, const co_worker *w, double now)
{
    double end = p->loop_t1 > 0 && p->loop_t1 < now ? p->loop_t1 : now;
    end = w->lost && w->last_heard < end ? w->last_heard : end;
    if (!(w->loop_from > 0) || end - w->loop_from < 1e-3)
        return 0.0;
    return (w->busy_s - w->loop_busy0) / (end - w->loop_from);
}

/* ---- sending --------------------------------------------------------------------------------- */

lm_status co_pool_send(co_pool *p, co_worker *w, uint64_t req, uint64_t seq,
                       Lumesh__Msg__BodyCase body_case, void *body)
{
    if (w->lost)
        return LM_OK;
    lm_msg m;
    lm_wire_msg_init(&m, req, seq, body_case, body);
    lm_status st = co_pool_send_msg(p, w->rid, w->rid_len, &m);
    if (st == LM_E_IO) {
        co_pool_lose(p, w, lm_last_error());
        lm_clear_error();
        return LM_OK;
    }
    return st;
}

lm_status co_pool_send_packed(co_pool *p, co_worker *w, const uint8_t *data, size_t size)
{
    if (w->lost)
        return LM_OK;
    lm_status st = co_pool_send_frame(p, w->rid, w->rid_len, data, size);
    if (st == LM_E_IO) {
        lm_clear_error();
        co_pool_lose(p, w, "it disconnected");
        return LM_OK;
    }
    return st;
}

uint64_t co_pool_next_req(co_pool *p)
{
    return ++p->next_req;
}

void co_pool_arm_req(co_worker *w, uint64_t req)
{
    co_pool_disarm(w);
    w->want = req;
    w->armed_at = co_pool_now();
}

uint64_t co_pool_arm(co_pool *p, co_worker *w)
{
    co_pool_arm_req(w, co_pool_next_req(p));
    return w->want;
}

void co_pool_arm_load(co_worker *w, uint64_t req)
{
    co_pool_arm_req(w, req);
    w->loading = 1;
}

void co_pool_disarm(co_worker *w)
{
    if (w->replied)
        lm_wire_in_free(&w->reply);
    w->replied = 0;
    w->want = 0;
    w->loading = 0;
}

/* ---- pumping and waiting -----------------------------------------------------------------------
 */

static lm_status beat(co_pool *p, double now)
{
    if (now - p->last_beat < CO_POOL_BEAT_S)
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
        st = co_pool_recv(p, wait, &f);
        if (st == LM_OK && f.data)
            st = co_pool_on_frame(p, &f);
        int got = f.data != NULL;
        lm_wire_frame_release(&f);
        if (st != LM_OK || !got)
            break;
        wait = 0; /* take in everything that is there, then return */
    }
    double now = co_pool_now();
    if (now - p->last_check < CO_POOL_CHECK_S)
        return st;
    p->last_check = now;
    co_pool_watch_handshakes(p);
    co_pool_notice_losses(p, now);
    return st == LM_OK ? beat(p, now) : st;
}

lm_status co_pool_wait(co_pool *p, uint32_t n, double timeout_s)
{
    double t0 = co_pool_now(), last_note = t0 - CO_POOL_WAIT_NOTE_S; /* say so at once */
    while (co_pool_alive(p) < n) {
        if (co_pool_interrupted())
            return lm_fail(LM_E_INVALID, "interrupted while waiting for workers");
        double now = co_pool_now();
        if (timeout_s > 0 && now - t0 > timeout_s)
            return lm_fail(LM_E_IO, "%u of %u workers came within %.0f s (at %s)", co_pool_alive(p),
                           n, timeout_s, p->endpoint);
        if (p->o.local_workers && !p->o.listen && !co_pool_respawns_left(p, now) && !p->spawned.n)
            return lm_fail(LM_E_IO, "every local worker has died, and as many replacements as "
                                    "allowed (see the lines above)");
        if (now - last_note >= CO_POOL_WAIT_NOTE_S) {
            co_pool_note(p, "waiting for workers at %s (%u of %u so far)", p->endpoint,
                         co_pool_alive(p), n);
            last_note = now;
        }
        lm_status st = co_pool_pump(p, 100);
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}
