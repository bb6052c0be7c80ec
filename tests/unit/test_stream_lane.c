/* tests/unit/test_stream_lane.c — a local link's shared-memory lane (proto/ring.h, stream.h):
 * frames arrive whole and in the order sent whichever way each went (the lane, or the socket for
 * large frames and a full ring); a reader asleep on the socket is woken by a frame put in the lane,
 * and the wake mark costs the lane nothing afterwards; a descriptor that is not a lane's memory,
 * and a ring whose lengths were scribbled on, are refused; two processes bouncing frames of every
 * size, each side sleeping at times, keep every byte and the order. */
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "proto/stream.h"
#include "test_support.h"

/* Two streams, the ends of one socketpair, sharing one lane. */
static void open_lane(lm_stream *a, lm_stream *b)
{
    int fd[2], shm;
    assert_int_equal(socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fd), 0);
    assert_int_equal(lm_ring_create(&shm), LM_OK);
    int shm2 = dup(shm);
    assert_true(shm2 >= 0);
    assert_int_equal(lm_stream_open(a, fd[0]), LM_OK);
    assert_int_equal(lm_stream_open(b, fd[1]), LM_OK);
    assert_int_equal(lm_stream_share(a, shm, 0), LM_OK);
    assert_int_equal(lm_stream_share(b, shm2, 1), LM_OK);
}

/* The next frame of s, waiting (spinning, then asleep) up to ~10 s; NULL data at the end. */
static lm_status next_frame(lm_stream *s, lm_wire_frame *f)
{
    for (int t = 0; t < 20000; t++) {
        lm_status st = lm_stream_next(s, f);
        if (st != LM_OK || f->data)
            return st;
        struct pollfd pf = {.fd = s->fd, .events = POLLIN};
        int rc = 0;
        if (t % 2 == 0)
            rc = poll(&pf, 1, 0);
        else if (!lm_stream_sleep(s))
            rc = poll(&pf, 1, 1);
        lm_stream_awake(s);
        if (rc > 0 && (st = lm_stream_fill(s)) != LM_OK) {
            lm_status last = lm_stream_next(s, f);
            return last != LM_OK || f->data ? last : st;
        }
    }
    return LM_E_IO;
}

/* Frame i's bytes: its size (some beyond the lane's limit) and content follow from i. */
static size_t frame_size(uint32_t i)
{
    return i % 37 == 5 ? LM_RING_MAX_FRAME + 1 + i : 1 + (i * 7919u) % 3000u;
}

static uint8_t frame_byte(uint32_t i, size_t k)
{
    return (uint8_t)((i * 2654435761u + k * 40503u) >> 13);
}

static void fill_frame(uint8_t *buf, uint32_t i)
{
    for (size_t k = 0, n = frame_size(i); k < n; k++)
        buf[k] = frame_byte(i, k);
}

static int frame_is(const lm_wire_frame *f, uint32_t i)
{
    if (!f->data || f->size != frame_size(i))
        return 0;
    for (size_t k = 0; k < f->size; k++)
        if (f->data[k] != frame_byte(i, k))
            return 0;
    return 1;
}

/* b takes frames [*got, upto) from a, checking each. */
static void take_upto(lm_stream *a, lm_stream *b, uint32_t *got, uint32_t upto)
{
    for (; *got < upto; (*got)++) {
        lm_wire_frame f;
        assert_int_equal(lm_stream_flush(a), LM_OK);
        assert_int_equal(next_frame(b, &f), LM_OK);
        assert_true(frame_is(&f, *got));
        lm_wire_frame_release(&f);
    }
}

/* Frames [first, first + n) from a to b, b taking all sent every `every` frames (0: at the end);
 * returns how many of them went over the socket. */
static uint64_t send_and_take(lm_stream *a, lm_stream *b, uint32_t first, uint32_t n,
                              uint32_t every, uint8_t *buf)
{
    uint64_t sent = a->sent;
    uint32_t got = first;
    for (uint32_t i = first; i < first + n; i++) {
        fill_frame(buf, i);
        assert_int_equal(lm_stream_put(a, buf, frame_size(i)), LM_OK);
        if (every && (i + 1) % every == 0)
            take_upto(a, b, &got, i + 1);
    }
    take_upto(a, b, &got, first + n);
    assert_int_equal(b->taken, a->sent);
    return a->sent - sent;
}

static void test_order_across_lane_and_socket(void **state)
{
    (void)state;
    lm_stream a, b;
    open_lane(&a, &b);
    uint8_t *buf = malloc(2 * LM_RING_MAX_FRAME);
    assert_non_null(buf);
    /* taken as it goes: the large frames over the socket, and the few after each until b took
     * it; the rest in the lane */
    uint64_t socket = send_and_take(&a, &b, 0, 400, 10, buf);
    assert_true(socket >= 400 / 37 && socket < 400 / 3);
    /* ~450 kB sent before b takes any: more than the ring holds, the rest over the socket */
    socket = send_and_take(&a, &b, 1000, 300, 0, buf);
    assert_true(socket > 300 / 4 && socket < 300);
    lm_wire_frame f;
    assert_int_equal(lm_stream_next(&b, &f), LM_OK);
    assert_null(f.data);
    free(buf);
    lm_stream_close(&a);
    lm_stream_close(&b);
}

static void test_sleeping_reader_woken(void **state)
{
    (void)state;
    lm_stream a, b;
    open_lane(&a, &b);
    assert_int_equal(lm_stream_sleep(&b), 0); /* nothing yet: b may sleep */
    assert_int_equal(lm_stream_put(&a, "hello", 5), LM_OK);
    struct pollfd pf = {.fd = b.fd, .events = POLLIN};
    assert_int_equal(poll(&pf, 1, 2000), 1); /* woken through the socket */
    lm_stream_awake(&b);
    assert_int_equal(lm_stream_fill(&b), LM_OK);
    lm_wire_frame f;
    assert_int_equal(lm_stream_next(&b, &f), LM_OK);
    assert_int_equal(f.size, 5);
    assert_memory_equal(f.data, "hello", 5);
    lm_wire_frame_release(&f);
    assert_int_equal(lm_stream_next(&b, &f), LM_OK); /* the wake mark is no frame */
    assert_null(f.data);
    assert_int_equal(b.taken, 1);
    uint64_t sent = a.sent;
    assert_int_equal(lm_stream_put(&a, "again", 5), LM_OK); /* b awake: the lane, no mark */
    assert_int_equal(a.sent, sent);
    assert_true(lm_stream_ready(&b));
    assert_int_equal(lm_stream_next(&b, &f), LM_OK);
    assert_memory_equal(f.data, "again", 5);
    lm_wire_frame_release(&f);
    /* a reader that says it sleeps after a frame came is told so, and need not */
    assert_int_equal(lm_stream_put(&a, "third", 5), LM_OK);
    assert_int_equal(lm_stream_sleep(&b), 1);
    lm_stream_awake(&b);
    lm_stream_close(&a);
    lm_stream_close(&b);
}

static void test_not_a_lane_refused(void **state)
{
    (void)state;
    int fd[2];
    assert_int_equal(pipe(fd), 0);
    lm_rings r;
    assert_int_equal(lm_ring_map(fd[0], 1, &r), LM_E_INVALID); /* no memory behind it: refused */
    assert_non_null(strstr(lm_last_error(), "not a link's shared memory"));
    assert_null(r.map);
    close(fd[1]);
}

static void test_scribbled_ring_refused(void **state)
{
    (void)state;
    const uint32_t bad[] = {0, LM_RING_MAX_FRAME + 1u, 64u};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        lm_stream a, b;
        open_lane(&a, &b);
        uint8_t *at = lm_ring_room(&a.ring, 8); /* an 8-byte frame whose length is then spoilt */
        assert_non_null(at);
        memcpy(at - 4, &bad[i], 4); /* 64: longer than what was published */
        lm_ring_publish(&a.ring);
        lm_wire_frame f;
        assert_int_equal(lm_stream_next(&b, &f), LM_E_FORMAT);
        assert_null(f.data);
        assert_non_null(strstr(lm_last_error(), "shared memory"));
        lm_stream_close(&a);
        lm_stream_close(&b);
    }
}

/* Side `who` of a bounce: frames 0..n-1 one way, each answered by the same frame back. */
static int bounce(lm_stream *s, int who, uint32_t n, uint8_t *buf)
{
    for (uint32_t i = 0; i < n; i++) {
        lm_wire_frame f;
        if (who == 0) {
            fill_frame(buf, i);
            if (lm_stream_put(s, buf, frame_size(i)) != LM_OK)
                return 0;
        }
        while (lm_stream_pending(s)) {
            struct pollfd pf = {.fd = s->fd, .events = POLLOUT};
            poll(&pf, 1, 100);
            if (lm_stream_flush(s) != LM_OK)
                return 0;
        }
        if (next_frame(s, &f) != LM_OK || !frame_is(&f, i))
            return 0;
        lm_status st = who == 1 ? lm_stream_put(s, f.data, f.size) : LM_OK;
        lm_wire_frame_release(&f);
        if (st != LM_OK)
            return 0;
    }
    return 1;
}

static void test_two_processes_bounce(void **state)
{
    (void)state;
    lm_stream a, b;
    open_lane(&a, &b);
    uint8_t *buf = malloc(2 * LM_RING_MAX_FRAME);
    assert_non_null(buf);
    const uint32_t n = 3000;
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        lm_stream_close(&a);
        int ok = bounce(&b, 1, n, buf);
        _exit(ok ? 0 : 1);
    }
    lm_stream_close(&b);
    assert_true(bounce(&a, 0, n, buf));
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    free(buf);
    lm_stream_close(&a);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_order_across_lane_and_socket),
        cmocka_unit_test(test_sleeping_reader_woken),
        cmocka_unit_test(test_not_a_lane_refused),
        cmocka_unit_test(test_scribbled_ring_refused),
        cmocka_unit_test(test_two_processes_bounce),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
