/* worker/serve.h — `lumesh-worker --connect ADDR`: serve views to a coordinator over ZeroMQ.
 *
 * The worker connects (DEALER) to the coordinator's ROUTER, says Hello (protocol version, host,
 * device, renderer and its fingerprint, worker/probe.h) and, once welcomed, does what it is told
 * (proto/lumesh.proto): hold assets by content hash (kept across jobs), take a job (the original
 * and the view set), render the targets of the views it is assigned, keep a replica of the current
 * mesh that changes only by the coordinator's changes in sequence, and answer requests —
 * evaluations, energies, oracle potentials, images — for its views. A request that finds the
 * replica at another sequence number than the coordinator expects is answered Stale, never priced.
 *
 * Between jobs, and whenever the coordinator has been silent for a while (it went away; a new one
 * may come at the same address), the worker says Hello again every second: a long-lived worker
 * serves job after job, its asset cache warm. Every malformed message is answered with a Failure
 * and logged; the worker goes on. */
#ifndef LM_WORKER_SERVE_H
#define LM_WORKER_SERVE_H

#include "common/error.h"

typedef struct wk_serve_options {
    const char *endpoint; /* required: "tcp://host:port" or "ipc://path" */
    const char *device;   /* NULL = "auto" */
    int once;             /* exit after the first job ends (workers spawned by a coordinator) */
    double silence_s;     /* coordinator presumed gone after this long without a word; 0 = 10 */
} wk_serve_options;

/* Serve until told to stop (SIGINT/SIGTERM), refused by a coordinator (LM_E_INVALID with its
 * reason) or, with once, the end of the first job. */
lm_status wk_serve(const wk_serve_options *opts);

#endif
