/* coordinator/pool/pool_links.c — the socketpairs to the worker processes this coordinator
 * starts (proto/stream.h says why not ZeroMQ there) with their shared-memory lanes (proto/ring.h),
 * and the one way the pool sends and receives: a peer whose routing id is a link's goes over its
 * link, every other one over the ROUTER socket. A link's worker still beats over the socket
 * ("<id>#hb"); a frame at the socket that claims a link's routing id is dropped. A link that closes
 * (the process ended) or breaks the framing loses its worker. */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>
#include <zmq.h>

#include "common/grow.h"
#include "common/log.h"
#include "coordinator/pool/pool_internal.h"

static co_link *link_of(co_pool *p, const uint8_t *id, size_t len)
{
    for (uint32_t i = 0; i < p->n_links; i++)
        if (p->links[i].rid_len == len && !memcmp(p->links[i].rid, id, len))
            return &p->links[i];
    return NULL;
}

static lm_status add_link(co_pool *p, co_link **out)
{
    if (p->n_links == p->cap_links) {
        size_t cap = lm_grow_cap(p->cap_links, (size_t)p->n_links + 1, 8, UINT32_MAX);
        if (!cap || !LM_RESIZE(&p->links, cap) || !LM_RESIZE(&p->poll_fds, cap + 1))
            return lm_fail(LM_E_NOMEM, "out of memory for workers' connections");
        p->cap_links = (uint32_t)cap;
    }
    *out = &p->links[p->n_links];
    memset(*out, 0, sizeof **out);
    (*out)->s.fd = -1;
    return LM_OK;
}

/* fd moved (close-on-exec) above the descriptors a worker is given its link on (3 and 4,
 * spawn.c), where it was one of them; -1 (errno) if it cannot be. */
static int above_child_fds(int fd)
{
    if (fd != 3 && fd != 4)
        return fd;
    int moved = fcntl(fd, F_DUPFD_CLOEXEC, 5);
    close(fd);
    return moved;
}

/* A socketpair, both ends close-on-exec, the child's end never descriptor 3 or 4; and its
 * shared-memory lane (proto/ring.h) in *shm, likewise, or -1 where the system gives none (the link
 * then carries everything over the socket, as before the lane: slower, never wrong). */
static lm_status make_pair(int fd[2], int *shm)
{
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fd) != 0)
        return lm_fail(LM_E_IO, "cannot make a connection for a worker: %s", strerror(errno));
    if ((fd[1] = above_child_fds(fd[1])) < 0) {
        int e = errno;
        close(fd[0]);
        return lm_fail(LM_E_IO, "cannot make a connection for a worker: %s", strerror(e));
    }
    lm_status st = lm_ring_create(shm);
    if (st == LM_OK && (*shm = above_child_fds(*shm)) < 0)
        st = lm_fail(LM_E_IO, "cannot move a worker's shared memory: %s", strerror(errno));
    if (st != LM_OK) {
        lm_warn("a local worker's messages all go over its socket: %s", lm_last_error());
        lm_clear_error();
        *shm = -1;
    }
    return LM_OK;
}

lm_status co_pool_spawn(co_pool *p, uint32_t n)
{
    char buf[4096];
    const char *program = co_spawn_find_worker(p->o.worker_path, buf);
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n && st == LM_OK; i++) {
        pid_t pid;
        if (p->o.socket_only) {
            co_spawn_args a = {p->endpoint, p->o.device, p->o.keys, -1, NULL, 0, -1};
            st = co_spawn_worker(&p->spawned, program, &a, &pid);
            continue;
        }
        co_link *l = NULL;
        int fd[2] = {-1, -1}, shm = -1;
        st = add_link(p, &l);
        if (st == LM_OK)
            st = make_pair(fd, &shm);
        if (st != LM_OK)
            break;
        l->rid_len =
            (size_t)snprintf(l->rid, sizeof l->rid, "local:%d:%u", (int)getpid(), ++p->links_made);
        co_spawn_args a = {p->endpoint, p->o.device, p->o.keys, fd[1], l->rid, p->o.spin_us, shm};
        st = co_spawn_worker(&p->spawned, program, &a, &pid);
        close(fd[1]);
        if (st == LM_OK)
            st = lm_stream_open(&l->s, fd[0]);
        else
            close(fd[0]);
        if (st == LM_OK && shm >= 0)
            st = lm_stream_share(&l->s, shm, 0); /* closes shm */
        else if (shm >= 0)
            close(shm);
        if (st == LM_OK)
            p->n_links++;
        else
            lm_stream_close(&l->s);
    }
    return st;
}

/* Close link l (taken out of the table) and lose its worker, saying why. */
static void drop_link(co_pool *p, co_link *l, const char *why)
{
    for (uint32_t i = p->n; i-- > 0;)
        if (p->w[i]->rid_len == l->rid_len && !memcmp(p->w[i]->rid, l->rid, l->rid_len)) {
            co_pool_lose(p, p->w[i], why);
            break;
        }
    lm_stream_close(&l->s);
    *l = p->links[--p->n_links];
}

void co_pool_links_close(co_pool *p)
{
    for (uint32_t i = 0; i < p->n_links; i++)
        lm_stream_close(&p->links[i].s);
    free(p->links);
    free(p->poll_fds);
    p->links = NULL;
    p->poll_fds = NULL;
    p->n_links = p->cap_links = 0;
}

void co_pool_links_flush(co_pool *p, int timeout_ms)
{
    double until = co_pool_now() + 1e-3 * timeout_ms;
    for (uint32_t i = 0; i < p->n_links; i++) {
        lm_stream *s = &p->links[i].s;
        while (lm_stream_pending(s) && lm_stream_flush(s) == LM_OK && lm_stream_pending(s)) {
            int left = (int)(1e3 * (until - co_pool_now()));
            struct pollfd pf = {.fd = s->fd, .events = POLLOUT};
            if (left <= 0 || poll(&pf, 1, left) <= 0)
                break;
        }
        lm_clear_error();
    }
}

/* ---- sending --------------------------------------------------------------------------------- */

/* A put on link l that failed for good ends it: it is dropped where it is polled (its frames
 * before count), so the send itself succeeds. */
static lm_status link_put_result(co_link *l, lm_status st)
{
    if (st != LM_E_IO)
        return st;
    l->ended = 1;
    lm_clear_error();
    return LM_OK;
}

lm_status co_pool_send_frame(co_pool *p, const uint8_t *id, size_t id_len, const void *data,
                             size_t size)
{
    co_link *l = link_of(p, id, id_len);
    if (l)
        return l->ended ? LM_OK : link_put_result(l, lm_stream_put(&l->s, data, size));
    p->sock_unsure = 1;
    if (zmq_send(p->sock, id, id_len, ZMQ_SNDMORE | ZMQ_DONTWAIT) < 0 ||
        zmq_send(p->sock, data, size, ZMQ_DONTWAIT) < 0) {
        int e = errno;
        return lm_fail(e == EHOSTUNREACH || e == EAGAIN ? LM_E_IO : LM_E_INTERNAL,
                       "sending to a worker: %s", zmq_strerror(e));
    }
    return LM_OK;
}

lm_status co_pool_send_msg(co_pool *p, const uint8_t *id, size_t id_len, const lm_msg *m)
{
    co_link *l = link_of(p, id, id_len);
    if (!l) {
        p->sock_unsure = 1;
        return lm_wire_send(p->sock, id, id_len, m);
    }
    return l->ended ? LM_OK : link_put_result(l, lm_stream_put_msg(&l->s, m));
}

/* ---- receiving ------------------------------------------------------------------------------- */

/* A whole frame some link holds, under its routing id; links that ended with nothing more to
 * give, or broke the framing, are dropped. */
static lm_status link_frame(co_pool *p, lm_wire_frame *f)
{
    for (uint32_t i = 0; i < p->n_links;) {
        co_link *l = &p->links[i];
        lm_status st = lm_stream_next(&l->s, f);
        if (st != LM_OK) {
            char why[300];
            snprintf(why, sizeof why, "its connection broke the framing (%.200s)", lm_last_error());
            lm_clear_error();
            drop_link(p, l, why);
            continue;
        }
        if (f->data) {
            memcpy(f->id, l->rid, l->rid_len);
            f->id_len = l->rid_len;
            return LM_OK;
        }
        if (l->ended) {
            drop_link(p, l, "its connection closed (the process ended)");
            continue;
        }
        i++;
    }
    return LM_OK;
}

/* Read and write what the links' poll results allow. */
static void serve_links(co_pool *p, const struct pollfd *fds)
{
    for (uint32_t i = 0; i < p->n_links; i++) {
        co_link *l = &p->links[i];
        short ev = fds[i].revents;
        if ((ev & POLLOUT) && lm_stream_flush(&l->s) != LM_OK)
            l->ended = 1;
        if ((ev & (POLLIN | POLLHUP | POLLERR)) && !l->ended && lm_stream_fill(&l->s) != LM_OK)
            l->ended = 1; /* frames read before the end are still taken */
        lm_clear_error();
    }
}

/* Whether the socket holds a message now (ZMQ_EVENTS, which also takes in ZeroMQ's pending
 * commands); "no" makes its descriptor safe to sleep on again. */
static int sock_readable(co_pool *p)
{
    int ev = 0;
    size_t len = sizeof ev;
    if (zmq_getsockopt(p->sock, ZMQ_EVENTS, &ev, &len) != 0)
        ev = 0; /* a socket that cannot answer has nothing to give */
    p->sock_unsure = (ev & ZMQ_POLLIN) != 0;
    return p->sock_unsure;
}

/* Whether a link has a frame to give without reading its socket (its shared-memory lane). */
static int links_ready(co_pool *p)
{
    for (uint32_t i = 0; i < p->n_links; i++)
        if (lm_stream_ready(&p->links[i].s))
            return 1;
    return 0;
}

/* poll(2) over fds with the links' lanes looked at too: first without sleeping for up to the
 * pool's await spin, yielding the processor to anything else that wants it, where local workers'
 * answers are awaited; then asleep, the links' writers told so (proto/stream.h). Returns as poll,
 * 0 too when only a lane has something. */
static int poll_awake(co_pool *p, struct pollfd *fds, nfds_t n, int timeout_ms)
{
    if (timeout_ms == 0)
        return poll(fds, n, 0);
    int rc = 0;
    if (p->o.await_spin_us > 0 && p->n_links) {
        double until = co_pool_now() + 1e-6 * p->o.await_spin_us;
        while (!links_ready(p) && (rc = poll(fds, n, 0)) == 0 && co_pool_now() < until)
            sched_yield();
    }
    if (rc != 0 || links_ready(p))
        return rc;
    int woke = 0;
    for (uint32_t i = 0; i < p->n_links; i++)
        woke |= lm_stream_sleep(&p->links[i].s);
    rc = woke ? 0 : poll(fds, n, timeout_ms);
    for (uint32_t i = 0; i < p->n_links; i++)
        lm_stream_awake(&p->links[i].s);
    return rc;
}

/* One poll(2) over the links and the socket's descriptor: zmq_poll would ask the socket for its
 * events (and getpid) on every call, twice when it sleeps, and a round trip over a link makes
 * several waits. Returns whether the socket has a message to take, or -1 (errno) on failure. */
static int wait_all(co_pool *p, int timeout_ms)
{
    int sock_ready = p->sock_unsure && sock_readable(p);
    struct pollfd one, *fds = p->poll_fds ? p->poll_fds : &one; /* links + the socket */
    for (uint32_t i = 0; i < p->n_links; i++) {
        short out = lm_stream_pending(&p->links[i].s) ? POLLOUT : 0;
        fds[i] = (struct pollfd){.fd = p->links[i].s.fd, .events = (short)(POLLIN | out)};
    }
    fds[p->n_links] = (struct pollfd){.fd = p->sock_fd, .events = POLLIN};
    int rc = poll_awake(p, fds, p->n_links + 1, sock_ready || p->sock_unsure ? 0 : timeout_ms);
    if (rc < 0)
        return -1;
    if (rc > 0)
        serve_links(p, fds);
    if (!sock_ready && (fds[p->n_links].revents & POLLIN))
        sock_ready = sock_readable(p);
    return sock_ready;
}

lm_status co_pool_recv(co_pool *p, int timeout_ms, lm_wire_frame *f)
{
    memset(f, 0, sizeof *f);
    lm_status st = link_frame(p, f);
    if (st != LM_OK || f->data)
        return st;
    int sock_ready = wait_all(p, timeout_ms);
    if (sock_ready < 0)
        return errno == EINTR ? LM_OK : lm_fail(LM_E_IO, "waiting: %s", strerror(errno));
    st = link_frame(p, f);
    if (st != LM_OK || f->data || !sock_ready)
        return st;
    p->sock_unsure = 1;
    st = lm_wire_recv(p->sock, 1, 0, f);
    if (st == LM_OK && f->data && link_of(p, f->id, f->id_len)) {
        lm_warn("dropped a message at %s that claimed a local worker's id", p->endpoint);
        lm_wire_frame_release(f);
    }
    return st;
}
