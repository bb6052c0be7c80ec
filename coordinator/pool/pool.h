/* coordinator/pool/pool.h — the coordinator's workers: one ROUTER socket that lumesh-worker
 * processes connect to by address (remote ones join by --connect at any time), and for the local
 * ones the pool spawns itself a socketpair each that carries their messages (proto/stream.h:
 * heartbeats still go to the socket); the handshake (protocol version and renderer identity: a job
 * never mixes renderers), heartbeats both ways, and one reply slot per worker for the request in
 * flight.
 *
 * Contract (for the remote views backend, coordinator/views/views_remote.c, its only user):
 *   - Every call is made from one thread. co_pool_pump blocks up to its timeout; everything else
 *     returns at once (a send is queued, by ZeroMQ or the link, never waits for a peer).
 *   - Workers come and go: co_pool_pump welcomes or refuses new ones (a refused worker is told
 *     why), and marks a worker lost when its process exits or its link closes (local: a
 *     replacement is started,
 *     within a budget), a send to it fails, it has been silent for CO_POOL_SILENCE_S (its
 *     heartbeat thread beats every second even while it works), it left a request unanswered for
 *     CO_POOL_REQUEST_S, or it failed CO_POOL_MAX_FAILURES requests (blocklisted for the job). A
 *     lost worker is never used again: its late answers are dropped, and whatever it says next is
 *     answered Rejoin (drop your job, say Hello: it comes back as a new worker, with no views
 *     until it is brought up again). Callers see losses as w->lost and re-plan; the pool never
 *     fails because of a worker.
 *   - Anyone connected may ask for the pool's state (Status): `lumesh workers --connect ADDR`.
 *   - Replies land in the worker's slot when their req matches the one armed by co_pool_request;
 *     any other reply is dropped (late answers, answers to a request that was given up).
 *   - Ownership: workers are owned by the pool (pointers stay valid until co_pool_destroy);
 *     co_pool_destroy ends the job on every worker, stops and reaps the processes it spawned, and
 *     closes the socket. Local workers also die with the coordinator (PR_SET_PDEATHSIG). */
#ifndef LM_COORDINATOR_POOL_POOL_H
#define LM_COORDINATOR_POOL_POOL_H

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include "common/error.h"
#include "proto/wire.h"

#define CO_POOL_SILENCE_S 3.0 /* a worker silent this long is presumed dead */
/* ... but one loading a job (a set-up request in flight: the assets, the Job that unpacks the
 * original, the Assign that renders its targets: tens of seconds for a 2M-triangle original, more
 * on a loaded machine) only after this long: its beats may be late then, and losing it costs the
 * whole load again (co_pool_arm_load). A worker hung while loading is still caught. */
#define CO_POOL_LOAD_SILENCE_S 60.0
/* losses (exited processes, silence, stuck requests) are looked for at most this often: their
 * limits are seconds, and a local worker's end shows at once on its link */
#define CO_POOL_CHECK_S 0.02
#define CO_POOL_END_LINGER_MS 2000 /* how long EndJob messages may take to go out on close */
#define CO_POOL_REQUEST_S 120.0 /* a worker that leaves a request unanswered this long is stuck */
#define CO_POOL_LOAD_REQUEST_S 900.0 /* the same for a set-up request (co_pool_arm_load) */
/* How long a local worker looks for the next request after each reply before it sleeps
 * (lumesh-worker --spin-us), where the local workers fit on this machine's processors; 0 where
 * they do not (a worker waiting awake would take a processor from another). Why 150:
 * tests/bench/PERFORMANCE.md (local workers' spin). */
#define CO_POOL_SPIN_US 150u
/* How long the coordinator itself looks for its local workers' answers before it sleeps, where
 * they fit on the processors (as CO_POOL_SPIN_US): a processor that slept costs a wake-up per
 * answer. Why 100: tests/bench/PERFORMANCE.md (local workers' spin). */
#define CO_POOL_AWAIT_SPIN_US 100u

typedef struct co_worker {
    uint32_t id; /* 1, 2, ... in the order they were welcomed */
    uint8_t rid[LM_WIRE_MAX_IDENTITY];
    size_t rid_len;
    char host[128], device[64], renderer[128], renderer_id[LM_WIRE_RENDERER_ID_CHARS + 1];
    uint32_t pid;
    uint32_t join; /* the Hello's join number: a repeat of it is the same join, not a restart */
    int lost;
    double joined, last_heard; /* seconds on the pool's clock */
    /* what the job made of it (kept by the views backend) */
    uint64_t job;                  /* the remote views' job it was brought up for (0 = none): a
                                      pool serves one views object at a time, and a newer one
                                      (a regrid's) brings every worker into its own job */
    uint32_t first, count, stride; /* views assigned (an lm_view_deal) */
    uint64_t evals;                /* patches evaluated for the job */
    double busy_s;                 /* seconds spent evaluating them (the worker's own count) */
    /* the optimisation loop's share (co_pool_mark_loop): busy_s then, and since when it counts
       (the loop's start, or its join when later); loop_from 0 = the loop has not begun */
    double loop_busy0, loop_from;
    /* the request in flight */
    uint64_t want; /* req armed; 0 = none */
    double armed_at;
    int loading; /* the request armed is a set-up one (co_pool_arm_load): the load limits apply */
    int replied;
    lm_wire_in reply;
    uint64_t lane_group; /* --lanes remote: the group whose start mesh it was sent (0 = none) */
    uint32_t failures;   /* requests it failed (CO_POOL_MAX_FAILURES: blocklisted) */
    uint64_t lanes_confirmed; /* --lanes remote: its lane results another worker's agreed with
                                 (views_remote_lanes.c: probation while below the audit's P) */
} co_worker;

typedef struct co_pool co_pool;

typedef struct co_pool_options {
    const char *listen;      /* "tcp://ADDR:PORT" to bind; NULL = a private ipc:// endpoint */
    uint32_t local_workers;  /* lumesh-worker processes to spawn (connected to the endpoint) */
    const char *worker_path; /* their program; NULL = LUMESH_WORKER, beside lumesh, or PATH */
    const char *device;      /* their --device (NULL = "auto") */
    const char *renderer_id; /* accept only this renderer; NULL = the first worker's */
    const char *keys;        /* CURVE key folder (proto/keys.h); required to listen beyond this
                                machine; local workers are given it too */
    int quiet;               /* no notes on stderr about workers joining and leaving */
    int socket_only;         /* local workers talk over the socket too, not a socketpair of
                                their own (proto/stream.h): for measuring the difference */
    int spin_us;             /* local workers' --spin-us: 0 = CO_POOL_SPIN_US where they fit on
                                the processors, else none (resolved by co_pool_create); < 0 =
                                none */
    int await_spin_us;       /* this process's wait for its local workers' answers, awake: 0 =
                                CO_POOL_AWAIT_SPIN_US where they fit on the processors, else
                                none (resolved by co_pool_create); < 0 = none */
} co_pool_options;

lm_status co_pool_create(const co_pool_options *o, co_pool **out);
void co_pool_destroy(co_pool *p);

/* The endpoint workers connect to (e.g. for `lumesh-worker --connect`). */
const char *co_pool_endpoint(const co_pool *p);
/* The renderer identity the pool accepts ("" until the first worker pins it). */
const char *co_pool_renderer_id(const co_pool *p);

/* Take in messages for up to timeout_ms (0 = what is there); every CO_POOL_CHECK_S at most, also
 * send heartbeats and notice losses. */
lm_status co_pool_pump(co_pool *p, int timeout_ms);

/* 1 when the local workers are as many as this machine's processors or more: while they render,
 * this process's own work takes a processor from one of them. */
int co_pool_cores_full(const co_pool *p);

/* Workers welcomed so far (lost ones included: check w->lost). */
uint32_t co_pool_size(const co_pool *p);
co_worker *co_pool_worker(co_pool *p, uint32_t i);
/* Welcomed and not lost. */
uint32_t co_pool_alive(const co_pool *p);

/* Wait until `n` workers are alive: pumping, saying every few seconds that the job waits.
 * LM_E_IO after timeout_s (0 = forever), LM_E_INVALID when interrupted (co_pool_interrupted). */
lm_status co_pool_wait(co_pool *p, uint32_t n, double timeout_s);

/* Send one message to w (a change of state when req is 0). A failed send marks w lost and
 * returns LM_OK: the caller sees w->lost. */
lm_status co_pool_send(co_pool *p, co_worker *w, uint64_t req, uint64_t seq,
                       Lumesh__Msg__BodyCase body_case, void *body);
/* Send bytes packed once (lumesh__msg__pack) to w: one encoding for many workers. */
lm_status co_pool_send_packed(co_pool *p, co_worker *w, const uint8_t *data, size_t size);
/* A fresh request number (one may be armed on several workers: one encoding for all). */
uint64_t co_pool_next_req(co_pool *p);
/* Arm w's slot for request req (the previous reply, if any, is released). */
void co_pool_arm_req(co_worker *w, uint64_t req);
/* A fresh request number armed in w's slot. */
uint64_t co_pool_arm(co_pool *p, co_worker *w);
/* As co_pool_arm_req, for a request that sets w up for a job (assets, Job, Assign): until it is
 * answered w is lost only after CO_POOL_LOAD_SILENCE_S of silence (CO_POOL_LOAD_REQUEST_S
 * unanswered), not CO_POOL_SILENCE_S (CO_POOL_REQUEST_S). */
void co_pool_arm_load(co_worker *w, uint64_t req);
/* Release w's reply and disarm its slot. */
void co_pool_disarm(co_worker *w);

/* A request of w failed (a Failure answer): the third blocklists w for the job (lost; its Hello
 * refused). */
void co_pool_failed(co_pool *p, co_worker *w, const char *what);
/* w answered something that cannot be right (a lane's result that does not decode or fit): it is
 * blocklisted for the job at once (lost), as if it had failed CO_POOL_MAX_FAILURES times. */
void co_pool_fence(co_pool *p, co_worker *w, const char *what);
/* What status queries report as the job's evaluations so far. */
void co_pool_set_job_evals(co_pool *p, uint64_t evals);
/* The optimisation loop begins now: each worker's busy share over the loop counts from here
 * (workers that join later: from their join), co_pool_loop_busy. */
void co_pool_mark_loop(co_pool *p);
/* The optimisation loop has ended now: the shares stop counting. */
void co_pool_mark_loop_end(co_pool *p);
/* w's share of the loop's wall time (since the loop began or w joined, until the loop's end, now
 * or, lost, when last heard) spent evaluating; 0 before co_pool_mark_loop. */
double co_pool_loop_busy(const co_pool *p, const co_worker *w, double now);

/* Seconds on the pool's clock (monotonic). */
double co_pool_now(void);

/* SIGINT, SIGTERM or SIGUSR1 seen since the process started (set by co_pool_catch_signals's
 * handler); co_pool_interrupt_signal names the last one seen (0 = none). */
void co_pool_catch_signals(void);
int co_pool_interrupted(void);
int co_pool_interrupt_signal(void);

#endif
