/* coordinator/views/views.h — the one constructor of views backends (common/views_api.h).
 *
 * Every kind is made from one description: what the targets are (the original), which views (a
 * view set and the range of it this object serves), the current mesh's materials (and optionally
 * the mesh itself), and where the pixels are made:
 *   local   in this process, on an EGL device (worker/render/views_local.c);
 *   split   `split` in-process children, each owning a contiguous range of the views, their int64
 *           results summed (coordinator/views/views_split.c): bit-identical to one local backend;
 *   remote  lumesh-worker processes of a pool (coordinator/pool/pool.h), each serving a share of
 *           the views (coordinator/views/views_remote.c): bit-identical again, for any number of
 *           workers.
 * Defaults are resolved here and nowhere else (co_views_desc_defaults). The coordinator makes
 * views only through this constructor; nothing outside coordinator/views/ names a backend. */
#ifndef LM_COORDINATOR_VIEWS_VIEWS_H
#define LM_COORDINATOR_VIEWS_VIEWS_H

#include <stdint.h>

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"
#include "coordinator/views/lane_audit.h"
#include "proto/asset.h"

typedef struct co_pool co_pool; /* coordinator/pool/pool.h */

typedef enum co_views_kind {
    CO_VIEWS_LOCAL = 0,
    CO_VIEWS_SPLIT,
    CO_VIEWS_REMOTE,
} co_views_kind;

/* Zero means default for every field but original and views. */
/* The original packed as an asset (proto/asset.h) once for all the remote views a job makes (its
 * regrids): the first views fill it, later ones copy it instead of packing and hashing the original
 * again. Its owner keeps `mesh` unchanged while the pack holds it and frees the pack with
 * co_original_pack_free; zeroed = empty. */
typedef struct co_original_pack {
    const lm_mesh *mesh; /* what the assets were packed from; NULL = empty */
    lm_asset_set assets;
    lm_asset_hash hash; /* the mesh asset's */
} co_original_pack;

void co_original_pack_free(co_original_pack *p);

typedef struct co_views_desc {
    co_views_kind kind;           /* 0 = local */
    const lm_mesh *original;      /* required: the targets are its images; its materials are the
                                     material table unless `materials` is given */
    const lm_view_set *views;     /* required: the job's whole view set (copied) */
    uint32_t first, count;        /* the range of `views` served; count 0 = first to the end */
    const lm_material *materials; /* the current mesh's material table; NULL = the original's */
    uint32_t n_materials;
    const lm_mesh *mesh;    /* set as the current mesh right away; NULL = later, by set_mesh */
    const char *device;     /* local and split children: "auto" (NULL), "host", "egl:N" */
    uint32_t split;         /* split: children (at most the range's views); 0 = 2 */
    co_pool *pool;          /* remote: the workers (borrowed; must outlive the views) */
    int whole;              /* remote: every worker serves every view (workers beyond the first are
                               replicas), so that each can run whole lanes (co_views_lane_runner) */
    co_audit_rule audit;    /* remote, whole: which lanes a second worker runs again (lane_audit.h);
                               zero = none (the job resolves its default) */
    co_original_pack *pack; /* remote: the original's asset kept across views (borrowed); NULL =
                               packed for these views alone */
} co_views_desc;

/* The description with every zero field resolved (no checks). */
co_views_desc co_views_desc_defaults(const co_views_desc *d);

/* Make views from a description. On success *out is ready: targets rendered, materials set, and
 * the mesh set when one was given. Nothing is left behind on failure. */
lm_status co_views_create(const co_views_desc *d, lm_views **out);

/* The split backend over children made by the caller (each serving a range of views, in order;
 * every child the same width, height and renderer). Takes ownership of the children, also on
 * failure. */
lm_status co_views_split_create(lm_views **children, uint32_t n, lm_views **out);

/* Remote views made with `whole`: *out runs the isolated lanes of each group on the workers
 * (coordinator/views/views_remote_lanes.c), its ctx the views (valid while they are). Other
 * views: LM_E_UNSUPPORTED. */
typedef struct lm_lane_runner lm_lane_runner;
lm_status co_views_lane_runner(lm_views *v, lm_lane_runner *out);

/* What the lanes' groups sent to the workers (co_views_lane_runner's views). */
typedef struct co_lane_stats {
    uint64_t groups;             /* groups run */
    uint64_t starts_full;        /* start meshes sent whole */
    uint64_t starts_delta;       /* start meshes sent as deltas against the last group's */
    uint64_t start_bytes;        /* their bytes, in all */
    uint64_t request_bytes;      /* the lanes' requests' bytes, in all (re-sends included) */
    uint64_t start_record_bytes; /* the start meshes' whole records, one per group, in all */
    uint64_t queues_full;        /* collapse queues sent whole (once per group and worker) */
    uint64_t queues_delta;       /* collapse queues sent as deltas against the last group's */
    uint64_t queue_bytes;        /* their bytes, in all */
    uint64_t queue_record_bytes; /* the queues' whole records, one per group, in all */
    uint64_t audits;             /* lanes run again by another worker (audits and arbitrations) */
    uint64_t audit_mismatches;   /* audits whose result differed (a third worker arbitrates) */
    uint64_t audit_fenced;       /* workers fenced for a wrong result */
    uint64_t audits_skipped;     /* audits due with no other worker to run them */
} co_lane_stats;

/* Adds v's counts to *sum (nothing when v is not remote views). */
void co_views_lane_stats(lm_views *v, co_lane_stats *sum);

#endif
