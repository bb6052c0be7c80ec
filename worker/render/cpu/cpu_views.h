/* worker/render/cpu/cpu_views.h — the views backend (common/views_api.h) on lumesh's own CPU
 * rasteriser
 * (`--device cpu`): target and current images rendered by worker/render/cpu/cpu_raster.c and
 * cpu_shade.c, with the same light model and the same integer luminance as the GL renderer, and ΔE
 * of a patch rasterised straight into the exact int64 sum over the pixels it changes (no image
 * read-back). Images are the same bits on every host, compiler and optimisation level.
 *
 * wk_views_local_create(..., "cpu", ...) makes it here; its views_api.h calls and the
 * wk_views_local_* extras go through the shared seam (worker/render/shared/views_seam.h). With
 * occlusion off, every removed triangle is searched and every added one drawn in every view,
 * without depth-tile rejection and without the shortcut for unchanged corners (slower, same
 * images). */
#ifndef LM_WORKER_CPU_VIEWS_H
#define LM_WORKER_CPU_VIEWS_H

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"

/* The CPU rasteriser's name and arithmetic version, as every image it makes records it. */
#define WK_CPU_RASTERISER "lumesh exact rasteriser 1 (fixed point)"

/* The renderer name recorded with every image and energy; its version (WK_CPU_RASTERISER)
 * changes whenever the rasteriser's arithmetic does (images of two versions are not comparable).
 */
#define WK_CPU_RENDERER "cpu: " WK_CPU_RASTERISER

/* Same contract as wk_views_local_create: views first..first+count-1 (count 0 = to the end) of
 * the job's set; a view's images do not depend on which others are held with it. targets: NULL to
 * render the original's targets, else their luminance, one image of the views' size per view
 * held (count of them, in order), copied (the caller keeps the buffer). */
lm_status wk_cpu_views_create(const lm_mesh *original, const lm_view_set *views, uint32_t first,
                              uint32_t count, const uint8_t *targets, lm_views **out);

#endif
