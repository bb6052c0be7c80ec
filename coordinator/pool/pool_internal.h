/* coordinator/pool/pool_internal.h — the pool's state, shared by pool.c (socket, sending,
 * reply slots, pumping, waiting), pool_peers.c (handshake, heartbeats, losses, blocklist, Rejoin,
 * status queries), pool_links.c (the local workers' socketpairs, sending and receiving) and
 * pool_security.c (CURVE, the ZAP handler, handshake failures, which addresses need keys). Not for
 * other files. */
#ifndef LM_COORDINATOR_POOL_POOL_INTERNAL_H
#define LM_COORDINATOR_POOL_POOL_INTERNAL_H

#include <poll.h>
#include <pthread.h>
#include <zmq.h>

#include "coordinator/pool/pool.h"
#include "coordinator/pool/spawn.h"
#include "proto/keys.h"
#include "proto/stream.h"

#define CO_POOL_BEAT_S 1.0
#define CO_POOL_WAIT_NOTE_S 5.0
/* failures after which a worker is blocklisted for the job */
#define CO_POOL_MAX_FAILURES 3
/* local workers are replaced at most 3N + 8 times in this many seconds */
#define CO_POOL_RESPAWN_WINDOW_S 60.0

typedef struct co_zap {
    pthread_t thread;
    void *sock;
    lm_allow allow;
    co_pool *pool;
    int started;
} co_zap;

/* A socketpair to a worker process the pool started (pool_links.c). */
typedef struct co_link {
    lm_stream s;
    char rid[64]; /* the routing id the worker is known by ("local:<our pid>:<n>") */
    size_t rid_len;
    int ended; /* closed or failed: dropped once its frames are taken */
} co_link;

struct co_pool {
    co_pool_options o;
    void *zctx, *sock;
    void *monitor; /* PAIR socket of the ROUTER's events (handshake failures); NULL = none */
    char endpoint[512];
    char ipc_dir[256]; /* the private folder of an ipc endpoint ("" for tcp) */
    char renderer_id[LM_WIRE_RENDERER_ID_CHARS + 1];
    co_worker **w;
    uint32_t n, cap;
    uint64_t next_req;
    double last_beat, last_refusal_note, last_check;
    co_spawned spawned;
    double *respawns; /* when recent replacements of lost local workers were started */
    uint32_t n_respawns, cap_respawns;
    char (*blocked)[160]; /* "host:pid" of blocklisted workers */
    uint32_t n_blocked;
    co_zap zap;
    double loop_t0, loop_t1; /* co_pool_mark_loop's, co_pool_mark_loop_end's times; 0 = not yet */
    uint64_t job_evals;      /* for status queries: evaluations of the job so far (views backend) */
    co_link *links;          /* of the local workers */
    uint32_t n_links, cap_links, links_made;
    struct pollfd *poll_fds; /* [cap_links + 1]: the links, then the socket's ZMQ_FD */
    /* The socket's descriptor signals only changes (ZeroMQ's ZMQ_FD): it can be slept on only
     * once ZMQ_EVENTS has said "nothing to read" since the socket was last used. sock_unsure is
     * set by every send or receive on the socket and cleared by that answer (pool_links.c). */
    int sock_fd, sock_unsure;
    int cores_full; /* co_pool_cores_full, decided at creation */
};

void co_pool_note(const co_pool *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* pool_peers.c */
lm_status co_pool_on_frame(co_pool *p, const lm_wire_frame *f);
void co_pool_notice_losses(co_pool *p, double now);
void co_pool_lose(co_pool *p, co_worker *w, const char *why);

/* pool_links.c: the one way frames go out and come in */
/* Start n local workers, each with a link of its own. */
lm_status co_pool_spawn(co_pool *p, uint32_t n);
/* To the peer with routing id `id`: over its link, else the ROUTER socket, never blocking.
 * LM_E_IO when a socket peer is gone (a link that fails is dropped by co_pool_recv). */
lm_status co_pool_send_frame(co_pool *p, const uint8_t *id, size_t id_len, const void *data,
                             size_t size);
lm_status co_pool_send_msg(co_pool *p, const uint8_t *id, size_t id_len, const lm_msg *m);
/* Wait up to timeout_ms for a frame from a link or the socket (as lm_wire_recv), moving what
 * links have queued meanwhile. */
lm_status co_pool_recv(co_pool *p, int timeout_ms, lm_wire_frame *f);
/* Write what links have queued, for up to timeout_ms (the end of a job); then close them. */
void co_pool_links_flush(co_pool *p, int timeout_ms);
void co_pool_links_close(co_pool *p);

/* pool.c */
/* Replacements of lost local workers still allowed now (pool_peers.c). */
uint32_t co_pool_respawns_left(co_pool *p, double now);

/* pool_security.c */
lm_status co_pool_secure(co_pool *p);
void co_pool_security_free(co_pool *p); /* before the context ends */
void co_pool_security_join(co_pool *p); /* after */
void co_pool_watch_handshakes(co_pool *p);
/* 1 when a tcp endpoint listens beyond this machine (loopback and ipc do not). */
int co_pool_endpoint_is_public(const char *endpoint);

#endif
