/* coordinator/simplify/fp_corners.h — a change's footprint from its distinct corners: the
 * triangles of a change (a candidate's placements and the triangles they remove) share most of
 * their corners, so each distinct point (bit for bit) is projected once per view instead of once
 * per triangle. The rectangles are exactly those co_fp_add_tri gives triangle by triangle: where
 * every point of a view projects, the box of all points (floor, ceil and the slack are monotonic,
 * so the union of the triangles' boxes is the box of their points); where one does not, that view
 * is done triangle by triangle from the projected points. */
#ifndef LM_COORDINATOR_SIMPLIFY_FP_CORNERS_H
#define LM_COORDINATOR_SIMPLIFY_FP_CORNERS_H

#include <stdint.h>

#include "common/error.h"
#include "coordinator/simplify/footprint.h"

typedef struct co_fp_corners {
    float (*pos)[3]; /* the distinct points */
    float (*win)[2]; /* their projection in the view being done */
    uint8_t *ok;     /* 1 where it projects */
    uint32_t n_pos, cap_pos;
    uint32_t (*tri)[3]; /* each triangle's points */
    uint32_t n_tri, cap_tri;
    uint32_t *slot; /* hash of the points: index + 1, 0 empty */
    uint32_t cap_slot;
} co_fp_corners;

void co_fp_corners_init(co_fp_corners *c);
void co_fp_corners_free(co_fp_corners *c);
/* No triangle. */
void co_fp_corners_reset(co_fp_corners *c);
lm_status co_fp_corners_add_tri(co_fp_corners *c, const lm_tri_data *t);
/* Grow fp (one rectangle per view of vs) by every triangle added since the reset. */
void co_fp_corners_apply(co_fp_corners *c, co_rect *fp, const lm_view_set *vs);

#endif
