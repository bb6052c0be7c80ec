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

#define LM_LANE_WIRE_VERSION 2u /* 2: lm_mesh_hash mixes 8 bytes at a time */
#define LM_LANE_MAX_NEW_VERTS                                                                      \
    64u /* vertex ids a lane may create above the start's (the merge                               \
           maps at most this many splits) */

/* *buf (malloc'd, caller frees) and *len. */
lm_status lm_lane_request_encode(const lm_lane_request *q, uint8_t **buf, size_t *len);
/* q: initialised (lm_lane_request_init); replaced on success, emptied on failure. */
lm_status lm_lane_request_decode(const uint8_t *buf, size_t len, lm_lane_request *q);

/* A request's bytes are its head (everything but the collapse queue) followed by the queue's
 * section (u32 count, 24-byte entries sorted by edge): lm_lane_request_encode's bytes are
 * lm_lane_request_encode_head's followed by lm_lane_queue_encode's of the request's queue. Every
 * lane of a group has the same queue: --lanes remote sends it once per group and worker. */
lm_status lm_lane_request_encode_head(const lm_lane_request *q, uint8_t **buf, size_t *len);
/* The head alone (trailing bytes refused): q replaced with an empty queue (NULL, 0), emptied on
 * failure. */
lm_status lm_lane_request_decode_head(const uint8_t *buf, size_t len, lm_lane_request *q);
lm_status lm_lane_queue_encode(const lm_cq_entry *e, uint32_t n, uint8_t **buf, size_t *len);
/* A queue's section: entries whose vertices are below n_verts, strictly sorted by edge, into *e
 * (malloc'd, caller frees; NULL on failure) and *n. */
lm_status lm_lane_queue_decode(const uint8_t *buf, size_t len, uint32_t n_verts, lm_cq_entry **e,
                               uint32_t *n);

lm_status lm_lane_result_encode(const lm_lane_result *r, uint8_t **buf, size_t *len);
/* n_verts: the request's (vertex ids at most n_verts + LM_LANE_MAX_NEW_VERTS); r: initialised
 * (lm_lane_result_init), cleared and filled on success, cleared on failure. */
lm_status lm_lane_result_decode(const uint8_t *buf, size_t len, uint32_t n_verts,
                                lm_lane_result *r);

#endif
