/* worker/serve/serve_beat.c — the worker's heartbeat: a thread with a socket of its own (routing id
 * "<the worker's id>#hb") that tells the coordinator every second, with jitter, that this process
 * lives — also while the main thread renders a long request (the coordinator then also knows it is
 * busy, and tells a slow worker from a dead one). A stopped process (SIGSTOP) or a cut network
 * stops the beats: the coordinator presumes the worker dead after a few seconds. */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <zmq.h>

#include "common/log.h"
#include "worker/serve/serve_internal.h"

#define BEAT_S 1.0
#define BEAT_JITTER 0.2 /* each interval is BEAT_S x (1 ± BEAT_JITTER) */

struct wk_beat {
    pthread_t thread;
    void *sock;
    atomic_int run, busy, paused; /* paused: no beats (a test hook's silent worker) */
    uint32_t rng;
};

static lm_status beat_once(wk_beat *b)
{
    Lumesh__Heartbeat h = LUMESH__HEARTBEAT__INIT;
    h.busy = atomic_load(&b->busy) != 0;
    lm_msg m;
    lm_wire_msg_init(&m, 0, 0, LUMESH__MSG__BODY_HEARTBEAT, &h);
    return lm_wire_send(b->sock, NULL, 0, &m);
}

static void *beat_main(void *arg)
{
    wk_beat *b = arg;
    while (atomic_load(&b->run)) {
        b->rng = b->rng * 1103515245u + 12345u;
        double j = 1.0 + BEAT_JITTER * (2.0 * (double)(b->rng >> 16 & 0x7fff) / 32767.0 - 1.0);
        lm_wire_frame f; /* anything the coordinator says to this socket is dropped */
        if (lm_wire_recv(b->sock, 0, (int)(1000.0 * BEAT_S * j), &f) == LM_OK)
            lm_wire_frame_release(&f);
        if (atomic_load(&b->run) && !atomic_load(&b->paused) && beat_once(b) != LM_OK)
            lm_clear_error(); /* no coordinator now: the next beat will try again */
    }
    return NULL;
}

lm_status wk_beat_start(wk_server *s, const char *id)
{
    wk_beat *b = calloc(1, sizeof *b);
    if (!b)
        return lm_fail(LM_E_NOMEM, "out of memory for the heartbeat");
    char hb[320];
    snprintf(hb, sizeof hb, "%.300s#hb", id);
    b->sock = zmq_socket(s->zctx, ZMQ_DEALER);
    lm_status st = b->sock ? lm_wire_socket_setup(b->sock, 0)
                           : lm_fail(LM_E_INTERNAL, "creating the heartbeat socket: %s",
                                     zmq_strerror(zmq_errno()));
    if (st == LM_OK)
        st = wk_serve_secure(s, b->sock);
    if (st == LM_OK && (zmq_setsockopt(b->sock, ZMQ_ROUTING_ID, hb, strlen(hb)) != 0 ||
                        zmq_connect(b->sock, s->o.endpoint) != 0))
        st = lm_fail(LM_E_INTERNAL, "connecting the heartbeat: %s", zmq_strerror(zmq_errno()));
    atomic_store(&b->run, 1);
    b->rng = (uint32_t)time(NULL) ^ (uint32_t)(uintptr_t)b;
    if (st == LM_OK && pthread_create(&b->thread, NULL, beat_main, b) != 0)
        st = lm_fail(LM_E_INTERNAL, "cannot start the heartbeat thread");
    if (st != LM_OK) {
        if (b->sock)
            zmq_close(b->sock);
        free(b);
        return st;
    }
    s->beat = b;
    return LM_OK;
}

void wk_beat_busy(wk_server *s, int busy)
{
    if (s->beat)
        atomic_store(&s->beat->busy, busy);
}

void wk_beat_pause(wk_server *s, int paused)
{
    if (s->beat)
        atomic_store(&s->beat->paused, paused);
}

void wk_beat_stop(wk_server *s)
{
    wk_beat *b = s->beat;
    if (!b)
        return;
    atomic_store(&b->run, 0);
    pthread_join(b->thread, NULL);
    zmq_close(b->sock);
    free(b);
    s->beat = NULL;
}
