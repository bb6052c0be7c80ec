/* worker/render/gl/gl_views_internal.h — state of the GL views backend, shared by gl_views.c
 * (life cycle, full renders, images) and views_eval.c (evaluate, commit). */
#ifndef LM_WORKER_VIEWS_LOCAL_INTERNAL_H
#define LM_WORKER_VIEWS_LOCAL_INTERNAL_H

#include "common/replica.h"
#include "worker/render/gl/gl_context.h"
#include "worker/render/gl/gl_views.h"
#include "worker/render/gl/render.h"
#include "worker/render/shared/buckets.h"
#include "worker/render/shared/cover.h"
#include "worker/render/shared/image_store.h"
#include "worker/render/shared/patch_prepare.h"
#include "worker/render/shared/views_core.h"

#define WK_FULL_ATLAS 0      /* full renders (and the colour images they leave) */
#define WK_SCRATCH_ATLASES 4 /* atlases 1..4: regions of up to 4 patches per readback */
#define WK_FULL_CHUNK 65536  /* triangles per upload in full renders */

/* One region to redraw: patch `patch` of the batch in view `view`. */
typedef struct wk_job {
    uint32_t patch, view;
    wk_rect rect;
    size_t first, count; /* triangles of the stream */
    size_t luma;         /* offset of its pixels in the batch's luminance buffer */
} wk_job;

/* A remembered "certainly hidden" answer for one triangle in one view. */
typedef struct wk_hidden_memo {
    uint32_t version; /* the view's depth version it was computed at */
    uint8_t known, hidden;
    int16_t witness[2]; /* when not hidden: a pixel of the footprint that shows it, or -1 */
} wk_hidden_memo;

typedef struct wk_views_local {
    wk_views_core core; /* first: views, images, replica, buckets, flags (views_core.h); its
                         * occlusion needs depth images */
    wk_gl_context *ctx;
    void *egl_context; /* EGLContext of ctx, to skip redundant makeCurrent */
    wk_renderer *r;
    int scratch_depth; /* region renders write the scratch atlases' depth images (commit only) */
    /* the stream of one upload */
    lm_corner *stream;
    uint32_t *stream_mat;
    size_t stream_n, stream_cap;
    /* jobs and their pixels for the last evaluation (kept for commit) */
    wk_job *jobs;
    size_t n_jobs, cap_jobs;
    uint8_t *luma;
    size_t n_luma, cap_luma;
    float *zreg; /* depth images of the regions (same offsets as luma) when occlusion is on */
    size_t cap_zreg;
    uint8_t *rgba;
    size_t cap_rgba;
    /* scratch for building patches' triangle lists */
    wk_idlist cand;
    wk_patch_marks marks; /* the patch's removed and added ids */
    lm_tri_data *sorted_added;
    size_t cap_sorted;
    wk_rect *visible; /* rectangles of a patch's visible removed triangles in one view */
    uint32_t cap_visible;
    const lm_tri_data **removed_tris; /* the records a patch removes */
    uint32_t cap_removed_tris;
    wk_hidden_memo *hidden; /* [view * cap_hidden + id]: the whole-footprint hidden test */
    size_t cap_hidden;
    wk_cover_patch cover_patch; /* of the patch being planned */
    wk_cover cover;             /* of that patch in the view being planned */
    /* regions to clear in one scratch atlas */
    uint32_t region_views[LM_MAX_VIEWS];
    wk_rect region_rects[LM_MAX_VIEWS];
    size_t n_regions;
    /* copies of the patches of the last evaluation */
    lm_patch *cached;
    uint32_t n_cached, cap_cached;
} wk_views_local;

lm_status wk_vl_make_current(wk_views_local *v);
lm_status wk_vl_stream_reserve(wk_views_local *v, size_t n_tris);
/* Append one triangle record to the stream. */
static inline void wk_vl_stream_push(wk_views_local *v, const lm_tri_data *t)
{
    lm_corner *c = v->stream + 3 * v->stream_n;
    c[0] = t->c[0];
    c[1] = t->c[1];
    c[2] = t->c[2];
    v->stream_mat[v->stream_n++] = t->material;
}

/* evaluate / commit (views_eval.c) */
lm_status wk_vl_evaluate(wk_views_core *c, const lm_patch *patches, uint32_t n, int64_t *delta);
lm_status wk_vl_commit(wk_views_core *c, const lm_patch *patch);
void wk_vl_forget_cache(wk_views_local *v);
void wk_vl_free_eval(wk_views_local *v);

#endif
