/* coordinator/simplify/fp_index.h — which edge-queue entries' footprints may meet a committed
 * change's: per view a grid of pixel cells, each listing the entries whose rectangle in that view
 * covers it (with the rectangle, so most misses are told apart without touching the entry). The
 * image simplifier asks it after every collapse instead of testing every entry of the queue in
 * every view; it then makes the exact test (co_fp_meet) on what the index names, so the entries it
 * marks stale are exactly those the full scan marked.
 *
 * Every entry whose latest footprint (co_fpx_put) meets fp in some view is named by co_fpx_query;
 * others may be named too (older footprints of an entry, far-off rectangles that share a border
 * cell): the caller tests. Rectangles are not clipped (footprint.h): cells past the image's edges
 * gather everything beyond them, so rectangles that meet share a cell. Records of an entry's older
 * footprints are left in place and swept when they outnumber the live ones. */
#ifndef LM_COORDINATOR_SIMPLIFY_FP_INDEX_H
#define LM_COORDINATOR_SIMPLIFY_FP_INDEX_H

#include <stdint.h>

#include "common/error.h"
#include "common/view.h"
#include "coordinator/simplify/footprint.h"

typedef struct co_fpx co_fpx;

/* An empty index over the views of vs (their sizes; vs is read only here). */
lm_status co_fpx_create(const lm_view_set *vs, co_fpx **out);
void co_fpx_destroy(co_fpx *x);

/* Entry i's footprint is fp (vs->count rectangles) from now on; its earlier ones are forgotten.
 * Fails only for memory (the index is then unchanged for i's new footprint: do not use it). */
lm_status co_fpx_put(co_fpx *x, uint32_t i, const co_rect *fp);
/* Entry i has no footprint any more (removed from the queue). */
void co_fpx_drop(co_fpx *x, uint32_t i);

/* hit(ctx, i) for every entry whose latest footprint may meet fp (vs->count rectangles) in some
 * view; an entry may be named more than once. hit may co_fpx_drop entries (then they are named no
 * more), never co_fpx_put. Does not block; allocates nothing. */
void co_fpx_query(co_fpx *x, const co_rect *fp, void (*hit)(void *ctx, uint32_t i), void *ctx);

#endif
