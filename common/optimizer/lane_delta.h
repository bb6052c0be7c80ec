/* common/optimizer/lane_delta.h — a group's start mesh record (lane_start.h), or its collapse
 * queue (lane_wire.h), as a delta against an earlier one (--lanes remote: a worker that holds the
 * previous group's start and queue is sent what changed, not the whole record).
 *
 * The delta is little-endian: magic "LNDL", base length, result length, op count, then ops. An op
 * is {skip, copy, literal} (u32 each) and `literal` bytes: the base cursor moves on `skip` bytes,
 * `copy` bytes of the base from there are appended (the cursor moves past them), then the literal
 * bytes. The base cursor only moves forward and never past the base, so the result holds at most
 * the base's bytes plus the delta's: applying it allocates O(base + delta). The encoder compares
 * the record section by section (head, positions, vertex flags, wedges, wedge flags, triangles,
 * triangle flags), so arrays that grew (a split's new slots) do not shift the rest. */
#ifndef LM_COMMON_OPTIMIZER_LANE_DELTA_H
#define LM_COMMON_OPTIMIZER_LANE_DELTA_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

/* The delta that turns base into cur: *out (malloc'd, caller frees), *n_out. Either may be any
 * bytes (records are compared by section when both are well-formed records). Fails only for
 * memory. */
lm_status lm_lane_delta_encode(const uint8_t *base, size_t n_base, const uint8_t *cur, size_t n_cur,
                               uint8_t **out, size_t *n_out);

/* The same for a collapse queue's section (lane_wire.h: a count, then 24-byte entries sorted by
 * edge): the two are walked in edge order, so entries added or removed do not shift the rest
 * (lm_lane_delta_apply applies it). Other bytes: as lm_lane_delta_encode. Fails only for memory. */
lm_status lm_lane_queue_delta_encode(const uint8_t *base, size_t n_base, const uint8_t *cur,
                                     size_t n_cur, uint8_t **out, size_t *n_out);

/* base + delta -> *out (malloc'd, caller frees), *n_out. Hostile input: a delta made for a base
 * of another length, truncated, with trailing bytes, ops that move past the base or a result of
 * another length than it names is refused with LM_E_FORMAT and one line (lm_last_error). */
lm_status lm_lane_delta_apply(const uint8_t *base, size_t n_base, const uint8_t *delta,
                              size_t n_delta, uint8_t **out, size_t *n_out);

#endif
