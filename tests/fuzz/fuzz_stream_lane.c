/* tests/fuzz/fuzz_stream_lane.c — libFuzzer target for a local link's shared-memory lane
 * (proto/ring.h): a peer that scribbles on the ring. The input is a list of frames, each 3 bytes
 * (a size of up to 64 kB, little-endian 16 bits, and what to do to its length: keep it, or write
 * the next 4 input bytes over it once published) put into the lane, then taken by the reader with
 * lm_stream_next. Any input must end in whole frames of the sizes put, or a refusal with a one-line
 * message; never a crash, a read outside the ring or the reader's buffer, or a hang. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "common/log.h"
#include "proto/stream.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int open_lane(lm_stream *a, lm_stream *b)
{
    int fd[2], shm;
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fd) != 0)
        return 0;
    if (lm_ring_create(&shm) != LM_OK) {
        close(fd[0]);
        close(fd[1]);
        return 0;
    }
    int shm2 = dup(shm);
    int ok = lm_stream_open(a, fd[0]) == LM_OK && lm_stream_open(b, fd[1]) == LM_OK;
    ok = lm_stream_share(a, shm, 0) == LM_OK && ok;
    ok = shm2 >= 0 && lm_stream_share(b, shm2, 1) == LM_OK && ok;
    return ok;
}

/* Put frames from the input until the ring is full or the input ends; returns where it ended. */
static size_t put_frames(lm_stream *a, const uint8_t *data, size_t size, size_t off)
{
    while (off + 3 <= size) {
        size_t n = (size_t)data[off] | (size_t)data[off + 1] << 8;
        uint8_t how = data[off + 2];
        off += 3;
        uint8_t *at = lm_ring_room(&a->ring, n ? n : 1);
        if (!at)
            return off;
        memset(at, 0x5a, n ? n : 1);
        if (how & 1 && off + 4 <= size) { /* the peer spoils the length it wrote */
            memcpy(at - 4, data + off, 4);
            off += 4;
        }
        lm_ring_publish(&a->ring);
    }
    return size;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int quiet;
    if (!quiet) {
        lm_log_set_level(LM_LOG_ERROR);
        quiet = 1;
    }
    lm_stream a, b;
    memset(&a, 0, sizeof a), memset(&b, 0, sizeof b);
    a.fd = b.fd = -1;
    if (!open_lane(&a, &b)) {
        lm_stream_close(&a);
        lm_stream_close(&b);
        return 0;
    }
    lm_status st = LM_OK;
    for (size_t off = 0; off < size && st == LM_OK;) {
        off = put_frames(&a, data, size, off);
        for (int frames = 0; st == LM_OK && frames < 100000; frames++) {
            lm_wire_frame f;
            st = lm_stream_next(&b, &f);
            if (st != LM_OK || !f.data)
                break;
            LM_ASSERT(f.size > 0 && f.size <= LM_RING_MAX_FRAME);
            lm_wire_frame_release(&f);
        }
    }
    LM_ASSERT(st == LM_OK || (lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n')));
    lm_clear_error();
    lm_stream_close(&a);
    lm_stream_close(&b);
    return 0;
}
