/* proto/wire.h — messages on the wire: one ZeroMQ message is one Msg of proto/lumesh.proto (a
 * local worker's link carries the same frames: proto/stream.h).
 *
 * Limits come first: sockets refuse frames above LM_WIRE_MAX_FRAME before any byte is decoded
 * (ZMQ_MAXMSGSIZE), and decoding allocates at most LM_WIRE_DECODE_BUDGET(frame) bytes (protobuf-c
 * has no limit of its own: an empty sub-message costs 2 bytes on the wire and dozens in memory).
 * A frame that does not decode, or decodes to no known body, is refused with a one-line message;
 * the caller drops the peer that sent it, never the job.
 *
 * Ownership: lm_wire_decode's message is freed with lm_wire_in_free. lm_wire_send packs into a
 * buffer of its own and does not keep the message. Sockets belong to the caller. */
#ifndef LM_PROTO_WIRE_H
#define LM_PROTO_WIRE_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "proto/lumesh.pb-c.h"

#define LM_WIRE_VERSION                                                                            \
    6u /* 2: SetSurface, Tri.same; 3: RunLane; 4: RunLane.start_delta;                             \
          5: RunLane.queue, .queue_delta; 6: Assign.targets, lm_mesh_hash 8 bytes at a time        \
          (start_hash) */
#define LM_WIRE_MAX_FRAME (64u << 20) /* bytes of one frame */
#define LM_WIRE_MAX_IDENTITY 256u     /* bytes of a ROUTER routing id */
#define LM_WIRE_CHUNK (4u << 20)      /* bytes of asset data per Asset message */
#define LM_WIRE_RENDERER_ID_CHARS 16  /* hex digits of a renderer's fingerprint (its probe) */
#define LM_WIRE_DECODE_BUDGET(n) (16 * (size_t)(n) + (1u << 20))

typedef Lumesh__Msg lm_msg;

/* A message with header fields and one body (a pointer to the body's struct, e.g. Lumesh__Hello*,
 * of the kind `body_case` names). */
void lm_wire_msg_init(lm_msg *m, uint64_t req, uint64_t seq, Lumesh__Msg__BodyCase body_case,
                      void *body);

/* The socket options every lumesh socket gets: the frame cap, no lingering on close, and (for a
 * ROUTER) an error rather than a silent drop when sending to a peer that is gone. */
lm_status lm_wire_socket_setup(void *sock, int is_router);

/* Pack and send one message; with a routing id (ROUTER sockets), to that peer. Blocking only as
 * far as ZeroMQ's queue is full (never on the peer). */
lm_status lm_wire_send(void *sock, const void *id, size_t id_len, const lm_msg *m);

/* One received frame (and, on a ROUTER, the routing id of its sender). */
typedef struct lm_wire_frame {
    uint8_t id[LM_WIRE_MAX_IDENTITY];
    size_t id_len;
    const uint8_t *data;
    size_t size;
    void *zmsg_;                                                  /* zmq_msg_t storage (internal) */
    void (*release_)(void *owner, const struct lm_wire_frame *f); /* a frame of another source */
    void *owner_;
} lm_wire_frame;

/* Wait up to timeout_ms (-1 = forever, 0 = poll) for a frame. LM_OK with f->size > 0 when one
 * came; LM_OK with f->data == NULL on timeout. Release with lm_wire_frame_release. */
lm_status lm_wire_recv(void *sock, int is_router, int timeout_ms, lm_wire_frame *f);
void lm_wire_frame_release(lm_wire_frame *f);

/* A decoded message and the bounded allocator that holds it (the struct must stay where it is
 * while msg is used: the allocator points into it). */
typedef struct lm_wire_in {
    lm_msg *msg;
    size_t budget_left_;
    ProtobufCAllocator alloc_;
} lm_wire_in;

/* Decode a frame (bounded allocation); LM_E_FORMAT for anything malformed or with no body. The
 * frame may be released right after. Free with lm_wire_in_free (also after a failure). */
lm_status lm_wire_decode(const uint8_t *data, size_t size, lm_wire_in *in);
void lm_wire_in_free(lm_wire_in *in);

/* Name of a message body, for logs ("evaluate", ...; "none"). */
const char *lm_wire_body_name(const lm_msg *m);
const char *lm_wire_case_name(Lumesh__Msg__BodyCase c);

#endif
