/* coordinator/views/views_remote_internal.h — state of the remote views backend, shared by
 * views_remote.c (the ops) and views_remote_layout.c (layout, bringing workers up, exchanges).
 * Not for other files. */
#ifndef LM_COORDINATOR_VIEWS_VIEWS_REMOTE_INTERNAL_H
#define LM_COORDINATOR_VIEWS_VIEWS_REMOTE_INTERNAL_H

#include <stdint.h>

#include "common/replica.h"
#include "coordinator/pool/pool.h"
#include "coordinator/views/views_remote.h"
#include "proto/asset.h"
#include "proto/wire_records.h"

#define CO_REMOTE_TRIES 32  /* attempts of one operation (workers lost or stale in between) */
#define CO_REMOTE_STRIKES 3 /* attempts whose workers died or failed on it: then it is poison */
#define CO_REMOTE_INTERRUPT_GRACE_S                                                                \
    5.0 /* an interrupted run waits this long for answers, then stops */

typedef lm_view_deal co_range; /* job view indices: a share of the views (common/view.h) */

typedef struct co_remote {
    lm_views base;
    co_pool *pool;
    uint64_t job;
    lm_asset_set assets;
    lm_asset_hash original, materials;
    int has_materials;
    const lm_mesh *original_mesh; /* what the original asset was packed from (borrowed) */
    double surface_k;             /* the geometric term the workers price (0 = none) */
    lm_view_set *views;           /* the job's whole view set */
    uint32_t first, count;
    int width, height;
    /* the current state, re-sent to workers that lack it */
    lm_replica rep;
    int mesh_set;
    uint64_t seq;
    /* the layout: live[i] serves range[group[i]] */
    co_worker **live;
    uint32_t n_live, cap_live;
    uint32_t *group;
    co_range ranges[LM_MAX_VIEWS];
    uint32_t n_ranges;
    char renderer[128];
    uint64_t evaluations;
    int whole;             /* every worker serves every view (co_views_desc.whole) */
    lm_asset_hash targets; /* whole: the targets asset of the view set, once rendered split */
    int has_targets;       /* ... made and held by every worker it was shipped to: Assign names
                              it (views_remote_layout.c, split_targets) */
    uint64_t lane_group;   /* the group of lanes running on the workers (views_remote_lanes.c) */
    uint8_t *lane_base;    /* the last group's encoded start mesh: later starts go as deltas
                              against it to the workers that took it (lane_delta.h) */
    size_t n_lane_base;
    uint8_t *lane_queue_base; /* the last group's encoded collapse queue: later queues go as
                                 deltas against it */
    size_t n_lane_queue_base;
    uint64_t lane_base_group; /* their group (0 = none) */
    co_lane_stats lane_stats; /* what the lanes' groups sent */
    co_audit_rule audit;      /* which lanes a second worker runs again (lane_audit.h) */
    /* scratch */
    lm_wire_arena arena;
    uint8_t *pack;
    size_t cap_pack;
} co_remote;

/* Make sure the layout uses every live worker and no lost one, bringing workers up as needed;
 * waits for a first worker when there is none. */
lm_status co_remote_layout(co_remote *r);
/* 1 when a worker of the layout is lost or a new one waits to be brought in. */
int co_remote_layout_stale(co_remote *r);

/* Pump until every worker of ws (n) that is not lost has replied to its armed request. */
lm_status co_remote_await(co_remote *r, co_worker **ws, uint32_t n);

/* Pack a message into r->pack (valid until the next pack); *size its length. */
lm_status co_remote_pack(co_remote *r, uint64_t req, uint64_t seq, Lumesh__Msg__BodyCase c,
                         void *body, size_t *size);

/* Every asset of r->assets on every worker of ws: Offer, then what each Needs, until Ready. */
lm_status co_remote_ship(co_remote *r, co_worker **ws, uint32_t n);

/* Send the current state (materials, geometric term, mesh) to w: after its views were assigned,
 * or when it said it is stale. */
lm_status co_remote_send_state(co_remote *r, co_worker *w);

/* The SetSurface of the current geometric term (r->surface_k > 0). */
void co_remote_surface_msg(const co_remote *r, Lumesh__SetSurface *out);

/* The replica's mesh as a SetMesh (its records in r->arena and *tris, which the caller frees
 * after sending, with lm_wire_arena_reset). */
lm_status co_remote_mesh_msg(co_remote *r, Lumesh__SetMesh *out, lm_tri_data **tris);

/* A reply that is not the expected kind: Stale (1: resend the state and try again) or a Failure
 * or anything else (an error naming the worker). */
lm_status co_remote_check_reply(co_remote *r, co_worker *w, Lumesh__Msg__BodyCase want, int *stale);

void co_remote_layout_free(co_remote *r);

/* The remote views behind v, or NULL when v is another kind. */
co_remote *co_remote_of(lm_views *v);

#endif
