/* coordinator/pool/pool_security.c — who may be a worker: with keys, the ROUTER is a CURVE server
 * and a ZAP handler (a thread answering ZeroMQ's authentication requests on
 * inproc://zeromq.zap.01) admits only the public keys of workers.allow, logging every refusal;
 * the socket's event monitor logs the connections whose handshake failed (plaintext peers, wrong
 * keys). Without keys only this machine may connect (loopback tcp, or the private ipc folder). */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zmq.h>

#include "common/log.h"
#include "coordinator/pool/pool_internal.h"

#define MONITOR_EVENTS                                                                             \
    (ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL | ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL |                  \
     ZMQ_EVENT_HANDSHAKE_FAILED_AUTH)

int co_pool_endpoint_is_public(const char *e)
{
    if (strncmp(e, "tcp://", 6))
        return 0; /* ipc, inproc: this machine */
    e += 6;
    return strncmp(e, "127.", 4) && strncmp(e, "localhost:", 10) && strncmp(e, "[::1]:", 6);
}

/* ---- the ZAP handler ------------------------------------------------------------------------- */

/* One request (RFC 27: version, id, domain, address, identity, mechanism, credentials...). */
static void zap_answer(co_zap *z)
{
    zmq_msg_t part[8];
    int n = 0, more = 1;
    while (more && n < 8) {
        zmq_msg_init(&part[n]);
        if (zmq_msg_recv(&part[n], z->sock, 0) < 0)
            return;
        more = zmq_msg_more(&part[n]);
        n++;
    }
    const char *status = "400", *text = "unknown key";
    if (n >= 7 && zmq_msg_size(&part[5]) == 5 && !memcmp(zmq_msg_data(&part[5]), "CURVE", 5) &&
        zmq_msg_size(&part[6]) == 32 && lm_allow_has(&z->allow, zmq_msg_data(&part[6])))
        status = "200", text = "OK";
    else if (!z->pool->o.quiet) {
        char addr[64] = "?";
        if (n >= 4)
            snprintf(addr, sizeof addr, "%.*s", (int)zmq_msg_size(&part[3]),
                     (const char *)zmq_msg_data(&part[3]));
        fprintf(stderr, "lumesh: refused a connection from %s: its key is not in workers.allow\n",
                addr);
    }
    const char *reply[6] = {"1.0", NULL, status, text, "", ""};
    for (int i = 0; i < 6; i++) {
        int flags = i < 5 ? ZMQ_SNDMORE : 0;
        if (i == 1)
            zmq_send(z->sock, zmq_msg_data(&part[1]), zmq_msg_size(&part[1]), flags);
        else
            zmq_send(z->sock, reply[i], strlen(reply[i]), flags);
    }
    for (int i = 0; i < n; i++)
        zmq_msg_close(&part[i]);
}

static void *zap_main(void *arg)
{
    co_zap *z = arg;
    for (;;) {
        zmq_pollitem_t it = {.socket = z->sock, .events = ZMQ_POLLIN};
        if (zmq_poll(&it, 1, -1) < 0) { /* the context is being terminated */
            zmq_close(z->sock);
            break;
        }
        zap_answer(z);
    }
    return NULL;
}

static lm_status start_zap(co_pool *p)
{
    co_zap *z = &p->zap;
    z->pool = p;
    lm_status st = lm_keys_load_allow(p->o.keys, &z->allow);
    if (st != LM_OK)
        return st;
    z->sock = zmq_socket(p->zctx, ZMQ_REP);
    int zero = 0;
    if (!z->sock || zmq_setsockopt(z->sock, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        zmq_bind(z->sock, "inproc://zeromq.zap.01") != 0)
        return lm_fail(LM_E_INTERNAL, "starting the authentication handler: %s",
                       zmq_strerror(zmq_errno()));
    if (pthread_create(&z->thread, NULL, zap_main, z) != 0)
        return lm_fail(LM_E_INTERNAL, "cannot start the authentication thread");
    z->started = 1;
    return LM_OK;
}

/* ---- handshake failures ---------------------------------------------------------------------- */

static lm_status start_monitor(co_pool *p)
{
    char ep[64];
    snprintf(ep, sizeof ep, "inproc://lumesh-monitor-%p", (void *)p);
    if (zmq_socket_monitor(p->sock, ep, MONITOR_EVENTS) != 0)
        return lm_fail(LM_E_INTERNAL, "watching handshakes: %s", zmq_strerror(zmq_errno()));
    p->monitor = zmq_socket(p->zctx, ZMQ_PAIR);
    if (!p->monitor || zmq_connect(p->monitor, ep) != 0)
        return lm_fail(LM_E_INTERNAL, "watching handshakes: %s", zmq_strerror(zmq_errno()));
    return LM_OK;
}

void co_pool_watch_handshakes(co_pool *p)
{
    if (!p->monitor)
        return;
    for (;;) {
        zmq_msg_t ev, addr;
        zmq_msg_init(&ev);
        if (zmq_msg_recv(&ev, p->monitor, ZMQ_DONTWAIT) < 0) {
            zmq_msg_close(&ev);
            return;
        }
        zmq_msg_init(&addr);
        zmq_msg_recv(&addr, p->monitor, 0);
        double now = co_pool_now();
        if (now - p->last_refusal_note > 1.0) { /* at most one line a second */
            co_pool_note(p, "a connection to %.*s failed its handshake (no keys, or wrong ones)",
                         (int)zmq_msg_size(&addr), (const char *)zmq_msg_data(&addr));
            p->last_refusal_note = now;
        }
        zmq_msg_close(&ev);
        zmq_msg_close(&addr);
    }
}

/* ---- setup ----------------------------------------------------------------------------------- */

lm_status co_pool_secure(co_pool *p)
{
    if (!p->o.keys)
        return LM_OK;
    lm_status st = start_zap(p);
    if (st == LM_OK)
        st = lm_keys_server(p->sock, p->o.keys);
    return st == LM_OK ? start_monitor(p) : st;
}

void co_pool_security_free(co_pool *p)
{
    if (p->monitor)
        zmq_close(p->monitor);
    p->monitor = NULL;
    if (p->zap.sock && !p->zap.started)
        zmq_close(p->zap.sock);
}

/* The ZAP thread ends when the context is terminated (its poll fails): join it after. */
void co_pool_security_join(co_pool *p)
{
    if (p->zap.started) {
        pthread_join(p->zap.thread, NULL);
        p->zap.started = 0;
    }
    lm_allow_free(&p->zap.allow);
}
