/* proto/stream.c — length-prefixed frames over a non-blocking byte stream, and beside it the
 * shared-memory lane of a local link (see stream.h). */
#include "proto/stream.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "common/grow.h"

#define STREAM_READ_CHUNK (64u << 10)
#define STREAM_KEEP_BYTES (1u << 20) /* a larger read buffer is given back once it is empty */

lm_status lm_stream_open(lm_stream *s, int fd)
{
    memset(s, 0, sizeof *s);
    s->fd = fd;
    int flags = fcntl(fd, F_GETFL);
    if (flags < 0 || fcntl(fd, F_SETFL, flags | O_NONBLOCK) < 0)
        return lm_fail(LM_E_IO, "a worker's connection (descriptor %d) cannot be used: %s", fd,
                       strerror(errno));
    return LM_OK;
}

void lm_stream_close(lm_stream *s)
{
    if (s->fd >= 0)
        close(s->fd);
    lm_ring_unmap(&s->ring);
    free(s->in);
    free(s->out);
    free(s->ring_in);
    memset(s, 0, sizeof *s);
    s->fd = -1;
}

lm_status lm_stream_share(lm_stream *s, int shm_fd, int side)
{
    LM_ASSERT(!s->ring.map && !s->sent && !s->taken);
    return lm_ring_map(shm_fd, side, &s->ring);
}

static lm_status reserve(uint8_t **buf, size_t *cap, size_t need)
{
    if (!LM_GROW(buf, cap, need, 4096))
        return lm_fail(LM_E_NOMEM, "out of memory for %zu bytes of a connection's buffer", need);
    return LM_OK;
}

lm_status lm_stream_flush(lm_stream *s)
{
    while (s->out_off < s->out_len) {
        ssize_t k = send(s->fd, s->out + s->out_off, s->out_len - s->out_off, MSG_NOSIGNAL);
        if (k < 0 && errno == EINTR)
            continue;
        if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            return LM_OK;
        if (k <= 0)
            return lm_fail(LM_E_IO, "the connection closed%s%s", k < 0 ? ": " : "",
                           k < 0 ? strerror(errno) : "");
        s->out_off += (size_t)k;
    }
    s->out_off = s->out_len = 0;
    return LM_OK;
}

/* Room for a frame of n bytes at the end of the queue, its length written: where its bytes go. */
static lm_status frame_room(lm_stream *s, size_t n, uint8_t **at)
{
    if (n == 0 || n > LM_WIRE_MAX_FRAME)
        return lm_fail(LM_E_RANGE, "a frame of %zu bytes (the limit is %u)", n, LM_WIRE_MAX_FRAME);
    if (s->out_off > 0 && s->out_off >= s->out_len / 2) { /* the unsent rest to the front */
        memmove(s->out, s->out + s->out_off, s->out_len - s->out_off);
        s->out_len -= s->out_off;
        s->out_off = 0;
    }
    lm_status st = reserve(&s->out, &s->out_cap, s->out_len + LM_STREAM_HEADER + n);
    if (st != LM_OK)
        return st;
    uint8_t *h = s->out + s->out_len;
    for (unsigned i = 0; i < LM_STREAM_HEADER; i++)
        h[i] = (uint8_t)(n >> (8 * i));
    s->out_len += LM_STREAM_HEADER + n;
    s->sent++;
    *at = h + LM_STREAM_HEADER;
    return LM_OK;
}

/* Room for a frame of n bytes in the shared lane, or NULL where it must go over the socket: no
 * lane, a frame too large or a ring too full, or socket frames the peer has not taken yet. */
static uint8_t *lane_room(lm_stream *s, size_t n)
{
    if (!s->ring.map || s->out_len > s->out_off || lm_ring_peer_taken(&s->ring) != s->sent)
        return NULL;
    return lm_ring_room(&s->ring, n);
}

/* Publish the frame given room in the lane, and wake a peer that may be asleep on the socket. */
static lm_status lane_publish(lm_stream *s)
{
    if (!lm_ring_publish(&s->ring))
        return LM_OK;
    lm_status st = reserve(&s->out, &s->out_cap, s->out_len + LM_STREAM_HEADER);
    if (st != LM_OK)
        return st;
    memset(s->out + s->out_len, 0xff, LM_STREAM_HEADER); /* LM_STREAM_WAKE */
    s->out_len += LM_STREAM_HEADER;
    s->sent++;
    return lm_stream_flush(s);
}

lm_status lm_stream_put(lm_stream *s, const void *data, size_t n)
{
    uint8_t *at = lane_room(s, n);
    if (at) {
        memcpy(at, data, n);
        return lane_publish(s);
    }
    lm_status st = frame_room(s, n, &at);
    if (st != LM_OK)
        return st;
    memcpy(at, data, n);
    return lm_stream_flush(s);
}

lm_status lm_stream_put_msg(lm_stream *s, const lm_msg *m)
{
    size_t n = lumesh__msg__get_packed_size(m);
    uint8_t *at = lane_room(s, n);
    if (at) {
        lumesh__msg__pack(m, at);
        return lane_publish(s);
    }
    lm_status st = frame_room(s, n, &at);
    if (st == LM_E_RANGE)
        return lm_fail(LM_E_RANGE, "a %s message of %zu bytes exceeds the frame limit of %u",
                       lm_wire_body_name(m), n, LM_WIRE_MAX_FRAME);
    if (st != LM_OK)
        return st;
    lumesh__msg__pack(m, at);
    return lm_stream_flush(s);
}

size_t lm_stream_pending(const lm_stream *s)
{
    return s->out_len - s->out_off;
}

static uint32_t frame_length(const uint8_t *h)
{
    uint32_t n = 0;
    for (unsigned i = 0; i < LM_STREAM_HEADER; i++)
        n |= (uint32_t)h[i] << (8 * i);
    return n;
}

/* Whether a whole frame (or a bad length, for lm_stream_next to refuse) is buffered. */
static int frame_ready(const lm_stream *s)
{
    size_t have = s->in_len - s->in_off;
    if (have < LM_STREAM_HEADER)
        return 0;
    uint32_t n = frame_length(s->in + s->in_off);
    return n == 0 || n > LM_WIRE_MAX_FRAME || have - LM_STREAM_HEADER >= n; /* a wake mark too */
}

lm_status lm_stream_fill(lm_stream *s)
{
    LM_ASSERT(!s->frame_out);
    if (s->in_off == s->in_len && s->in_cap > STREAM_KEEP_BYTES) { /* after a large frame */
        free(s->in);
        s->in = NULL;
        s->in_off = s->in_len = s->in_cap = 0;
    }
    if (s->in_off > 0) { /* move the unread bytes to the front */
        memmove(s->in, s->in + s->in_off, s->in_len - s->in_off);
        s->in_len -= s->in_off;
        s->in_off = 0;
    }
    while (!frame_ready(s)) { /* never more than one frame ahead: the buffer stays bounded */
        lm_status st = reserve(&s->in, &s->in_cap, s->in_len + STREAM_READ_CHUNK);
        if (st != LM_OK)
            return st;
        ssize_t k = recv(s->fd, s->in + s->in_len, s->in_cap - s->in_len, 0);
        if (k < 0 && errno == EINTR)
            continue;
        if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            return LM_OK;
        if (k <= 0)
            return lm_fail(LM_E_IO, "the connection closed%s%s", k < 0 ? ": " : "",
                           k < 0 ? strerror(errno) : "");
        s->in_len += (size_t)k;
    }
    return LM_OK;
}

static void release_frame(void *owner, const lm_wire_frame *f)
{
    lm_stream *s = owner;
    s->in_off += LM_STREAM_HEADER + f->size;
    s->frame_out = 0;
}

static void release_lane_frame(void *owner, const lm_wire_frame *f)
{
    (void)f;
    ((lm_stream *)owner)->frame_out = 0;
}

/* The next frame of the shared lane, if any (into f, as lm_stream_next). */
static lm_status lane_next(lm_stream *s, lm_wire_frame *f)
{
    size_t n = 0;
    lm_status st = lm_ring_take(&s->ring, &s->ring_in, &s->ring_in_cap, &n);
    if (st != LM_OK || n == 0)
        return st;
    f->data = s->ring_in;
    f->size = n;
    f->release_ = release_lane_frame;
    f->owner_ = s;
    s->frame_out = 1;
    return LM_OK;
}

/* One more socket frame (or wake mark) taken, said to the writer. */
static void count_taken(lm_stream *s)
{
    s->taken++;
    if (s->ring.map)
        lm_ring_set_taken(&s->ring, s->taken);
}

int lm_stream_ready(const lm_stream *s)
{
    return (s->ring.map && lm_ring_ready(&s->ring)) || frame_ready(s);
}

int lm_stream_sleep(lm_stream *s)
{
    return s->ring.map ? lm_ring_sleep(&s->ring) : 0;
}

void lm_stream_awake(lm_stream *s)
{
    if (s->ring.map)
        lm_ring_awake(&s->ring);
}

lm_status lm_stream_next(lm_stream *s, lm_wire_frame *f)
{
    memset(f, 0, sizeof *f);
    LM_ASSERT(!s->frame_out);
    if (s->ring.map) {
        lm_status st = lane_next(s, f);
        if (st != LM_OK || f->data)
            return st;
    }
    size_t have = s->in_len - s->in_off;
    while (s->ring.map && have >= LM_STREAM_HEADER &&
           frame_length(s->in + s->in_off) == LM_STREAM_WAKE) {
        s->in_off += LM_STREAM_HEADER, have -= LM_STREAM_HEADER;
        count_taken(s);
    }
    if (have < LM_STREAM_HEADER)
        return LM_OK;
    uint32_t n = frame_length(s->in + s->in_off);
    if (n == 0 || n > LM_WIRE_MAX_FRAME)
        return lm_fail(LM_E_FORMAT, "a frame of %u bytes announced (the limit is %u)", n,
                       LM_WIRE_MAX_FRAME);
    if (have - LM_STREAM_HEADER < n)
        return LM_OK;
    f->data = s->in + s->in_off + LM_STREAM_HEADER;
    f->size = n;
    f->release_ = release_frame;
    f->owner_ = s;
    s->frame_out = 1;
    count_taken(s);
    return LM_OK;
}
