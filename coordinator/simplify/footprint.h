/* coordinator/simplify/footprint.h — where a change can show in the images: per view, the pixel
 * rectangle that bounds every triangle of a change before and after it (projected corners, one
 * pixel of slack). Rectangles are not clipped to the image, so two changes that share a world
 * point always meet; a corner at or behind the eye makes the whole plane. A change alters the
 * images only inside its footprint, so the ΔE of a candidate whose footprint meets a committed
 * change's in no view is still exact: the image simplifier's staleness test. */
#ifndef LM_COORDINATOR_SIMPLIFY_FOOTPRINT_H
#define LM_COORDINATOR_SIMPLIFY_FOOTPRINT_H

#include <stdint.h>

#include "common/patch.h"
#include "common/view.h"

typedef struct co_rect {
    int32_t x0, y0, x1, y1; /* inclusive pixel bounds; empty when x0 > x1 */
} co_rect;

/* n empty rectangles. */
void co_fp_clear(co_rect *fp, uint32_t n);
/* Grow the rectangle of every view of vs to cover triangle t. */
void co_fp_add_tri(co_rect *fp, const lm_view_set *vs, const lm_tri_data *t);
/* The pieces of co_fp_add_tri: a view's projection of a point (0 at or behind the eye, or not
 * finite); r grown to the pixels of the window box lo..hi (one pixel of slack), or to the whole
 * plane. */
int co_fp_project(const lm_view *v, const float pos[3], float win[2]);
void co_fp_grow_box(co_rect *r, const float lo[2], const float hi[2]);
void co_fp_grow_plane(co_rect *r);
/* Grow a by b (view by view). */
void co_fp_union(co_rect *a, const co_rect *b, uint32_t n);
/* 1 when the two footprints meet in some view. */
int co_fp_meet(const co_rect *a, const co_rect *b, uint32_t n);

#endif
