/* worker/render/shared/image_store.h — the per-view luminance images of a view set: target Ŷ (the
 * original's) and current Y (the mesh's), 8-bit integer luminance per pixel, and the exact int64
 * energy sums E_h = Σ (Ŷ - Y)² kept current as regions are committed. Also ΔE over a region and the
 * oracle's blurred difference images. Plain memory, no GL: testable on its own.
 *
 * Images are stored row by row from the BOTTOM row up (GL window order), so pixel (x, y) of view h
 * is at [h][y * width + x] with y counted from the bottom; a region is a wk_rect in those
 * coordinates, its pixels packed row by row (bottom first) with stride = its width. */
#ifndef LM_WORKER_IMAGE_STORE_H
#define LM_WORKER_IMAGE_STORE_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/image.h"
#include "common/view.h"
#include "worker/render/shared/buckets.h"

void wk_luma_from_rgba(const uint8_t *rgba, size_t n_pixels, uint8_t *out);

typedef struct wk_image_store wk_image_store;

lm_status wk_image_store_create(uint32_t n_views, int width, int height, wk_image_store **out);
void wk_image_store_destroy(wk_image_store *s);

/* Whole images (width*height bytes, bottom row first). Setting either recomputes E_h. */
void wk_image_store_set_target(wk_image_store *s, uint32_t view, const uint8_t *y);
void wk_image_store_set_current(wk_image_store *s, uint32_t view, const uint8_t *y);
const uint8_t *wk_image_store_target(const wk_image_store *s, uint32_t view);
const uint8_t *wk_image_store_current(const wk_image_store *s, uint32_t view);

/* Σ over region r of (Ŷ - Y')² - (Ŷ - Y)², where Y' = `region` (packed pixels of r). */
int64_t wk_image_store_region_delta(const wk_image_store *s, uint32_t view, const wk_rect *r,
                                    const uint8_t *region);
/* Copy `region` into the current image over r and update E_h by the region's delta. */
void wk_image_store_commit_region(wk_image_store *s, uint32_t view, const wk_rect *r,
                                  const uint8_t *region);

/* Set the current luminance of pixels idx[i] (y * width + x, each at most once) to y[i] and
 * update E_h exactly. */
void wk_image_store_commit_pixels(wk_image_store *s, uint32_t view, const uint32_t *idx,
                                  const uint8_t *y, size_t n);

/* Σ of E_h over the views (total) and each E_h (per_view, n_views entries); either may be NULL. */
void wk_image_store_energies(const wk_image_store *s, int64_t *total, int64_t *per_view);

/* E_h as kept, and recomputed from scratch (for checks). */
int64_t wk_image_store_energy(const wk_image_store *s, uint32_t view);
int64_t wk_image_store_energy_recompute(const wk_image_store *s, uint32_t view);

/* A counter that changes whenever the depth image of view does (0 without depth images): results
 * of the hidden tests below stay true while it stays the same. */
uint32_t wk_image_store_depth_version(const wk_image_store *s, uint32_t view);

/* Depth images (optional): per view the window depth of the visible surface (1 where background),
 * kept alongside the current images to skip views where a change is certainly hidden. */
lm_status wk_image_store_enable_depth(wk_image_store *s);
int wk_image_store_has_depth(const wk_image_store *s);
void wk_image_store_set_depth(wk_image_store *s, uint32_t view, const float *z);
void wk_image_store_commit_depth(wk_image_store *s, uint32_t view, const wk_rect *r,
                                 const float *region);
/* 1 when every pixel of r holds a surface nearer than zmin - eps: a triangle whose fragments lie
 * in r at depths >= zmin cannot be visible there. */
int wk_image_store_hidden(const wk_image_store *s, uint32_t view, const wk_rect *r, float zmin,
                          float eps);
/* The same over the pixels a triangle's footprint may touch: those whose centre lies within
 * WK_PIXEL_SLACK of the projected triangle (within its rectangle); the whole rectangle if not
 * projected. */
int wk_image_store_hidden_tri(const wk_image_store *s, uint32_t view, const wk_footprint *f,
                              float eps);
/* The same over those of the footprint's pixels that lie in clip (1 when none does). */
int wk_image_store_hidden_tri_in(const wk_image_store *s, uint32_t view, const wk_footprint *f,
                                 const wk_rect *clip, float eps);
/* The same, and when it answers 0 after finding a pixel of the footprint in clip that is not
 * hidden, that pixel in witness (else -1, -1). */
int wk_image_store_hidden_tri_witness(const wk_image_store *s, uint32_t view, const wk_footprint *f,
                                      const wk_rect *clip, float eps, int witness[2]);

/* The oracle's image: out[y*width+x] = Σ over the (2 radius + 1)² window around (x, y), clipped to
 * the image, of (Ŷ - Y)². radius in 0..64; out has width*height entries. */
lm_status wk_image_store_blurred_diff(const wk_image_store *s, uint32_t view, int radius,
                                      uint32_t *out);

#define WK_ORACLE_RADIUS 4 /* the oracle's blur radius (a 9x9 window) */

/* The oracle's potentials: for each world point the sum over the views (views->count = n_views,
 * of this store's size) of its blurred difference image (radius) at the point's pixel, 0 where it
 * projects outside or behind the eye. */
lm_status wk_image_store_potentials(const wk_image_store *s, const lm_view_set *views, int radius,
                                    const float (*points)[3], size_t n, int64_t *out);

#endif
