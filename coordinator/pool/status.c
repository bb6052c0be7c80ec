/* coordinator/pool/status.c — the client side of status queries (status.h). */
#include "coordinator/pool/status.h"

#include <string.h>
#include <zmq.h>

#include "proto/keys.h"

static lm_status ask(void *sock, const char *endpoint, const char *keys)
{
    lm_status st = lm_wire_socket_setup(sock, 0);
    if (st == LM_OK && keys)
        st = lm_keys_client(sock, keys);
    if (st == LM_OK && zmq_connect(sock, endpoint) != 0)
        st = lm_fail(LM_E_INVALID, "cannot connect to '%s': %s", endpoint,
                     zmq_strerror(zmq_errno()));
    Lumesh__Status q = LUMESH__STATUS__INIT;
    lm_msg m;
    lm_wire_msg_init(&m, 1, 0, LUMESH__MSG__BODY_STATUS, &q);
    return st == LM_OK ? lm_wire_send(sock, NULL, 0, &m) : st;
}

/* Frames until the StatusResult (a Rejoin or Welcome may come first to a new peer: skipped). */
static lm_status answer(void *sock, double timeout_s, lm_wire_in *out)
{
    for (int tries = 0; tries < 8; tries++) {
        lm_wire_frame f;
        lm_status st = lm_wire_recv(sock, 0, (int)(1000.0 * timeout_s), &f);
        if (st == LM_OK && !f.data)
            st = lm_fail(LM_E_IO, "no answer within %.1f s", timeout_s);
        if (st == LM_OK)
            st = lm_wire_decode(f.data, f.size, out);
        lm_wire_frame_release(&f);
        if (st != LM_OK)
            return st;
        if (out->msg->body_case == LUMESH__MSG__BODY_STATUS_RESULT)
            return LM_OK;
        lm_wire_in_free(out);
    }
    return lm_fail(LM_E_FORMAT, "the coordinator did not answer the status query");
}

lm_status co_pool_status_query(const char *endpoint, const char *keys, double timeout_s,
                               lm_wire_in *out)
{
    memset(out, 0, sizeof *out);
    void *ctx = zmq_ctx_new(), *sock = ctx ? zmq_socket(ctx, ZMQ_DEALER) : NULL;
    lm_status st = sock
                       ? ask(sock, endpoint, keys)
                       : lm_fail(LM_E_INTERNAL, "creating a socket: %s", zmq_strerror(zmq_errno()));
    if (st == LM_OK)
        st = answer(sock, timeout_s, out);
    if (st != LM_OK)
        lm_wire_in_free(out);
    if (sock)
        zmq_close(sock);
    if (ctx)
        zmq_ctx_term(ctx);
    return st;
}
