/* worker/render/gl/gl_views.h — the views backend (common/views_api.h) on an EGL context: target
 * images of the original rendered once into atlases, the current images of the mesh kept up to
 * date through committed patches, patches evaluated incrementally (triangle buckets, scissored
 * redraw of the affected region of every view, one readback per batch). Made through
 * wk_views_local_create (worker/render/views_local.h), which checks the views and the original
 * first; the call below is its GL side. Its views_api.h calls and the wk_views_local_* extras go
 * through the shared seam (worker/render/shared/views_seam.h); occlusion is LM_E_UNSUPPORTED
 * where the device cannot render depth images. */
#ifndef LM_WORKER_RENDER_GL_GL_VIEWS_H
#define LM_WORKER_RENDER_GL_GL_VIEWS_H

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"
#include "worker/render/gl/gl_context.h"

/* Views `views` (this backend's own, in order) that sit at the positions `deal` gives among a
 * job's `total` views (the atlas places them as a backend holding all of them would, so splits
 * agree), rendered on ctx, which the views own from now on (destroyed here on failure). targets:
 * NULL to render the original's targets, else their luminance, one image of the views' size per
 * view in `views`' order, copied (the caller keeps the buffer). */
lm_status wk_gl_views_create(const lm_mesh *original, const lm_view_set *views, lm_view_deal deal,
                             uint32_t total, wk_gl_context *ctx, const uint8_t *targets,
                             lm_views **out);

#endif
