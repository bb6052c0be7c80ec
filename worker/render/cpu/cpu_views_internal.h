/* worker/render/cpu/cpu_views_internal.h — state of the CPU views backend, shared by cpu_views.c
 * (life cycle, extras), cpu_render.c (full renders) and cpu_eval.c (evaluate, commit). */
#ifndef LM_WORKER_CPU_VIEWS_INTERNAL_H
#define LM_WORKER_CPU_VIEWS_INTERNAL_H

#include "common/replica.h"
#include "worker/render/cpu/cpu_cull.h"
#include "worker/render/cpu/cpu_holes.h"
#include "worker/render/cpu/cpu_raster.h"
#include "worker/render/cpu/cpu_setups.h"
#include "worker/render/cpu/cpu_shade.h"
#include "worker/render/cpu/cpu_subcache.h"
#include "worker/render/cpu/cpu_texture.h"
#include "worker/render/cpu/cpu_views.h"
#include "worker/render/shared/buckets.h"
#include "worker/render/shared/image_store.h"
#include "worker/render/shared/patch_prepare.h"
#include "worker/render/shared/views_core.h"

/* Scratch of evaluate and commit (cpu_eval.c). Per-id arrays have cap_ids entries. */
typedef struct wk_cpu_eval {
    wk_cpu_log log;  /* arrays of one view's size */
    uint32_t *owned; /* [plane] pixels found by wk_cpu_owned */
    uint8_t *luma;   /* [plane] new luminance of the logged pixels, in log order */
    uint8_t *rgb;    /* [3 plane] colours of a full render's pixels of one sub */
    float *texl;     /* [3 plane] texture factors of the logged pixels (of one sub in a render) */
    uint64_t *tile_old; /* raised tiles' maxima before the pass */
    uint32_t *tile_idx, *tile_stamp;
    size_t n_raised;
    uint8_t *tile_mask; /* [tiles]: tiles with unresolved pixels */
    uint32_t *mask_idx;
    uint64_t *cmax; /* [tiles]: greatest key of a masked tile's unresolved pixels */
    size_t n_mask;
    wk_cpu_setups set;
    wk_patch_marks marks; /* the patch's removed and added ids (its stamp: marks.now) */
    size_t cap_ids;
    uint32_t *twin_stamp, *twin_of;  /* per id: twins (stamped marks.now) and their records */
    uint32_t *textwin_stamp;         /* twins whose material and texture coordinates stay too */
    wk_cpu_box box;                  /* of the patch's added triangles that are not twins */
    uint32_t *loc_stamp, *loc_first; /* per id: its subs in `set` during this pass */
    uint8_t *loc_n;
    wk_idlist cand;
    uint64_t gathered;     /* sum of the loads that gather a view's memory (never used) */
    wk_cpu_holes *holes;   /* [n_views] each view's last step A, replayed (cpu_holes.h) */
    uint8_t *removed_twin; /* [cap_removed] the patch's removed ids: 1 where a twin */
    uint32_t cap_removed;
} wk_cpu_eval;

typedef struct wk_cpu_views {
    wk_views_core core; /* first: views, images, replica, buckets, flags (views_core.h) */
    wk_cpu_view cviews[LM_MAX_VIEWS];
    int tiles_w, tiles_h;
    size_t plane, tiles;
    wk_cpu_materials mats[2]; /* 0: the original's, 1: the current model's when set (core.table) */
    uint64_t *keys; /* [n_views * plane] keys of the current mesh (of the target while creating) */
    uint64_t *tmax; /* [n_views * tiles] */
    uint32_t *second; /* [n_views * plane] lower bounds of the second least keys (wk_cpu_keys) */
    uint32_t *count;  /* [cap_count * n_views] visible pixels of each current triangle id in each
                         view, an id's views side by side (wk_cpu_count): an evaluation reads its
                         removed triangles' counts view after view, a line now serves 16 views */
    size_t cap_count;
    uint8_t *rgba; /* [n_views * plane * 4] colours of the last full render */
    float *texf;   /* [n_views * plane * 3] texture factors of the visible surface (NULL: none) */
    wk_cpu_subcache subcache; /* subs of the current triangles */
    wk_cpu_vcorner
        *vc; /* [cap_vc] a mesh source's vertices in the view being drawn (cpu_render.c) */
    size_t cap_vc;
    wk_cpu_eval eval;
} wk_cpu_views;

/* The visible-pixel count of triangle id in view h (id < cap_count). */
static inline uint32_t *wk_cpu_count(const wk_cpu_views *v, uint32_t h, uint32_t id)
{
    return &v->count[(size_t)id * v->core.views.count + h];
}

static inline wk_cpu_keys wk_cpu_view_keys(wk_cpu_views *v, uint32_t h)
{
    return (wk_cpu_keys){.key = v->keys + h * v->plane,
                         .tmax = v->tmax + h * v->tiles,
                         .width = v->core.width,
                         .height = v->core.height,
                         .tiles_w = v->tiles_w};
}

/* A source of triangle records for a full render: an original mesh's alive triangles or the
 * replica's. */
typedef struct wk_cpu_source {
    const lm_mesh *mesh;
    const lm_replica *rep;
} wk_cpu_source;

/* Full render of view h from src with material table `table` (cpu_render.c): keys, tile maxima,
 * colours, and luminance into y; visible pixel counts per id into count (one per id of src's
 * range, view h's alone; or NULL when not wanted, then counted in scratch). */
lm_status wk_cpu_render_view(wk_cpu_views *v, uint32_t h, const wk_cpu_source *src, int table,
                             uint8_t *y, uint32_t *count);

/* Grow the visible-pixel counts to at least need ids (new ones 0). */
lm_status wk_cpu_count_reserve(wk_cpu_views *v, size_t need);

/* cpu_eval.c (the backend's evaluate and commit, views_seam.h) */
lm_status wk_cpu_evaluate(wk_views_core *c, const lm_patch *patches, uint32_t n, int64_t *delta);
lm_status wk_cpu_commit(wk_views_core *c, const lm_patch *patch);
lm_status wk_cpu_eval_init(wk_cpu_views *v);
void wk_cpu_eval_free(wk_cpu_eval *e, uint32_t n_views);

#endif
