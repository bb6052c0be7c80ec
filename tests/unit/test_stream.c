/* tests/unit/test_stream.c — frames over a local worker's socketpair (proto/stream.h): they arrive
 * whole and in order, also a frame far larger than the socket's buffers, written and read in
 * pieces by two processes; a length of 0 or above the frame limit is refused before anything is
 * read for it; the frames sent before the peer closed are still delivered, then the end; a
 * message packed straight into the queue decodes; nothing blocks. */
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "proto/stream.h"
#include "test_support.h"

static void pair(int fd[2])
{
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fd), 0);
}

/* Two streams, the ends of one socketpair. */
static void open_pair(lm_stream *a, lm_stream *b)
{
    int fd[2];
    pair(fd);
    assert_int_equal(lm_stream_open(a, fd[0]), LM_OK);
    assert_int_equal(lm_stream_open(b, fd[1]), LM_OK);
}

/* The next frame, waiting for it (at most ~10 s); NULL data at the end of the stream. */
static lm_status next_frame(lm_stream *s, lm_wire_frame *f)
{
    for (int t = 0; t < 10000; t++) {
        lm_status st = lm_stream_next(s, f);
        if (st != LM_OK || f->data)
            return st;
        struct pollfd pf = {.fd = s->fd, .events = POLLIN};
        poll(&pf, 1, 1);
        st = lm_stream_fill(s);
        if (st != LM_OK) {
            lm_status last = lm_stream_next(s, f);
            return last != LM_OK || f->data ? last : st;
        }
    }
    return LM_E_IO;
}

static void test_frames_in_order(void **state)
{
    (void)state;
    lm_stream a, b;
    open_pair(&a, &b);
    for (int i = 1; i <= 50; i++) {
        char msg[64];
        int n = snprintf(msg, sizeof msg, "frame %d", i);
        assert_int_equal(lm_stream_put(&a, msg, (size_t)n), LM_OK);
    }
    assert_int_equal(lm_stream_pending(&a), 0);
    for (int i = 1; i <= 50; i++) {
        lm_wire_frame f;
        char want[64];
        int n = snprintf(want, sizeof want, "frame %d", i);
        assert_int_equal(next_frame(&b, &f), LM_OK);
        assert_non_null(f.data);
        assert_int_equal(f.size, (size_t)n);
        assert_memory_equal(f.data, want, (size_t)n);
        lm_wire_frame_release(&f);
    }
    lm_wire_frame f;
    assert_int_equal(lm_stream_next(&b, &f), LM_OK);
    assert_null(f.data); /* nothing more, and no wait */
    lm_stream_close(&a);
    lm_stream_close(&b);
}

static void test_large_frame_in_pieces(void **state)
{
    (void)state;
    const size_t n = 9u << 20; /* far beyond a Unix socket's buffer */
    int fd[2];
    pair(fd);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) { /* the writer: non-blocking puts, flushed as the reader takes them */
        close(fd[1]);
        lm_stream w;
        uint8_t *big = malloc(n);
        int ok = big && lm_stream_open(&w, fd[0]) == LM_OK;
        for (size_t i = 0; ok && i < n; i++)
            big[i] = (uint8_t)(i * 2654435761u >> 24);
        ok = ok && lm_stream_put(&w, big, n) == LM_OK && lm_stream_put(&w, "end", 3) == LM_OK;
        while (ok && lm_stream_pending(&w)) {
            struct pollfd pf = {.fd = w.fd, .events = POLLOUT};
            poll(&pf, 1, 100);
            ok = lm_stream_flush(&w) == LM_OK;
        }
        _exit(ok ? 0 : 1);
    }
    close(fd[0]);
    lm_stream r;
    assert_int_equal(lm_stream_open(&r, fd[1]), LM_OK);
    lm_wire_frame f;
    assert_int_equal(next_frame(&r, &f), LM_OK);
    assert_int_equal(f.size, n);
    int same = 1;
    for (size_t i = 0; i < n && same; i++)
        same = f.data[i] == (uint8_t)(i * 2654435761u >> 24);
    assert_true(same);
    lm_wire_frame_release(&f);
    assert_int_equal(next_frame(&r, &f), LM_OK);
    assert_int_equal(f.size, 3);
    assert_memory_equal(f.data, "end", 3);
    lm_wire_frame_release(&f);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    /* the writer has gone: the end of the stream */
    assert_int_equal(next_frame(&r, &f), LM_E_IO);
    assert_null(f.data);
    lm_stream_close(&r);
}

static void test_frames_before_the_end(void **state)
{
    (void)state;
    lm_stream a, b;
    open_pair(&a, &b);
    assert_int_equal(lm_stream_put(&a, "last words", 10), LM_OK);
    lm_stream_close(&a);
    lm_wire_frame f;
    assert_int_equal(next_frame(&b, &f), LM_OK);
    assert_int_equal(f.size, 10);
    lm_wire_frame_release(&f);
    assert_int_equal(next_frame(&b, &f), LM_E_IO);
    assert_non_null(strstr(lm_last_error(), "closed"));
    /* and a put to a peer that has gone fails, without a signal */
    assert_int_equal(lm_stream_put(&b, "x", 1), LM_E_IO);
    lm_stream_close(&b);
}

static void raw_length(int fd, uint32_t n)
{
    uint8_t h[4] = {(uint8_t)n, (uint8_t)(n >> 8), (uint8_t)(n >> 16), (uint8_t)(n >> 24)};
    assert_int_equal(write(fd, h, 4), 4);
}

static void test_bad_lengths_refused(void **state)
{
    (void)state;
    const uint32_t bad[] = {0, LM_WIRE_MAX_FRAME + 1u, UINT32_MAX};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        int fd[2];
        pair(fd);
        lm_stream r;
        assert_int_equal(lm_stream_open(&r, fd[1]), LM_OK);
        raw_length(fd[0], bad[i]);
        lm_wire_frame f;
        assert_int_equal(next_frame(&r, &f), LM_E_FORMAT);
        assert_null(f.data);
        assert_true(r.in_cap < (1u << 20)); /* nothing was allocated for the announced length */
        close(fd[0]);
        lm_stream_close(&r);
    }
    int fd[2];
    pair(fd);
    lm_stream w;
    assert_int_equal(lm_stream_open(&w, fd[0]), LM_OK);
    assert_int_equal(lm_stream_put(&w, "", 0), LM_E_RANGE);
    assert_int_equal(lm_stream_put(&w, "x", (size_t)LM_WIRE_MAX_FRAME + 1), LM_E_RANGE);
    assert_int_equal(lm_stream_pending(&w), 0);
    close(fd[1]);
    lm_stream_close(&w);
}

static void test_truncated_frame_waits(void **state)
{
    (void)state;
    int fd[2];
    pair(fd);
    lm_stream r;
    assert_int_equal(lm_stream_open(&r, fd[1]), LM_OK);
    raw_length(fd[0], 6);
    assert_int_equal(write(fd[0], "abc", 3), 3);
    assert_int_equal(lm_stream_fill(&r), LM_OK);
    lm_wire_frame f;
    assert_int_equal(lm_stream_next(&r, &f), LM_OK);
    assert_null(f.data); /* half a frame: not yet */
    assert_int_equal(write(fd[0], "def", 3), 3);
    assert_int_equal(next_frame(&r, &f), LM_OK);
    assert_int_equal(f.size, 6);
    assert_memory_equal(f.data, "abcdef", 6);
    lm_wire_frame_release(&f);
    close(fd[0]);
    lm_stream_close(&r);
}

static void test_message_frames(void **state)
{
    (void)state;
    lm_stream a, b;
    open_pair(&a, &b);
    Lumesh__Heartbeat h = LUMESH__HEARTBEAT__INIT;
    h.busy = 1;
    lm_msg m;
    lm_wire_msg_init(&m, 5, 9, LUMESH__MSG__BODY_HEARTBEAT, &h);
    assert_int_equal(lm_stream_put_msg(&a, &m), LM_OK);
    lm_wire_frame f;
    assert_int_equal(next_frame(&b, &f), LM_OK);
    lm_wire_in in;
    assert_int_equal(lm_wire_decode(f.data, f.size, &in), LM_OK);
    assert_true(in.msg->req == 5 && in.msg->seq == 9);
    assert_int_equal(in.msg->body_case, LUMESH__MSG__BODY_HEARTBEAT);
    assert_true(in.msg->heartbeat->busy);
    lm_wire_in_free(&in);
    lm_wire_frame_release(&f);
    lm_stream_close(&a);
    lm_stream_close(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frames_in_order),       cmocka_unit_test(test_large_frame_in_pieces),
        cmocka_unit_test(test_frames_before_the_end), cmocka_unit_test(test_bad_lengths_refused),
        cmocka_unit_test(test_truncated_frame_waits), cmocka_unit_test(test_message_frames),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
