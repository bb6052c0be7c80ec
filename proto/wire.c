/* proto/wire.c — framing over ZeroMQ (one message = one frame, a routing frame first on ROUTER
 * sockets), socket limits, and bounded decoding of Msg. */
#include "proto/wire.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <zmq.h>

void lm_wire_msg_init(lm_msg *m, uint64_t req, uint64_t seq, Lumesh__Msg__BodyCase body_case,
                      void *body)
{
    lumesh__msg__init(m);
    m->req = req;
    m->seq = seq;
    m->body_case = body_case;
    memcpy(&m->hello, &body, sizeof body); /* every member of the body union is a pointer */
}

lm_status lm_wire_socket_setup(void *sock, int is_router)
{
    int64_t max = LM_WIRE_MAX_FRAME;
    int zero = 0, one = 1;
    if (zmq_setsockopt(sock, ZMQ_MAXMSGSIZE, &max, sizeof max) != 0 ||
        zmq_setsockopt(sock, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        (is_router && zmq_setsockopt(sock, ZMQ_ROUTER_MANDATORY, &one, sizeof one) != 0))
        return lm_fail(LM_E_INTERNAL, "setting up a socket: %s", zmq_strerror(errno));
    return LM_OK;
}

lm_status lm_wire_send(void *sock, const void *id, size_t id_len, const lm_msg *m)
{
    size_t n = lumesh__msg__get_packed_size(m);
    if (n > LM_WIRE_MAX_FRAME)
        return lm_fail(LM_E_RANGE, "a %s message of %zu bytes exceeds the frame limit of %u",
                       lm_wire_body_name(m), n, LM_WIRE_MAX_FRAME);
    zmq_msg_t msg;
    if (zmq_msg_init_size(&msg, n) != 0)
        return lm_fail(LM_E_NOMEM, "out of memory for a %zu-byte message", n);
    lumesh__msg__pack(m, zmq_msg_data(&msg));
    /* never blocking: a peer that is not there (or not reading) loses the message */
    if (id && zmq_send(sock, id, id_len, ZMQ_SNDMORE | ZMQ_DONTWAIT) < 0) {
        int e = errno;
        zmq_msg_close(&msg);
        return lm_fail(e == EHOSTUNREACH || e == EAGAIN ? LM_E_IO : LM_E_INTERNAL,
                       "sending to a worker: %s", zmq_strerror(e));
    }
    if (zmq_msg_send(&msg, sock, ZMQ_DONTWAIT) < 0) {
        int e = errno;
        zmq_msg_close(&msg);
        return lm_fail(LM_E_IO, "sending a %s message: %s", lm_wire_body_name(m), zmq_strerror(e));
    }
    return LM_OK;
}

/* Drop the rest of a multi-part message (frames a lumesh peer never sends). */
static void drain(void *sock)
{
    int more = 1;
    size_t len = sizeof more;
    while (zmq_getsockopt(sock, ZMQ_RCVMORE, &more, &len) == 0 && more) {
        zmq_msg_t junk;
        zmq_msg_init(&junk);
        zmq_msg_recv(&junk, sock, 0);
        zmq_msg_close(&junk);
    }
}

static int has_more(void *sock)
{
    int more = 0;
    size_t len = sizeof more;
    return zmq_getsockopt(sock, ZMQ_RCVMORE, &more, &len) == 0 && more;
}

/* The routing frame of a ROUTER socket (the peer's id). */
static lm_status recv_identity(void *sock, lm_wire_frame *f)
{
    zmq_msg_t id;
    zmq_msg_init(&id);
    if (zmq_msg_recv(&id, sock, 0) < 0) {
        zmq_msg_close(&id);
        return lm_fail(LM_E_IO, "receiving: %s", zmq_strerror(errno));
    }
    size_t n = zmq_msg_size(&id);
    f->id_len = n < LM_WIRE_MAX_IDENTITY ? n : LM_WIRE_MAX_IDENTITY;
    memcpy(f->id, zmq_msg_data(&id), f->id_len);
    zmq_msg_close(&id);
    return LM_OK;
}

lm_status lm_wire_recv(void *sock, int is_router, int timeout_ms, lm_wire_frame *f)
{
    memset(f, 0, sizeof *f);
    zmq_pollitem_t item = {.socket = sock, .events = ZMQ_POLLIN};
    int rc = zmq_poll(&item, 1, timeout_ms);
    if (rc < 0)
        return errno == EINTR ? LM_OK : lm_fail(LM_E_IO, "waiting: %s", zmq_strerror(errno));
    if (rc == 0)
        return LM_OK;
    if (is_router) {
        lm_status st = recv_identity(sock, f);
        if (st != LM_OK)
            return st;
        if (!has_more(sock))
            return LM_OK; /* a routing frame alone: nothing to read */
    }
    zmq_msg_t *msg = malloc(sizeof *msg);
    if (!msg)
        return lm_fail(LM_E_NOMEM, "out of memory receiving");
    zmq_msg_init(msg);
    if (zmq_msg_recv(msg, sock, 0) < 0) {
        zmq_msg_close(msg);
        free(msg);
        return lm_fail(LM_E_IO, "receiving: %s", zmq_strerror(errno));
    }
    if (has_more(sock))
        drain(sock);
    f->zmsg_ = msg;
    f->data = zmq_msg_data(msg);
    f->size = zmq_msg_size(msg);
    return LM_OK;
}

void lm_wire_frame_release(lm_wire_frame *f)
{
    if (f->release_)
        f->release_(f->owner_, f);
    if (f->zmsg_) {
        zmq_msg_close(f->zmsg_);
        free(f->zmsg_);
    }
    memset(f, 0, sizeof *f);
}

/* ---- bounded decoding ---------------------------------------------------------------------- */

/* Each block carries its size in front (16 bytes keep the alignment) so that free can give it
 * back to the budget (ctx: the bytes left). */
static void *budget_alloc(void *ctx, size_t n)
{
    size_t *left = ctx;
    if (n > *left || n > SIZE_MAX - 16)
        return NULL;
    size_t *p = malloc(n + 16);
    if (!p)
        return NULL;
    *left -= n;
    p[0] = n;
    return (uint8_t *)p + 16;
}

static void budget_free(void *ctx, void *ptr)
{
    if (!ptr)
        return;
    size_t *left = ctx;
    size_t *p = (size_t *)(void *)((uint8_t *)ptr - 16);
    *left += p[0];
    free(p);
}

lm_status lm_wire_decode(const uint8_t *data, size_t size, lm_wire_in *in)
{
    memset(in, 0, sizeof *in);
    if (size == 0 || size > LM_WIRE_MAX_FRAME)
        return lm_fail(LM_E_FORMAT, "a frame of %zu bytes is not a message", size);
    in->budget_left_ = LM_WIRE_DECODE_BUDGET(size);
    in->alloc_ = (ProtobufCAllocator){
        .alloc = budget_alloc, .free = budget_free, .allocator_data = &in->budget_left_};
    in->msg = lumesh__msg__unpack(&in->alloc_, size, data);
    if (!in->msg)
        return lm_fail(LM_E_FORMAT,
                       "a frame of %zu bytes does not decode (malformed, or too large unpacked)",
                       size);
    if (in->msg->body_case == LUMESH__MSG__BODY__NOT_SET) {
        lm_wire_in_free(in);
        return lm_fail(LM_E_FORMAT, "a message with no known body");
    }
    return LM_OK;
}

void lm_wire_in_free(lm_wire_in *in)
{
    if (in->msg)
        lumesh__msg__free_unpacked(in->msg, &in->alloc_);
    in->msg = NULL;
}

const char *lm_wire_case_name(Lumesh__Msg__BodyCase c)
{
    const ProtobufCFieldDescriptor *f =
        protobuf_c_message_descriptor_get_field(&lumesh__msg__descriptor, (unsigned)c);
    return f ? f->name : "none";
}

const char *lm_wire_body_name(const lm_msg *m)
{
    return m ? lm_wire_case_name(m->body_case) : "none";
}
