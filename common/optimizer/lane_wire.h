/* common/optimizer/lane_wire.h — the wire form of a lane's request and result (lane_work.h):
 * little-endian, floating-point values as their raw bits (binio.h), so that a lane run in another
 * process merges into the same bytes. A worker op would carry these bytes as one message field.
 * Decoding takes hostile input: truncation, trailing bytes, counts beyond what the bytes can hold
 * or the sanity caps, ids out of range, non-finite parameters are all refused with LM_E_FORMAT and
 * one line (lm_last_error); it never reads past len and allocates at most O(len). */
#ifndef LM_COMMON_OPTIMIZER_LANE_WIRE_H
#define LM_COMMON_OPTIMIZER_LANE_WIRE_H

#include <stddef.h>
#include <stdint.h>

#include "common/optimizer/lane_work.h"

#define LM_LANE_WIRE_VERSION 1u
#define LM_LANE_MAX_NEW_VERTS                                                                      \
    64u /* vertex ids a lane may create above the start's (the merge                               \
           maps at most this many splits) */

/* *buf (malloc'd, caller frees) and *len. */
lm_status lm_lane_request_encode(const lm_lane_request *q, uint8_t **buf, size_t *len);
/* q: initialised (lm_lane_request_init); replaced on success, emptied on failure. */
lm_status lm_lane_request_decode(const uint8_t *buf, size_t len, lm_lane_request *q);

lm_status lm_lane_result_encode(const lm_lane_result *r, uint8_t **buf, size_t *len);
/* n_verts: the request's (vertex ids at most n_verts + LM_LANE_MAX_NEW_VERTS); r: initialised
 * (lm_lane_result_init), cleared and filled on success, cleared on failure. */
lm_status lm_lane_result_decode(const uint8_t *buf, size_t len, uint32_t n_verts,
                                lm_lane_result *r);

#endif
