/* tests/unit/test_worker_assets.c — a real lumesh-worker's side of shipping assets, driven by a
 * stand-in coordinator (a ROUTER socket of the test's own): an offer of an asset the worker lacks
 * is answered with Need for it; when the coordinator gives the worker up in the middle of the
 * transfer and offers again (a worker presumed dead that is taken back), the worker asks for the
 * asset again and, once it has all of it, says Ready. (It used to keep the half-done upload, ask
 * for nothing and never say Ready: the coordinator waited on it forever.) */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zmq.h>

#include "coordinator/pool/spawn.h"
#include "proto/asset.h"
#include "proto/wire.h"
#include "test_support.h"

#define ASSET_BYTES 1000

typedef struct rig {
    void *ctx, *sock;
    char *dir, endpoint[512];
    pid_t worker;
    uint8_t id[LM_WIRE_MAX_IDENTITY];
    size_t id_len;
} rig;

/* The next message from the worker's main socket (its beat thread's are skipped). */
static Lumesh__Msg__BodyCase next_msg(rig *r, lm_wire_in *in)
{
    for (int tries = 0; tries < 400; tries++) {
        lm_wire_frame f;
        assert_int_equal(lm_wire_recv(r->sock, 1, 100, &f), LM_OK);
        if (!f.data)
            continue;
        int beat = f.id_len >= 3 && !memcmp(f.id + f.id_len - 3, "#hb", 3);
        if (!beat) {
            memcpy(r->id, f.id, f.id_len);
            r->id_len = f.id_len;
            assert_int_equal(lm_wire_decode(f.data, f.size, in), LM_OK);
        }
        lm_wire_frame_release(&f);
        if (!beat && in->msg->body_case != LUMESH__MSG__BODY_HEARTBEAT)
            return in->msg->body_case;
        if (!beat)
            lm_wire_in_free(in);
    }
    fail_msg("the worker sent nothing for 40 s");
    return LUMESH__MSG__BODY__NOT_SET;
}

static void send_msg(rig *r, uint64_t req, Lumesh__Msg__BodyCase c, void *body)
{
    lm_msg m;
    lm_wire_msg_init(&m, req, 0, c, body);
    assert_int_equal(lm_wire_send(r->sock, r->id, r->id_len, &m), LM_OK);
}

static void rig_start(rig *r)
{
    memset(r, 0, sizeof *r);
    r->dir = lmt_mkdtemp();
    snprintf(r->endpoint, sizeof r->endpoint, "ipc://%s/pool", r->dir);
    r->ctx = zmq_ctx_new();
    r->sock = zmq_socket(r->ctx, ZMQ_ROUTER);
    assert_int_equal(lm_wire_socket_setup(r->sock, 1), LM_OK);
    assert_int_equal(zmq_bind(r->sock, r->endpoint), 0);
    char buf[4096];
    const char *exe = co_spawn_find_worker(NULL, buf);
    r->worker = fork();
    assert_true(r->worker >= 0);
    if (r->worker == 0) {
        execl(exe, exe, "--connect", r->endpoint, "--device", "cpu", (char *)NULL);
        _exit(127);
    }
    lm_wire_in in;
    assert_int_equal(next_msg(r, &in), LUMESH__MSG__BODY_HELLO);
    Lumesh__Welcome w = LUMESH__WELCOME__INIT;
    w.worker = 1;
    w.join = in.msg->hello->join;
    lm_wire_in_free(&in);
    send_msg(r, 0, LUMESH__MSG__BODY_WELCOME, &w);
}

/* Also after a failed check (cmocka's teardown): no worker is left behind. */
static int rig_stop(void **state)
{
    rig *r = *state;
    if (r->worker > 0) {
        kill(r->worker, SIGKILL);
        waitpid(r->worker, NULL, 0);
    }
    if (r->sock)
        zmq_close(r->sock);
    if (r->ctx)
        zmq_ctx_term(r->ctx);
    if (r->dir)
        lmt_rmdir(r->dir);
    memset(r, 0, sizeof *r);
    return 0;
}

static void offer(rig *r, uint64_t req, const lm_asset_hash *h)
{
    ProtobufCBinaryData list = {LM_ASSET_HASH_BYTES, (uint8_t *)h->b};
    Lumesh__Offer o = LUMESH__OFFER__INIT;
    o.n_assets = 1;
    o.assets = &list;
    send_msg(r, req, LUMESH__MSG__BODY_OFFER, &o);
}

static void chunk(rig *r, uint64_t req, const lm_asset_hash *h, const uint8_t *data, size_t off,
                  size_t len)
{
    Lumesh__Asset a = LUMESH__ASSET__INIT;
    a.hash = (ProtobufCBinaryData){LM_ASSET_HASH_BYTES, (uint8_t *)h->b};
    a.size = ASSET_BYTES;
    a.offset = off;
    a.data = (ProtobufCBinaryData){len, (uint8_t *)data + off};
    send_msg(r, req, LUMESH__MSG__BODY_ASSET, &a);
}

/* Need for exactly the one asset h, to request req. */
static void expect_need(rig *r, uint64_t req, const lm_asset_hash *h)
{
    lm_wire_in in;
    assert_int_equal(next_msg(r, &in), LUMESH__MSG__BODY_NEED);
    assert_int_equal(in.msg->req, req);
    assert_int_equal(in.msg->need->n_assets, 1);
    assert_memory_equal(in.msg->need->assets[0].data, h->b, LM_ASSET_HASH_BYTES);
    lm_wire_in_free(&in);
}

static void test_offer_again_after_a_broken_transfer(void **state)
{
    rig *r = *state;
    rig_start(r);
    uint8_t data[ASSET_BYTES];
    for (int i = 0; i < ASSET_BYTES; i++)
        data[i] = (uint8_t)(i * 7 + 3);
    lm_asset_hash h;
    lm_asset_hash_of(data, sizeof data, &h);

    offer(r, 10, &h);
    expect_need(r, 10, &h);
    chunk(r, 10, &h, data, 0, ASSET_BYTES / 2); /* then the coordinator gives the worker up */

    offer(r, 20, &h); /* ... and takes it back */
    expect_need(r, 20, &h);
    chunk(r, 20, &h, data, 0, ASSET_BYTES / 2);
    chunk(r, 20, &h, data, ASSET_BYTES / 2, ASSET_BYTES - ASSET_BYTES / 2);
    lm_wire_in in;
    assert_int_equal(next_msg(r, &in), LUMESH__MSG__BODY_READY);
    assert_int_equal(in.msg->req, 20);
    lm_wire_in_free(&in);

    offer(r, 30, &h); /* cached now: Ready at once */
    assert_int_equal(next_msg(r, &in), LUMESH__MSG__BODY_READY);
    assert_int_equal(in.msg->req, 30);
    lm_wire_in_free(&in);
}

static int rig_setup(void **state)
{
    static rig r;
    memset(&r, 0, sizeof r);
    *state = &r;
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_offer_again_after_a_broken_transfer, rig_setup,
                                        rig_stop),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
