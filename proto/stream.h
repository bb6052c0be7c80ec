/* proto/stream.h — the same frames as a ZeroMQ socket carries (proto/wire.h), over a byte stream:
 * the Unix socketpair between a coordinator and a worker process it started itself.
 *
 * Why not ZeroMQ there: a message over ZeroMQ crosses an I/O thread on each side, four thread
 * wake-ups per round trip, which on a machine whose cores are all rendering costs far more than
 * the message (measured by tests/bench/bench_scaling: 198 us over ipc against 28 us over a plain
 * Unix socket, on this 2-core machine). Workers that connect by address keep ZeroMQ (CURVE,
 * reconnection, many peers on one socket).
 *
 * On the wire: each frame is its length (4 bytes, little-endian) then its bytes. A length of 0 or
 * above LM_WIRE_MAX_FRAME is refused before anything is read into memory for it.
 *
 * Blocking: none of these calls blocks. lm_stream_put queues a frame and writes what the socket
 * takes at once; the rest goes with lm_stream_flush when the descriptor is writable (poll for
 * POLLOUT while lm_stream_pending says so). lm_stream_fill reads what is there.
 *
 * Failure: LM_E_IO when the peer has gone (end of stream, a reset) or the socket fails; LM_E_FORMAT
 * when the peer broke the framing. Either way the stream is of no further use: close it.
 *
 * Ownership: the stream owns its descriptor from lm_stream_open on, and closes it in
 * lm_stream_close. A frame from lm_stream_next points into the stream's buffer until it is
 * released (lm_wire_frame_release); one frame at a time is out. */
#ifndef LM_PROTO_STREAM_H
#define LM_PROTO_STREAM_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "proto/wire.h"

#define LM_STREAM_HEADER 4u

typedef struct lm_stream {
    int fd; /* -1 when closed */
    uint8_t *in;
    size_t in_off, in_len, in_cap; /* unread bytes are in[in_off, in_len) */
    uint8_t *out;
    size_t out_off, out_len, out_cap; /* unsent bytes are out[out_off, out_len) */
    int frame_out;                    /* a frame from lm_stream_next is not released yet */
} lm_stream;

/* Take descriptor fd (made non-blocking). LM_E_IO if it cannot be. */
lm_status lm_stream_open(lm_stream *s, int fd);
void lm_stream_close(lm_stream *s);

/* Queue one frame of n bytes (1..LM_WIRE_MAX_FRAME, else LM_E_RANGE) and write what goes now. */
lm_status lm_stream_put(lm_stream *s, const void *data, size_t n);
/* Queue message m packed as one frame (no copy of its own), and write what goes now. */
lm_status lm_stream_put_msg(lm_stream *s, const lm_msg *m);
/* Write what the socket takes now of what is queued. */
lm_status lm_stream_flush(lm_stream *s);
/* Bytes queued and not yet written. */
size_t lm_stream_pending(const lm_stream *s);

/* Read what the socket has now. LM_E_IO at the end of the stream (after the frames before it were
 * read: take them with lm_stream_next first). */
lm_status lm_stream_fill(lm_stream *s);
/* The next whole frame read, if any: LM_OK with f->data set (the frame's id is left empty), LM_OK
 * with f->data NULL when none is complete yet, LM_E_FORMAT when the peer sent a bad length. */
lm_status lm_stream_next(lm_stream *s, lm_wire_frame *f);

#endif
