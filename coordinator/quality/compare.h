/* coordinator/quality/compare.h — models judged against their original through the in-process
 * renderer: image energies over a view set (e.g. the 24 held-out views), and a picture grid with
 * one row per view and the columns original | model 1 | model 2 ... for before/after images. Each
 * model is drawn with its own materials (as loaded from its file). */
#ifndef LM_COORDINATOR_COMPARE_H
#define LM_COORDINATOR_COMPARE_H

#include <stdint.h>
#include <stdio.h>

#include "common/image.h"
#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"

#define CO_COMPARE_GAP 4 /* pixels between the cells of a grid */

/* Silhouette coverage of a model against the original, summed over all views and pixels. */
typedef struct co_coverage {
    int measured;         /* 0 where the device has no depth images: the counts are all zero */
    uint64_t original_px; /* pixels where the original shows a surface */
    uint64_t missing_px;  /* ... and the model shows the background: holes, cracks, shrinkage */
    uint64_t extra_px;    /* the model shows a surface where the original shows background */
    uint64_t cracks_px;   /* missing pixels well inside the original's silhouette (at least
                             co_crack_margin pixels from its background): holes and cracks
                             between parts rather than a thinner outline */
} co_coverage;

/* The crack margin for images of side `width`: 2 pixels at 256, growing with the size. */
int co_crack_margin(int width);

/* Coverage masks of every view from the views' last full render (the original's right after
 * the views are made, the model's right after set_mesh): n_views * width * height bytes,
 * caller frees *masks. LM_E_UNSUPPORTED where the device has no depth images. */
lm_status co_coverage_masks(lm_views *views, uint8_t **masks);
/* Compare two mask sets of `views` images of w x h pixels. */
lm_status co_coverage_compare(const uint8_t *original, const uint8_t *model, int w, int h,
                              uint32_t views, co_coverage *out);

/* energy[i] = E(models[i]) against the original over `views`; per_view (may be NULL) receives
 * model i's energy in view h at [i * views->count + h]; cov (may be NULL) each model's silhouette
 * coverage; renderer (may be NULL, 128 bytes) the renderer's description. */
lm_status co_compare_energies(const lm_mesh *original, const lm_view_set *views,
                              const char *device_spec, const lm_mesh *const *models, uint32_t n,
                              int64_t *energy, int64_t *per_view, co_coverage *cov, char *renderer);

/* `{"original_px": ..., "missing_px": ..., "extra_px": ..., "cracks_px": ...}`, or `null` when
 * not measured. */
void co_coverage_print_json(FILE *fp, const co_coverage *c);

/* A window of one view's image (pixels, x right, y down from the top row). */
typedef struct co_crop {
    uint32_t view;
    int x, y, w, h;
} co_crop;

/* A grid image: one row per view (or, with crop, the single window crop), 1 + n columns (the
 * original first), CO_COMPARE_GAP pixels of dark grey between cells. Caller destroys *out. */
lm_status co_compare_grid(const lm_mesh *original, const lm_view_set *views,
                          const char *device_spec, const lm_mesh *const *models, uint32_t n,
                          const co_crop *crop, lm_image **out);

/* The side x side window, over all views, with the most of `model`'s crack pixels (see
 * co_coverage.cracks_px): *out and the number of those pixels in it. */
lm_status co_compare_find_cracks(const lm_mesh *original, const lm_view_set *views,
                                 const char *device_spec, const lm_mesh *model, int side,
                                 co_crop *out, uint64_t *cracks);

#endif
