/* worker/serve/serve.h — `lumesh-worker --connect ADDR`: serve views to a coordinator over ZeroMQ.
 *
 * The worker connects (DEALER) to the coordinator's ROUTER, says Hello (protocol version, host,
 * device, renderer and its fingerprint, worker/render/probe.h) and, once welcomed, does what it is
 * told (proto/lumesh.proto): hold assets by content hash (kept across jobs), take a job (the
 * original and the view set), render the targets of the views it is assigned, keep a replica of the
 * current mesh that changes only by the coordinator's changes in sequence, and answer requests —
 * evaluations, energies, oracle potentials, images — for its views. A request that finds the
 * replica at another sequence number than the coordinator expects is answered Stale, never priced.
 *
 * Between jobs, whenever the coordinator has been silent for a while (it went away; a new one may
 * come at the same address) and when a coordinator says it does not know this worker (Rejoin: it
 * restarted, or presumed the worker dead), the worker drops its job and says Hello again every
 * second: a long-lived worker serves job after job, its asset cache warm. A heartbeat thread tells
 * the coordinator every second that the process lives, also while a long request runs
 * (serve_beat.c). Every malformed message is answered with a Failure and logged; the worker goes
 * on. With keys, every frame is encrypted and both ends authenticated (CURVE). */
#ifndef LM_WORKER_SERVE_H
#define LM_WORKER_SERVE_H

#include <stddef.h>

#include "common/error.h"

typedef struct wk_serve_options {
    const char *endpoint; /* required: "tcp://host:port" or "ipc://path" */
    const char *device;   /* NULL = "auto" */
    int once;             /* exit after the first job ends (workers spawned by a coordinator) */
    double silence_s;     /* coordinator presumed gone after this long without a word; 0 = 30 */
    const char *keys;     /* CURVE key folder (proto/keys.h): worker.key, coordinator.pub */
    const char *health;   /* answer health queries on this endpoint (e.g. ipc://PATH); NULL = no */
    int link_fd;          /* >= 0: messages over this socketpair (proto/stream.h), heartbeats to
                             endpoint; the worker ends when it closes. -1 (or 0 with no link_id):
                             everything over endpoint */
    const char *link_id;  /* the routing id the coordinator gave the link (with link_fd) */
    int link_shm;         /* > 0 (with link_fd): the link's shared-memory lane (proto/ring.h),
                             taken over; 0 = none */
    double spin_s;        /* with link_fd: after each reply, look for the next request this long
                             (yielding the processor to anyone else who wants it) before sleeping;
                             0 = sleep at once. The coordinator's next request usually comes
                             sooner, and a processor woken from sleep can cost more than that
                             (tens of µs on a virtual machine). */
} wk_serve_options;

/* The most --spin-us takes. */
#define WK_SERVE_MAX_SPIN_US 10000

/* Ask the worker whose health endpoint is `endpoint` how it stands: its answer (one JSON
 * object) into buf; LM_E_IO when it does not answer within timeout_s. *ready = 1 when it is
 * welcomed by a coordinator. */
lm_status wk_serve_health_query(const char *endpoint, double timeout_s, char *buf, size_t cap,
                                int *ready);

/* Serve until told to stop (SIGINT/SIGTERM), refused by a coordinator (LM_E_INVALID with its
 * reason) or, with once, the end of the first job. */
lm_status wk_serve(const wk_serve_options *opts);

#endif
