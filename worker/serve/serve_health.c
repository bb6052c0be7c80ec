/* worker/serve/serve_health.c — the worker's health endpoint (`lumesh-worker --health-socket
 * ADDR`): a REP socket that answers any request with one JSON object — state, the coordinator, the
 * job, its views, the renderer, the replica's sequence number — for container probes and humans
 * (`lumesh-worker --health ADDR`). Answered between requests of the coordinator: a worker busy on a
 * long request answers late, one that is stuck does not (the probe's timeout says so). */
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

#include "worker/serve/serve_internal.h"

lm_status wk_health_open(wk_server *s)
{
    s->health = zmq_socket(s->zctx, ZMQ_REP);
    int zero = 0;
    if (!s->health || zmq_setsockopt(s->health, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        zmq_bind(s->health, s->o.health) != 0)
        return lm_fail(LM_E_INVALID, "cannot answer health queries on '%s': %s", s->o.health,
                       zmq_strerror(zmq_errno()));
    return LM_OK;
}

static const char *state_of(const wk_server *s)
{
    if (!s->welcomed)
        return "waiting"; /* for a coordinator */
    if (!s->v)
        return "idle"; /* welcomed, no views */
    return s->stale ? "stale" : "serving";
}

void wk_health_answer(wk_server *s)
{
    char req[64], out[1024];
    if (zmq_recv(s->health, req, sizeof req, ZMQ_DONTWAIT) < 0)
        return;
    int n =
        snprintf(out, sizeof out,
                 "{\"state\": \"%s\", \"welcomed\": %s, \"coordinator\": \"%s\", \"job\": %llu, "
                 "\"views\": [%u, %u], \"views_stride\": %u, \"seq\": %llu, \"device\": \"%s\", "
                 "\"renderer\": \"%s\", "
                 "\"renderer_id\": \"%s\", \"assets\": %u, \"pid\": %d}",
                 state_of(s), s->welcomed ? "true" : "false", s->o.endpoint,
                 (unsigned long long)s->job, s->v ? s->deal.first : 0, s->v ? s->deal.count : 0,
                 s->v ? s->deal.stride : 1, (unsigned long long)s->seq, s->o.device, s->renderer,
                 s->renderer_id, s->cache.n, (int)getpid());
    zmq_send(s->health, out, n > 0 && (size_t)n < sizeof out ? (size_t)n : 0, 0);
}

lm_status wk_serve_health_query(const char *endpoint, double timeout_s, char *buf, size_t cap,
                                int *ready)
{
    void *ctx = zmq_ctx_new(), *sock = ctx ? zmq_socket(ctx, ZMQ_REQ) : NULL;
    int zero = 0;
    lm_status st = LM_OK;
    if (!sock || zmq_setsockopt(sock, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        zmq_connect(sock, endpoint) != 0)
        st = lm_fail(LM_E_INVALID, "cannot reach '%s': %s", endpoint, zmq_strerror(zmq_errno()));
    if (st == LM_OK && zmq_send(sock, "health", 6, 0) < 0)
        st = lm_fail(LM_E_IO, "asking '%s': %s", endpoint, zmq_strerror(zmq_errno()));
    zmq_pollitem_t p = {.socket = sock, .events = ZMQ_POLLIN};
    if (st == LM_OK && zmq_poll(&p, 1, (long)(1000.0 * timeout_s)) <= 0)
        st = lm_fail(LM_E_IO, "no answer from '%s' within %.1f s", endpoint, timeout_s);
    int n = st == LM_OK ? zmq_recv(sock, buf, cap - 1, 0) : -1;
    if (st == LM_OK && n < 0)
        st =
            lm_fail(LM_E_IO, "reading the answer of '%s': %s", endpoint, zmq_strerror(zmq_errno()));
    if (st == LM_OK) {
        buf[(size_t)n < cap - 1 ? (size_t)n : cap - 1] = 0;
        *ready = strstr(buf, "\"welcomed\": true") != NULL;
    }
    if (sock)
        zmq_close(sock);
    if (ctx)
        zmq_ctx_term(ctx);
    return st;
}
