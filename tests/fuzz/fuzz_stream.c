/* tests/fuzz/fuzz_stream.c — libFuzzer target for a local worker's link (proto/stream.h): the
 * input arrives over a real socketpair, as a peer would send it, and is read frame by frame (each
 * length checked before anything is read for it), every frame decoded as fuzz_wire_msg decodes
 * one. Any input must end in frames, the end of the stream, or a refusal with a one-line message;
 * never a crash, a hang, a leak or a buffer beyond one frame.
 * Seeds: every message kind as two frames of a link, written by make_wire_seeds (scripts/test.sh).
 */
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "common/log.h"
#include "proto/stream.h"
#include "proto/wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check(lm_status st)
{
    LM_ASSERT(st == LM_OK || (lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n')));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int quiet;
    if (!quiet) {
        lm_log_set_level(LM_LOG_ERROR);
        quiet = 1;
    }
    int fd[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fd) != 0)
        return 0;
    size_t off = 0; /* the socket holds far more than -max_len */
    while (off < size) {
        ssize_t k = write(fd[0], data + off, size - off);
        if (k <= 0)
            break;
        off += (size_t)k;
    }
    close(fd[0]); /* the peer has said everything */
    lm_stream s;
    lm_status st = lm_stream_open(&s, fd[1]);
    for (int frames = 0; st == LM_OK && frames < 100000; frames++) {
        lm_wire_frame f;
        st = lm_stream_next(&s, &f);
        if (st == LM_OK && !f.data) {
            st = lm_stream_fill(&s);
            if (st == LM_OK)
                st = lm_stream_next(&s, &f);
            else if (lm_stream_next(&s, &f) != LM_OK || !f.data)
                break; /* the end (or a refusal), the frames before it taken */
        }
        if (st != LM_OK || !f.data)
            break;
        LM_ASSERT(f.size > 0 && f.size <= LM_WIRE_MAX_FRAME);
        LM_ASSERT(s.in_cap <= (size_t)f.size + (2u << 20));
        lm_wire_in in;
        check(lm_wire_decode(f.data, f.size, &in));
        lm_wire_in_free(&in);
        lm_wire_frame_release(&f);
    }
    check(st);
    lm_clear_error();
    lm_stream_close(&s);
    return 0;
}
