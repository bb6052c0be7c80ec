/* proto/stream.h — the same frames as a ZeroMQ socket carries (proto/wire.h), over a byte stream:
 * the Unix socketpair between a coordinator and a worker process it started itself.
 *
 * Why not ZeroMQ there: a message over ZeroMQ crosses an I/O thread on each side, four thread
 * wake-ups per round trip, which on a machine whose cores are all rendering costs far more than
 * the message (tests/bench/PERFORMANCE.md: round trips, from tests/bench/bench_scaling). Workers
 * that connect by address keep ZeroMQ (CURVE, reconnection, many peers on one socket).
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
 * The shared-memory lane (proto/ring.h, lm_stream_share): with it, a frame of up to
 * LM_RING_MAX_FRAME goes through the ring when the ring has room and the peer has taken every frame
 * sent over the socket before it; every other frame goes over the socket. The reader takes the
 * ring's frames first, so the order is the order sent. A reader that goes to sleep on the socket
 * says so first (lm_stream_sleep); a writer that then puts a frame in the ring also sends a wake
 * mark over the socket (a length of LM_STREAM_WAKE, no bytes), which lm_stream_next passes over.
 * Waiting for frames means waiting for both: lm_stream_ready, and the descriptor (ends, the
 * socket's frames, wake marks).
 *
 * Ownership: the stream owns its descriptor from lm_stream_open on, and closes it in
 * lm_stream_close (with its mapping of the shared lane). A frame from lm_stream_next points into
 * the stream's buffer until it is released (lm_wire_frame_release); one frame at a time is out. */
#ifndef LM_PROTO_STREAM_H
#define LM_PROTO_STREAM_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "proto/ring.h"
#include "proto/wire.h"

#define LM_STREAM_HEADER 4u
#define LM_STREAM_WAKE 0xffffffffu /* a length that is a wake mark (see above) */

typedef struct lm_stream {
    int fd; /* -1 when closed */
    uint8_t *in;
    size_t in_off, in_len, in_cap; /* unread bytes are in[in_off, in_len) */
    uint8_t *out;
    size_t out_off, out_len, out_cap; /* unsent bytes are out[out_off, out_len) */
    int frame_out;                    /* a frame from lm_stream_next is not released yet */
    lm_rings ring;                    /* the shared lane; ring.map NULL without one */
    uint64_t sent, taken;             /* socket frames written and taken (wake marks included) */
    uint8_t *ring_in;                 /* the last frame taken from the ring */
    size_t ring_in_cap;
} lm_stream;

/* Take descriptor fd (made non-blocking). LM_E_IO if it cannot be. */
lm_status lm_stream_open(lm_stream *s, int fd);
void lm_stream_close(lm_stream *s);
/* Add the shared lane: region shm_fd (proto/ring.h; closed whatever the result), mapped as side
 * 0 (the coordinator, which made it) or 1 (the worker). Before any frame is sent or read. */
lm_status lm_stream_share(lm_stream *s, int shm_fd, int side);

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
/* Whether lm_stream_next has a frame (or a failure) to give without reading the socket. */
int lm_stream_ready(const lm_stream *s);
/* Before sleeping on the descriptor: says so to the writer, and returns whether a frame came
 * through the shared lane meanwhile (then take it instead of sleeping). lm_stream_awake after. */
int lm_stream_sleep(lm_stream *s);
void lm_stream_awake(lm_stream *s);
/* The next whole frame read, if any: LM_OK with f->data set (the frame's id is left empty), LM_OK
 * with f->data NULL when none is complete yet, LM_E_FORMAT when the peer sent a bad length. */
lm_status lm_stream_next(lm_stream *s, lm_wire_frame *f);

#endif
