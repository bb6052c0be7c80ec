/* proto/ring.c — frames through shared memory beside a local link (see ring.h).
 *
 * A frame in a ring is its length (4 bytes) then its bytes, from a position that is a multiple of
 * 8; a frame never wraps: where it would, a RING_WRAP length sends the reader to the ring's start.
 * Positions count bytes since the start and only grow; head - tail is what the reader has still to
 * take. Written with release and read with acquire, so a frame's bytes are there when its head is.
 * The sleep flag against the head is Dekker's handshake: each side stores its own, then (sequential
 * consistency) loads the other's, so a frame published as the reader goes to sleep is seen by one
 * of the two. */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* memfd_create */
#endif
#include "proto/ring.h"

#include <errno.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#define RING_WRAP 0xffffffffu
#define RING_ALIGN 8u

struct lm_ring_shared {
    _Alignas(64) _Atomic uint64_t head; /* the writer's */
    _Alignas(64) _Atomic uint64_t tail; /* the reader's */
    _Atomic uint64_t taken;             /* the reader's: socket frames it has taken */
    _Atomic uint32_t sleeping;          /* the reader's: it may be asleep on its socket */
    _Alignas(64) uint8_t data[LM_RING_BYTES];
};

lm_status lm_ring_create(int *fd)
{
    *fd = memfd_create("lumesh-link", MFD_CLOEXEC);
    if (*fd < 0)
        return lm_fail(LM_E_IO, "cannot make shared memory for a worker: %s", strerror(errno));
    if (ftruncate(*fd, (off_t)(2 * sizeof(lm_ring_shared))) != 0) {
        int e = errno;
        close(*fd);
        *fd = -1;
        return lm_fail(LM_E_IO, "cannot size shared memory for a worker: %s", strerror(e));
    }
    return LM_OK;
}

lm_status lm_ring_map(int fd, int side, lm_rings *r)
{
    memset(r, 0, sizeof *r);
    size_t len = 2 * sizeof(lm_ring_shared);
    struct stat st;
    if (fstat(fd, &st) != 0 || st.st_size < (off_t)len) { /* else a touch beyond it is SIGBUS */
        close(fd);
        return lm_fail(LM_E_INVALID, "descriptor %d is not a link's shared memory", fd);
    }
    void *m = mmap(NULL, len, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    int e = errno;
    close(fd);
    if (m == MAP_FAILED)
        return lm_fail(LM_E_IO, "cannot map a link's shared memory: %s", strerror(e));
    lm_ring_shared *two = m;
    r->map = m;
    r->map_len = len;
    r->tx = &two[side ? 1 : 0];
    r->rx = &two[side ? 0 : 1];
    return LM_OK;
}

void lm_ring_unmap(lm_rings *r)
{
    if (r->map)
        munmap(r->map, r->map_len);
    memset(r, 0, sizeof *r);
}

static size_t frame_span(size_t n)
{
    return (4 + n + RING_ALIGN - 1) / RING_ALIGN * RING_ALIGN;
}

uint8_t *lm_ring_room(lm_rings *r, size_t n)
{
    if (n == 0 || n > LM_RING_MAX_FRAME)
        return NULL;
    uint64_t head = r->tx_head, tail = atomic_load_explicit(&r->tx->tail, memory_order_acquire);
    if (head - tail > LM_RING_BYTES) /* the reader's position is nonsense: use the socket */
        return NULL;
    size_t at = (size_t)(head % LM_RING_BYTES), span = frame_span(n);
    size_t skip = span > LM_RING_BYTES - at ? LM_RING_BYTES - at : 0;
    if (head + skip + span - tail > LM_RING_BYTES)
        return NULL;
    if (skip) {
        uint32_t wrap = RING_WRAP;
        memcpy(r->tx->data + at, &wrap, 4);
        at = 0;
    }
    uint32_t len = (uint32_t)n;
    memcpy(r->tx->data + at, &len, 4);
    r->tx_next = head + skip + span;
    return r->tx->data + at + 4;
}

int lm_ring_publish(lm_rings *r)
{
    r->tx_head = r->tx_next;
    atomic_store_explicit(&r->tx->head, r->tx_head, memory_order_seq_cst);
    return atomic_load_explicit(&r->tx->sleeping, memory_order_seq_cst) != 0;
}

int lm_ring_ready(const lm_rings *r)
{
    return atomic_load_explicit(&r->rx->head, memory_order_acquire) != r->rx_tail;
}

static lm_status broken(const char *what)
{
    return lm_fail(LM_E_FORMAT, "the worker link's shared memory is broken (%s)", what);
}

lm_status lm_ring_take(lm_rings *r, uint8_t **buf, size_t *cap, size_t *n)
{
    *n = 0;
    for (;;) {
        uint64_t tail = r->rx_tail, head = atomic_load_explicit(&r->rx->head, memory_order_acquire);
        if (head == tail)
            return LM_OK;
        if (head - tail > LM_RING_BYTES || head % RING_ALIGN)
            return broken("a position out of range");
        size_t at = (size_t)(tail % LM_RING_BYTES);
        uint32_t len;
        memcpy(&len, r->rx->data + at, 4);
        if (len == RING_WRAP) {
            r->rx_tail = tail + (LM_RING_BYTES - at);
            atomic_store_explicit(&r->rx->tail, r->rx_tail, memory_order_release);
            continue;
        }
        size_t span = frame_span(len);
        if (len == 0 || len > LM_RING_MAX_FRAME || span > LM_RING_BYTES - at || span > head - tail)
            return broken("a bad frame length");
        if (*cap < len) {
            uint8_t *b = realloc(*buf, LM_RING_MAX_FRAME);
            if (!b)
                return lm_fail(LM_E_NOMEM, "out of memory for a frame from a worker's link");
            *buf = b;
            *cap = LM_RING_MAX_FRAME;
        }
        memcpy(*buf, r->rx->data + at + 4, len);
        r->rx_tail = tail + span;
        atomic_store_explicit(&r->rx->tail, r->rx_tail, memory_order_release);
        *n = len;
        return LM_OK;
    }
}

int lm_ring_sleep(lm_rings *r)
{
    atomic_store_explicit(&r->rx->sleeping, 1, memory_order_seq_cst);
    return atomic_load_explicit(&r->rx->head, memory_order_seq_cst) != r->rx_tail;
}

void lm_ring_awake(lm_rings *r)
{
    atomic_store_explicit(&r->rx->sleeping, 0, memory_order_relaxed);
}

void lm_ring_set_taken(lm_rings *r, uint64_t taken)
{
    atomic_store_explicit(&r->rx->taken, taken, memory_order_release);
}

uint64_t lm_ring_peer_taken(const lm_rings *r)
{
    return atomic_load_explicit(&r->tx->taken, memory_order_acquire);
}
