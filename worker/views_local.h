/* worker/views_local.h — the in-process views backend (common/views_api.h) on an EGL context:
 * renders the target images of the original once, keeps the current images of the mesh set with
 * set_mesh up to date through committed patches, and evaluates patches incrementally (triangle
 * buckets, scissored redraw of the affected region of every view, one readback per batch). */
#ifndef LM_WORKER_VIEWS_LOCAL_H
#define LM_WORKER_VIEWS_LOCAL_H

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"

/* device_spec: "auto", "egl:N" or "host" (NULL = "auto"). The original's materials (diffuse and
 * textures) form the material table that triangle records' material ids index, for the target and,
 * unless wk_views_local_set_materials says otherwise, for the current mesh. On success *out
 * holds the target images; set_mesh must be called before evaluate/commit/energy. */
lm_status wk_views_local_create(const lm_mesh *original, const lm_view_set *views,
                                const char *device_spec, lm_views **out);

/* Use these materials (copied, textures uploaded) for the current mesh's material ids instead of
 * the original's, e.g. when the model was loaded from its own file. Re-renders a mesh already set.
 */
lm_status wk_views_local_set_materials(lm_views *views, const lm_material *mats, uint32_t n);

/* Tuning and introspection for tests and benchmarks. */
typedef struct wk_views_local_stats {
    uint64_t evaluations;    /* patches evaluated */
    uint64_t batches;        /* readback synchronisations in evaluate/commit */
    uint64_t tris_drawn;     /* triangles sent in evaluate/commit */
    uint64_t regions;        /* view regions redrawn in evaluate/commit */
    uint64_t region_pixels;  /* their pixels */
    uint64_t commits_cached; /* commits that reused an evaluation's pixels */
    uint64_t views_skipped;  /* (patch, view) pairs not drawn: change hidden or off-screen */
} wk_views_local_stats;
void wk_views_local_get_stats(lm_views *views, wk_views_local_stats *out);

/* Skipping of views where every removed and added triangle lies certainly behind the visible
 * surface (on by default where the device can render the depth image; exact either way). Turning
 * it on re-renders a mesh already set. */
lm_status wk_views_local_set_occlusion(lm_views *views, int on);

/* Copy the current (which = 0) or target (which = 1) luminance image of a view (width*height
 * bytes, bottom row first). */
lm_status wk_views_local_luma(lm_views *views, int which, uint32_t view, uint8_t *out);
/* The colour image of a view from the last full render (RGBA8, width*height*4 bytes, bottom row
 * first): right after create the original's, right after set_mesh the mesh's. */
lm_status wk_views_local_read_rgba(lm_views *views, uint32_t view, uint8_t *out);
/* Coverage of a view in the last full render: out[i] = 1 where a surface was drawn, 0 where the
 * background shows (width*height bytes, bottom row first). LM_E_UNSUPPORTED where the device
 * has no readable depth images. */
lm_status wk_views_local_read_coverage(lm_views *views, uint32_t view, uint8_t *out);

#endif
