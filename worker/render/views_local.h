/* worker/render/views_local.h — the in-process views (common/views_api.h), the one header through
 * which the coordinator and the worker process make them: a --device spec picks the backend, the
 * GL one on an EGL context (worker/render/gl/gl_views.h) or lumesh's exact CPU rasteriser
 * (worker/render/cpu/cpu_views.h). Both render the target images of the original once, keep the
 * current images of the mesh set with set_mesh up to date through committed patches, and evaluate
 * patches incrementally. */
#ifndef LM_WORKER_VIEWS_LOCAL_H
#define LM_WORKER_VIEWS_LOCAL_H

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"
#include "worker/render/shared/views_stats.h"

/* Views first..first+count-1 of the job's view set `views` (count 0 = to the end); each is
 * rendered exactly as it is in a backend that holds all of them (render.h), so splits agree.
 * device_spec: "auto", "cpu", "egl:N" or "host" (NULL = "auto"; "cpu", and "auto" without a GPU,
 * make worker/render/cpu/cpu_views.h's backend). The original's materials (diffuse and
 * textures) form the material table that triangle records' material ids index, for the target and,
 * unless set_materials says otherwise, for the current mesh. On success *out holds the target
 * images; set_mesh must be called before evaluate/commit/energy. The coordinator makes these
 * through co_views_create (coordinator/views/views.h); the worker process calls this directly. */
lm_status wk_views_local_create(const lm_mesh *original, const lm_view_set *views, uint32_t first,
                                uint32_t count, const char *device_spec, lm_views **out);
/* The same for the views of `deal` (view.h), e.g. every G-th: what a worker serves. */
lm_status wk_views_local_create_dealt(const lm_mesh *original, const lm_view_set *views,
                                      lm_view_deal deal, const char *device_spec, lm_views **out);

/* The same without rendering the targets: `targets` holds the luminance of every view of `views`
 * (views->count images of the views' size, view after view, rows bottom first: what a backend
 * holding them renders, e.g. a proto/asset.h targets asset), and the views of `deal` take theirs
 * from it (copied; the caller keeps the buffer). The views are then exactly those the calls above
 * make, for the same targets. */
lm_status wk_views_local_create_given(const lm_mesh *original, const lm_view_set *views,
                                      lm_view_deal deal, const char *device_spec,
                                      const uint8_t *targets, lm_views **out);

/* 1 if views was made by wk_views_local_create, on any device (the two calls below need such an
 * object). */
int wk_views_is_local(const lm_views *views);

/* LM_E_UNSUPPORTED (zeroed stats) for other kinds of views. */
lm_status wk_views_local_get_stats(lm_views *views, wk_views_local_stats *out);

/* Skipping of views where every removed and added triangle lies certainly behind the visible
 * surface (on by default where the device can render the depth image; exact either way). Turning
 * it on re-renders a mesh already set. */
lm_status wk_views_local_set_occlusion(lm_views *views, int on);

#endif
