/* proto/ring.h — the shared-memory lane of a local link (proto/stream.h): two single-producer,
 * single-consumer rings of frames in one memory region that a coordinator and a worker process it
 * started both map, one ring each way.
 *
 * Why: a round trip over the socketpair costs four system calls (two sends, two receives) even
 * when both sides are awake and spinning: 4.6 us here against 0.6 us through shared memory, for a
 * 2.7 kB request and a short answer (two processes bouncing them, on this 2-core machine). An
 * evaluation is one round trip per worker, and the coordinator makes one to every worker in turn.
 *
 * Contract:
 * - Creation: lm_ring_create makes the region (a memfd, zeroed, close-on-exec) and returns its
 *   descriptor, which the other process is given; each side maps it with lm_ring_map, side 0 the
 *   process that created it. The mapping lives until lm_ring_unmap; the descriptor is closed by
 *   lm_ring_map.
 * - Blocking: nothing here blocks or waits. lm_ring_room says "no room" (NULL) instead.
 * - Failure: a peer that wrote positions or lengths no writer could (a bug, or a process that
 *   scribbled on the region) makes lm_ring_take fail with LM_E_FORMAT; the link is then of no use.
 *   Lengths are read once from shared memory and every frame is copied out before it is used, so a
 *   peer that writes while it is read cannot make the reader step outside its buffers.
 * - Ownership: frames are copied into the ring (lm_ring_room, then lm_ring_publish) and out of it
 *   (lm_ring_take into a buffer the caller owns). */
#ifndef LM_PROTO_RING_H
#define LM_PROTO_RING_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

#define LM_RING_BYTES (256u << 10)    /* each way */
#define LM_RING_MAX_FRAME (64u << 10) /* a larger frame goes over the socket */

typedef struct lm_ring_shared lm_ring_shared; /* one direction, in the shared region */

typedef struct lm_rings {
    void *map;
    size_t map_len;
    lm_ring_shared *tx, *rx; /* what this side writes, and reads */
    uint64_t tx_head;        /* this side's own copy of tx's write position */
    uint64_t tx_next;        /* the write position once the frame made room for is published */
    uint64_t rx_tail;        /* this side's own copy of rx's read position */
} lm_rings;

/* A new region for two rings, as a descriptor (close-on-exec) in *fd. */
lm_status lm_ring_create(int *fd);
/* Map region fd (closed whatever the result) as side 0 (its creator) or 1. LM_E_INVALID when fd
 * has less memory behind it than a region (not one: touching it would raise SIGBUS). */
lm_status lm_ring_map(int fd, int side, lm_rings *r);
void lm_ring_unmap(lm_rings *r);

/* Room for one frame of n bytes in tx: where its bytes go, or NULL when it is larger than
 * LM_RING_MAX_FRAME or the ring is too full now. The frame is the reader's once published. */
uint8_t *lm_ring_room(lm_rings *r, size_t n);
/* Make the frame given room for visible to the reader. Returns whether the reader said it may be
 * asleep (lm_ring_sleep): then the caller must wake it some other way (the socket). */
int lm_ring_publish(lm_rings *r);

/* Whether rx holds a frame (or anything: a bad frame is reported by lm_ring_take). */
int lm_ring_ready(const lm_rings *r);
/* The next frame of rx copied into *buf (grown as needed; *cap its size), its length in *n; *n 0
 * when there is none. LM_E_FORMAT when the writer broke the ring; LM_E_NOMEM. */
lm_status lm_ring_take(lm_rings *r, uint8_t **buf, size_t *cap, size_t *n);

/* Before this side sleeps on its socket: says so to the writer, then returns whether a frame
 * arrived meanwhile (then do not sleep). lm_ring_awake when this side is back. */
int lm_ring_sleep(lm_rings *r);
void lm_ring_awake(lm_rings *r);

/* The count of socket frames this side has taken from its peer, for the peer to read (see
 * stream.c: a frame goes through the ring only when the reader has taken every socket frame sent
 * before it, so that the reader, which looks in the ring first, keeps the order). */
void lm_ring_set_taken(lm_rings *r, uint64_t taken);
uint64_t lm_ring_peer_taken(const lm_rings *r);

#endif
