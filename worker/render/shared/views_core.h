/* worker/render/shared/views_core.h — what both in-process views backends (render/gl,
 * render/cpu) hold alike: their views, the image store, the current mesh's replica and each
 * view's triangle buckets, the state flags and counters. A backend's views object starts with
 * one; views_seam.h answers the views_api.h calls that both backends answer alike from it.
 * Here: its creation and end, the buckets' (re)build and the replica and buckets following a
 * committed patch. */
#ifndef LM_WORKER_RENDER_SHARED_VIEWS_CORE_H
#define LM_WORKER_RENDER_SHARED_VIEWS_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "common/patch.h"
#include "common/replica.h"
#include "common/view.h"
#include "common/views_api.h"
#include "worker/render/shared/buckets.h"
#include "worker/render/shared/image_store.h"
#include "worker/render/shared/views_stats.h"

typedef struct wk_views_backend wk_views_backend; /* views_seam.h */

typedef struct wk_views_core {
    lm_views base; /* first: the views_api.h object (its ops are views_seam.c's) */
    const wk_views_backend *backend;
    lm_view_set views; /* the backend's own, in order; all of one size */
    int width, height;
    wk_image_store *img;
    wk_buckets *buckets[LM_MAX_VIEWS];
    lm_replica rep;    /* the current mesh */
    int table;         /* material table of the current mesh: 0 the original's, 1 set_materials' */
    int mesh_set;      /* set_mesh succeeded (and no commit failed half-way since) */
    int buckets_ready; /* buckets match the replica */
    int occlusion;     /* skip views where a patch is certainly hidden */
    uint64_t seq;      /* changes of state so far (views_api.h) */
    wk_views_local_stats stats;
} wk_views_core;

/* The first `count` views of `views` (all of one size) and an empty replica; nothing allocated. */
void wk_views_core_init(wk_views_core *c, const lm_view *views, uint32_t count);
/* The image store and every view's (empty) buckets. */
lm_status wk_views_core_create_parts(wk_views_core *c);
/* Frees what the core holds (not c itself). */
void wk_views_core_free(wk_views_core *c);

/* Ready for evaluate/commit: a mesh set (LM_E_INVALID otherwise) and the buckets built. */
lm_status wk_views_core_ready(wk_views_core *c);
/* (Re)build every view's buckets from the replica. */
lm_status wk_views_core_build_buckets(wk_views_core *c);

/* Replica and buckets follow committed patch p; forget(c, id) is called for every removed and
 * every added id first (what the backend keeps per id). On failure both may be half-applied. */
lm_status wk_views_core_apply(wk_views_core *c, const lm_patch *p,
                              void (*forget)(wk_views_core *c, uint32_t id));

#endif
