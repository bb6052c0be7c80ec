/* tests/support/zmq_poke.c — a hostile peer for the fault tests: connects a DEALER to ENDPOINT and
 * sends MODE frames, then waits a moment and exits 0 (whatever the coordinator does with them).
 *   garbage N    N frames of random bytes (up to 4 KiB each)
 *   oversize MB  one frame of MB mebibytes (above the frame limit: the coordinator's socket drops
 * it) bodyless N   N well-formed frames that decode to no known body hello        a Hello of
 * another protocol version (refused) usage: zmq_poke ENDPOINT MODE [N] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zmq.h>

#include "proto/wire.h"

static void send_random(void *s, unsigned n)
{
    uint32_t x = 2463534242u;
    uint8_t buf[4096];
    for (unsigned i = 0; i < n; i++) {
        size_t len = 1 + i * 97 % sizeof buf;
        for (size_t k = 0; k < len; k++) {
            x ^= x << 13, x ^= x >> 17, x ^= x << 5;
            buf[k] = (uint8_t)x;
        }
        zmq_send(s, buf, len, 0);
    }
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: zmq_poke ENDPOINT garbage|oversize|bodyless|hello [N]\n");
        return 1;
    }
    unsigned n = argc > 3 ? (unsigned)atoi(argv[3]) : 10;
    void *ctx = zmq_ctx_new(), *s = zmq_socket(ctx, ZMQ_DEALER);
    int linger = 3000; /* frames queued before the connection is up are still delivered */
    zmq_setsockopt(s, ZMQ_LINGER, &linger, sizeof linger);
    if (zmq_connect(s, argv[1]) != 0) {
        fprintf(stderr, "zmq_poke: %s\n", zmq_strerror(zmq_errno()));
        return 1;
    }
    usleep(200000);
    if (!strcmp(argv[2], "garbage")) {
        send_random(s, n);
    } else if (!strcmp(argv[2], "oversize")) {
        size_t len = (size_t)n << 20;
        uint8_t *big = calloc(1, len);
        zmq_send(s, big, len, 0);
        free(big);
    } else if (!strcmp(argv[2], "bodyless")) {
        for (unsigned i = 0; i < n; i++)
            zmq_send(s, "\x08\x07", 2, 0); /* req = 7, no body */
    } else if (!strcmp(argv[2], "hello")) {
        Lumesh__Hello h = LUMESH__HELLO__INIT;
        h.version = LM_WIRE_VERSION + 7, h.host = "poke", h.renderer_id = "x";
        lm_msg m;
        lm_wire_msg_init(&m, 0, 0, LUMESH__MSG__BODY_HELLO, &h);
        lm_wire_send(s, NULL, 0, &m);
    } else {
        fprintf(stderr, "zmq_poke: unknown mode %s\n", argv[2]);
        return 1;
    }
    usleep(500000);
    zmq_close(s);
    zmq_ctx_term(ctx);
    return 0;
}
