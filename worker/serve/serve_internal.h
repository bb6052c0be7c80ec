/* worker/serve/serve_internal.h — the worker server's state, shared by serve.c (connection, Hello,
 * heartbeats, dispatch), serve_assets.c (offers, asset uploads, the cache) and serve_job.c (the
 * job, the assigned views, changes of state and requests). Not for other files. */
#ifndef LM_WORKER_SERVE_INTERNAL_H
#define LM_WORKER_SERVE_INTERNAL_H

#include <stdint.h>

#include "common/bvh.h"
#include "common/mesh.h"
#include "common/patch.h"
#include "common/replica.h"
#include "common/surface_table.h"
#include "common/view.h"
#include "common/views_api.h"
#include "proto/asset.h"
#include "proto/stream.h"
#include "proto/wire.h"
#include "proto/wire_records.h"
#include "worker/render/probe.h"
#include "worker/serve/serve.h"

/* An asset arriving in chunks. */
typedef struct wk_upload {
    lm_asset_hash hash;
    uint8_t *data;
    size_t size, got;
} wk_upload;

typedef struct wk_beat wk_beat;   /* serve_beat.c */
typedef struct wk_lanes wk_lanes; /* serve_lane.c */

typedef struct wk_server {
    wk_serve_options o;
    void *zctx, *sock; /* sock: the DEALER socket (NULL with a link) */
    lm_stream link;    /* with o.link_id: the socketpair to the coordinator that started us */
    int linked, link_closed;
    double spin_until; /* look for requests without sleeping until then (o.spin_s) */
    void *health;      /* REP socket answering health queries (NULL = none) */
    wk_beat *beat;
    char id[320]; /* routing id */
    char host[256], renderer[128], renderer_id[LM_WIRE_RENDERER_ID_CHARS + 1];
    int welcomed, unheard_noted;
    uint32_t worker_id; /* the coordinator's id for this worker (its Welcome) */
    uint32_t join;      /* the join Hello says: one more each time the worker drops its welcome */
    const char *fault;  /* LUMESH_WORKER_FAULT (test builds only, LUMESH_TEST_HOOKS): serve_job.c */
    double last_heard, last_hello, last_beat;
    /* assets */
    lm_asset_set cache;
    wk_upload *up;
    uint32_t n_up, cap_up;
    uint64_t offer_req; /* the open offer (0 = none) */
    /* the job */
    uint64_t job;
    lm_mesh *original;
    lm_asset_hash original_hash;
    lm_view_set *views; /* the job's whole view set */
    lm_view_deal deal;  /* the views assigned */
    lm_views *v;        /* the assigned views (NULL until Assign) */
    uint32_t n_materials;
    int mesh_set;   /* a mesh was set on v */
    lm_replica rep; /* v's current triangles: what patches are encoded against (Tri.same) */
    /* the geometric term of this worker's share of triangle ids (SetSurface; NULL = none), over
       the hierarchy of the original it was built for (kept across jobs of that original) */
    lm_surface_table *geo;
    lm_bvh *bvh;
    lm_asset_hash bvh_of;
    wk_lanes *lanes; /* RunLane's host, start mesh and scratch (NULL until a lane comes) */
    uint64_t seq;    /* of the replica (the coordinator's count of changes) */
    int stale;       /* a change failed or was missed: no request is answered until the state is
                        sent again */
    /* scratch */
    lm_patch *patches;
    uint32_t cap_patches;
    int64_t *deltas;
    size_t cap_deltas;
    lm_wire_arena arena;
} wk_server;

double wk_serve_now(void);

/* The CURVE client options of a socket of this worker, when it has keys (no-op otherwise). */
lm_status wk_serve_secure(wk_server *s, void *sock);

/* serve_beat.c */
lm_status wk_beat_start(wk_server *s, const char *id);
void wk_beat_busy(wk_server *s, int busy);
/* Stop (1) or resume (0) the beats: only the test hook "slow-load" (serve_job.c) does. */
void wk_beat_pause(wk_server *s, int paused);
void wk_beat_stop(wk_server *s);

/* serve_health.c */
lm_status wk_health_open(wk_server *s);
/* Answer a waiting health query (call when the health socket is readable). */
void wk_health_answer(wk_server *s);

/* Replies (req echoed, the replica's seq). */
lm_status wk_serve_send(wk_server *s, uint64_t req, Lumesh__Msg__BodyCase c, void *body);
lm_status wk_serve_fail(wk_server *s, uint64_t req, lm_status code, const char *message);

/* serve_assets.c */
lm_status wk_serve_offer(wk_server *s, const lm_msg *m);
lm_status wk_serve_asset(wk_server *s, const lm_msg *m);
void wk_serve_assets_free(wk_server *s);

/* serve_job.c */
lm_status wk_serve_job(wk_server *s, const lm_msg *m);
lm_status wk_serve_assign(wk_server *s, const lm_msg *m);
/* The test hook "slow-load=S": S, or 0 without it (serve_job.c). */
double wk_serve_slow_load_s(const wk_server *s);
lm_status wk_serve_change(wk_server *s, const lm_msg *m);
lm_status wk_serve_request(wk_server *s, const lm_msg *m);
void wk_serve_end_job(wk_server *s);
/* RunLane (serve_lane.c): the lane run and answered LaneDone, or Stale, or a Failure. */
lm_status wk_serve_lane(wk_server *s, const lm_msg *m);
void wk_serve_lanes_free(wk_server *s);

#endif
