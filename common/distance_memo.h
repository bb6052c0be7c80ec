/* common/distance_memo.h — squared distances from points to the original surface,
 * remembered by point. The geometric term asks for the same points again and again: an edge's
 * midpoint belongs to both triangles beside it, a patch's outer edges stay put while its vertex
 * is tried at one place after another, and a commit prices the triangles its evaluation priced.
 * A hit returns the very double lm_bvh_closest_sq gave for those exact bits, so no result
 * depends on what the memo holds. */
#ifndef LM_COMMON_DISTANCE_MEMO_H
#define LM_COMMON_DISTANCE_MEMO_H

#include <stdint.h>

#include "common/bvh.h"
#include "common/error.h"

typedef struct lm_distance_memo lm_distance_memo;

/* 2^log2_slots remembered points (direct-mapped: a newer point takes an older one's slot) over
 * bvh, which must outlive the memo. */
lm_status lm_distance_memo_create(const lm_bvh *bvh, uint32_t log2_slots, lm_distance_memo **out);
void lm_distance_memo_destroy(lm_distance_memo *m);

/* lm_bvh_closest_sq(bvh, q), from the memo when q's bits were asked for and are still held. */
double lm_distance_memo_sq(lm_distance_memo *m, const double q[3]);

#endif
