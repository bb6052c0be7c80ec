/* worker/render/gl/render.h — the OpenGL ES 3 renderer of a view set (paper §4.1): one light at the
 * viewer, Gouraud shading of per-corner normals (not normalised: the optimizer may scale them,
 * two-sided: |n·l|), colour = texture(uv) × vertex colour × material diffuse × (0.15 + 0.85 |n·l|),
 * clamped, on a 50% grey background (128/255), depth-tested (GL_LESS).
 *
 * All views of a set live in one atlas framebuffer (RGBA8 + depth 24), each view in its own fixed
 * tile, the tile it has in the layout of the job's whole view set; a view is ALWAYS drawn into its
 * own tile with the same viewport (which clips), so drawing a region of it does exactly the
 * arithmetic of a full render there. Several atlases of identical layout may exist (scratch space
 * for several patches in one batch). Triangles come as a non-indexed stream uploaded once per
 * batch; a draw paints a range of it (ascending triangle ids, consecutive triangles of one material
 * forming one draw call) into one view's tile.
 *
 * Regions: a batch first clears all its regions (background grey at depth 1) with ONE draw of
 * quads (a scissored glClear per region costs on Mesa as much as a small draw plus a state save
 * and restore), then draws each region with the scissor set to it.
 *
 * The GL context must be current on the calling thread for every call. */
#ifndef LM_WORKER_RENDER_H
#define LM_WORKER_RENDER_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/mesh.h"
#include "common/patch.h"
#include "common/view.h"
#include "worker/render/shared/buckets.h"

#define WK_RENDER_TABLES 2 /* material tables: 0 = target (original), 1 = current model */
#define WK_RENDER_MAX_ATLASES 16
#define WK_BACKGROUND 128 /* background grey, in 8-bit units */

typedef struct wk_renderer wk_renderer;

/* The renderer of `views`, which are the job's views deal.first, deal.first + deal.stride, ...
 * (deal.count = views->count) of a job of `total` views: each is drawn in the tile it has in the
 * job's atlas layout (see layout_tiles in render.c), so its pixels do not depend on how the
 * job's views are shared out. */
lm_status wk_renderer_create(const lm_view_set *views, lm_view_deal deal, uint32_t total,
                             wk_renderer **out);
void wk_renderer_destroy(wk_renderer *r);

/* Material table `table`: copies the diffuse colours and uploads the textures (RGBA8, mipmapped,
 * repeating; uv (0,0) is the bottom-left of the image). */
lm_status wk_renderer_set_materials(wk_renderer *r, int table, const lm_material *mats, uint32_t n);
uint32_t wk_renderer_material_count(const wk_renderer *r, int table);

/* Replace the stream with the corners of n triangles (3 per triangle). */
lm_status wk_renderer_upload(wk_renderer *r, const lm_corner *corners, size_t n_tris);

/* Atlases (< WK_RENDER_MAX_ATLASES) are created on first use. */
/* Clear every tile of an atlas to background grey at depth 1. */
lm_status wk_renderer_clear_all(wk_renderer *r, uint32_t atlas);

/* Clear rects[i] of view views[i] to background grey at depth 1, for all i (one draw). */
lm_status wk_renderer_clear_regions(wk_renderer *r, uint32_t atlas, const uint32_t *views,
                                    const wk_rect *rects, size_t n);

typedef struct wk_draw {
    uint32_t atlas, view;
    size_t first, count; /* stream triangles, in ascending id order */
    wk_rect rect;        /* the pixels of the view to paint (the scissor box) */
} wk_draw;

/* materials[i] is the material (in `table`) of stream triangle i. */
lm_status wk_renderer_draw(wk_renderer *r, int table, const wk_draw *d, const uint32_t *materials);

/* Read the RGBA8 pixels of rect of a view (rows bottom first, 4 * width bytes each). The first read
 * after draws waits for them: read after drawing everything of a batch. */
lm_status wk_renderer_read(wk_renderer *r, uint32_t atlas, uint32_t view, const wk_rect *rect,
                           uint8_t *rgba);

/* Whether atlases carry a depth image (the winning fragments' window depth in an R32F colour
 * attachment; needs float render targets, as GLES 3.2 and EXT_color_buffer_float have), and
 * reading it: rect of a view, rows bottom first, one float per pixel. */
int wk_renderer_has_depth_images(wk_renderer *r);
lm_status wk_renderer_read_depth(wk_renderer *r, uint32_t atlas, uint32_t view, const wk_rect *rect,
                                 float *depth);
/* Whether draws and region clears into an atlas also write its depth image (on when created).
 * Off, every fragment writes one render target less; the depth image of what is drawn then is
 * stale and must not be read. Colours and the depth test are the same either way. */
lm_status wk_renderer_write_depth_images(wk_renderer *r, uint32_t atlas, int on);

/* GL errors since the last check, as an lm_status naming `what`. */
lm_status wk_renderer_check(wk_renderer *r, const char *what);

#endif
