/* tests/unit/test_lane_wire.c — a lane's request and result on the wire (lane_wire.h): they come
 * back field for field and re-encode to the same bytes; every truncation, a trailing byte, bad
 * kinds, huge counts, ids out of range and non-finite values are refused with LM_E_FORMAT, and no
 * single flipped byte crashes the decoder. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/lane_wire.h"
#include "test_support.h"

#define N_VERTS 100u

static void fill_stat(lm_stat *s, uint64_t *seed)
{
    *s = (lm_stat){lmt_urand(seed),
                   lmt_urand(seed) - 0.5,
                   lmt_urand(seed),
                   lmt_urand(seed) * 9,
                   (uint64_t)(lmt_urand(seed) * 1e6),
                   (uint64_t)(lmt_urand(seed) * 1e3)};
}

static void make_request(lm_lane_request *q)
{
    uint64_t seed = 3;
    lm_lane_request_init(q);
    q->index = 2, q->n_group = 4, q->a = 7, q->b = 11, q->n_verts = N_VERTS, q->clock = 123456;
    for (uint32_t v = 20; v < 40; v += 3)
        assert_int_equal(lm_lane_request_veto(q, v), LM_OK);
    q->stats.half_life = 5000, q->stats.min_weight = 0.5;
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        for (int l = 0; l < LM_LEVELS; l++)
            fill_stat(&q->stats.op[k][l], &seed);
    q->tp_cfg = (lm_teleport_config){20000, 50000, 3000};
    q->last_collapse = 777, q->last_time = 99;
    for (int l = 0; l < LM_LEVELS; l++)
        fill_stat(&q->improve[l], &seed);
    q->n_queue = 30;
    q->queue = calloc(q->n_queue, sizeof *q->queue);
    for (uint32_t i = 0; i < q->n_queue; i++)
        q->queue[i] =
            (lm_cq_entry){i, i + 1 + i % 3, (int64_t)i * 1000 - 7000, (int32_t)(i % 5) - 1, i % 2};
}

static void make_result(lm_lane_result *r)
{
    lm_lane_result_init(r);
    snprintf(r->msg, sizeof r->msg, "%s", "all well");
    const double x[5] = {0.25, -1.5, 3.0, 1e-9, 42.0};
    const uint32_t dims[3] = {2, 0, 3};
    size_t at = 0;
    for (uint32_t i = 0; i < 3; i++) {
        lm_move_record m = {(lm_move_kind)(i + 1),
                            (int)i,
                            3 + i,
                            50 + i,
                            i == 2 ? N_VERTS + 1 : LM_NONE,
                            0,
                            dims[i],
                            x + at,
                            -100 - (int64_t)i};
        assert_int_equal(lm_lane_result_accepted(r, &m, -(int64_t)i), LM_OK);
        at += dims[i];
    }
    r->d_acc = -303, r->mesh_hash = 0x1234567890abcdefull, r->total = -300, r->evals = 250;
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        r->attempted[k] = 10 + (uint64_t)k, r->accepted[k] = (uint64_t)k;
    r->searches = 2, r->searches_failed = 1, r->collapses_tried = 9;
    r->last_collapse = 4321, r->last_time = 1234;
    for (uint32_t i = 0; i < 5; i++)
        assert_int_equal(lm_lane_log_add(&r->log, i % 5 == 4 ? LM_LANE_LOG_IMPROVE : i % 4,
                                         (int)(i % 4), -1.5 * i, 20.0 + i, 1000 + i),
                         LM_OK);
    for (uint32_t i = 0; i < 6; i++)
        lm_lane_log_queue(&r->log, &(lm_cq_entry){i, N_VERTS + i % 2, 5 * (int64_t)i, 1, i % 2},
                          (int)(i % 3 != 0));
    for (uint32_t v = 0; v < 8; v++)
        assert_int_equal(lm_idset_add(&r->touched, v * 7 % 13), LM_OK);
}

static uint8_t *encode_request(const lm_lane_request *q, size_t *len)
{
    uint8_t *buf;
    assert_int_equal(lm_lane_request_encode(q, &buf, len), LM_OK);
    return buf;
}

static uint8_t *encode_result(const lm_lane_result *r, size_t *len)
{
    uint8_t *buf;
    assert_int_equal(lm_lane_result_encode(r, &buf, len), LM_OK);
    return buf;
}

static lm_status decode_request(const uint8_t *buf, size_t len)
{
    lm_lane_request q;
    lm_lane_request_init(&q);
    lm_status st = lm_lane_request_decode(buf, len, &q);
    lm_lane_request_free(&q);
    return st;
}

static lm_status decode_result(const uint8_t *buf, size_t len)
{
    lm_lane_result r;
    lm_lane_result_init(&r);
    lm_status st = lm_lane_result_decode(buf, len, N_VERTS, &r);
    lm_lane_result_free(&r);
    return st;
}

static void test_request_round_trip(void **state)
{
    (void)state;
    lm_lane_request q, d;
    make_request(&q);
    lm_lane_request_init(&d);
    size_t len, len2;
    uint8_t *buf = encode_request(&q, &len);
    assert_int_equal(lm_lane_request_decode(buf, len, &d), LM_OK);
    assert_true(d.index == q.index && d.n_group == q.n_group && d.a == q.a && d.b == q.b &&
                d.n_verts == q.n_verts && d.clock == q.clock && d.n_vetoed == q.n_vetoed &&
                d.n_queue == q.n_queue && d.last_collapse == q.last_collapse);
    assert_memory_equal(d.vetoed, q.vetoed, q.n_vetoed * sizeof *q.vetoed);
    assert_memory_equal(&d.stats, &q.stats, sizeof q.stats);
    assert_memory_equal(d.improve, q.improve, sizeof q.improve);
    for (uint32_t i = 0; i < q.n_queue; i++)
        assert_true(d.queue[i].a == q.queue[i].a && d.queue[i].b == q.queue[i].b &&
                    d.queue[i].est == q.queue[i].est && d.queue[i].level == q.queue[i].level &&
                    d.queue[i].in_heap == q.queue[i].in_heap);
    assert_true(lm_lane_request_vetoed(&d, 23) && !lm_lane_request_vetoed(&d, 24));
    uint8_t *buf2 = encode_request(&d, &len2);
    assert_int_equal(len2, len);
    assert_memory_equal(buf2, buf, len);
    free(buf);
    free(buf2);
    lm_lane_request_free(&q);
    lm_lane_request_free(&d);
}

/* The head and the queue: head followed by queue is the whole request's bytes; each decodes
 * alone; the whole request is no head (trailing bytes) and an unsorted queue is refused. */
static void test_request_head_and_queue(void **state)
{
    (void)state;
    lm_lane_request q, d;
    make_request(&q);
    lm_lane_request_init(&d);
    size_t len, n_head, n_queue;
    uint8_t *buf = encode_request(&q, &len), *head = NULL, *queue = NULL;
    assert_int_equal(lm_lane_request_encode_head(&q, &head, &n_head), LM_OK);
    assert_int_equal(lm_lane_queue_encode(q.queue, q.n_queue, &queue, &n_queue), LM_OK);
    assert_int_equal(n_head + n_queue, len);
    assert_memory_equal(buf, head, n_head);
    assert_memory_equal(buf + n_head, queue, n_queue);
    assert_int_equal(lm_lane_request_decode_head(head, n_head, &d), LM_OK);
    assert_true(d.a == q.a && d.b == q.b && d.n_vetoed == q.n_vetoed && d.queue == NULL &&
                d.n_queue == 0);
    assert_int_equal(lm_lane_request_decode_head(buf, len, &d), LM_E_FORMAT);
    lm_cq_entry *e = NULL;
    uint32_t n = 0;
    assert_int_equal(lm_lane_queue_decode(queue, n_queue, N_VERTS, &e, &n), LM_OK);
    assert_int_equal(n, q.n_queue);
    assert_memory_equal(e, q.queue, n * sizeof *e);
    free(e);
    /* vertices past n_verts; out of order; a count beyond the bytes */
    assert_int_equal(lm_lane_queue_decode(queue, n_queue, 20, &e, &n), LM_E_FORMAT);
    assert_null(e);
    assert_int_equal(n, 0);
    memcpy(queue + 4, buf + n_head + 4 + 24, 8);
    assert_int_equal(lm_lane_queue_decode(queue, n_queue, N_VERTS, &e, &n), LM_E_FORMAT);
    queue[0] = 0xff;
    assert_int_equal(lm_lane_queue_decode(queue, n_queue, N_VERTS, &e, &n), LM_E_FORMAT);
    free(buf);
    free(head);
    free(queue);
    lm_lane_request_free(&q);
    lm_lane_request_free(&d);
}

static lm_status decode_head(const uint8_t *buf, size_t len)
{
    lm_lane_request q;
    lm_lane_request_init(&q);
    lm_status st = lm_lane_request_decode_head(buf, len, &q);
    lm_lane_request_free(&q);
    return st;
}

static lm_status decode_queue(const uint8_t *buf, size_t len)
{
    lm_cq_entry *e = NULL;
    uint32_t n = 0;
    lm_status st = lm_lane_queue_decode(buf, len, N_VERTS, &e, &n);
    free(e);
    return st;
}

static void test_result_round_trip(void **state)
{
    (void)state;
    lm_lane_result r, d;
    make_result(&r);
    lm_lane_result_init(&d);
    size_t len, len2;
    uint8_t *buf = encode_result(&r, &len);
    assert_int_equal(lm_lane_result_decode(buf, len, N_VERTS, &d), LM_OK);
    assert_string_equal(d.msg, "all well");
    assert_int_equal(d.n_ops, 3);
    assert_int_equal(d.n_xs, 5);
    assert_memory_equal(d.xs, r.xs, 5 * sizeof *r.xs);
    for (uint32_t i = 0; i < 3; i++)
        assert_true(d.ops[i].r.kind == r.ops[i].r.kind && d.ops[i].r.v == r.ops[i].r.v &&
                    d.ops[i].r.dim == r.ops[i].r.dim && d.ops[i].x_at == r.ops[i].x_at &&
                    d.ops[i].r.delta == r.ops[i].r.delta);
    assert_true(d.d_acc == r.d_acc && d.mesh_hash == r.mesh_hash && d.evals == r.evals &&
                d.collapses_tried == r.collapses_tried && d.last_time == r.last_time);
    assert_memory_equal(d.attempted, r.attempted, sizeof r.attempted);
    assert_memory_equal(d.log.adds, r.log.adds, r.log.n_adds * sizeof *r.log.adds);
    assert_int_equal(d.log.n_queue, r.log.n_queue);
    assert_int_equal(d.touched.n, r.touched.n);
    assert_memory_equal(d.touched.ids, r.touched.ids, r.touched.n * sizeof *r.touched.ids);
    uint8_t *buf2 = encode_result(&d, &len2);
    assert_int_equal(len2, len);
    assert_memory_equal(buf2, buf, len);
    free(buf);
    free(buf2);
    lm_lane_result_free(&r);
    lm_lane_result_free(&d);
}

/* Every prefix and one trailing byte refused; no flipped byte crashes. */
static void check_cut_and_flip(const uint8_t *buf, size_t len,
                               lm_status (*decode)(const uint8_t *, size_t))
{
    for (size_t n = 0; n < len; n++)
        assert_int_equal(decode(buf, n), LM_E_FORMAT);
    uint8_t *b = malloc(len + 1);
    memcpy(b, buf, len);
    b[len] = 0;
    assert_int_equal(decode(b, len + 1), LM_E_FORMAT);
    for (size_t i = 0; i < len; i++) {
        for (int bit = 0; bit < 8; bit += 3) {
            b[i] ^= (uint8_t)(1u << bit);
            lm_status st = decode(b, len);
            assert_true(st == LM_OK || st == LM_E_FORMAT);
            b[i] ^= (uint8_t)(1u << bit);
        }
    }
    free(b);
}

static void test_truncated_and_flipped(void **state)
{
    (void)state;
    lm_lane_request q;
    lm_lane_result r;
    make_request(&q);
    make_result(&r);
    size_t lq, lr;
    uint8_t *bq = encode_request(&q, &lq), *br = encode_result(&r, &lr);
    check_cut_and_flip(bq, lq, decode_request);
    check_cut_and_flip(br, lr, decode_result);
    uint8_t *h = NULL, *qq = NULL;
    size_t lh, lqq;
    assert_int_equal(lm_lane_request_encode_head(&q, &h, &lh), LM_OK);
    assert_int_equal(lm_lane_queue_encode(q.queue, q.n_queue, &qq, &lqq), LM_OK);
    check_cut_and_flip(h, lh, decode_head);
    check_cut_and_flip(qq, lqq, decode_queue);
    free(h);
    free(qq);
    free(bq);
    free(br);
    lm_lane_request_free(&q);
    lm_lane_result_free(&r);
}

static void put32(uint8_t *at, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        at[i] = (uint8_t)(v >> (8 * i));
}

/* The request with the u32 at byte off replaced by v: refused. */
static void refuse_request_u32(size_t off, uint32_t v)
{
    lm_lane_request q;
    make_request(&q);
    size_t len;
    uint8_t *buf = encode_request(&q, &len);
    put32(buf + off, v);
    assert_int_equal(decode_request(buf, len), LM_E_FORMAT);
    free(buf);
    lm_lane_request_free(&q);
}

static void refuse_result_u32(size_t off, uint32_t v)
{
    lm_lane_result r;
    make_result(&r);
    size_t len;
    uint8_t *buf = encode_result(&r, &len);
    put32(buf + off, v);
    assert_int_equal(decode_result(buf, len), LM_E_FORMAT);
    free(buf);
    lm_lane_result_free(&r);
}

static void test_hostile_fields(void **state)
{
    (void)state;
    /* request: magic, version, index >= group, group too large, edge a == b, vertex past n_verts,
     * a huge vetoed count, a vetoed id out of range, out of order */
    refuse_request_u32(0, 0x12345678);
    refuse_request_u32(4, 99);
    refuse_request_u32(8, 4);
    refuse_request_u32(12, LM_MAX_EDGES_IN_FLIGHT + 1);
    refuse_request_u32(20, 7);
    refuse_request_u32(16, N_VERTS);
    refuse_request_u32(36, 0xffffffffu);
    refuse_request_u32(40, N_VERTS);
    refuse_request_u32(44, 0);
    /* result: status, message length, operation count, kind, level, an id past the new ones, a
     * dimension whose parameters are not there, a NaN parameter */
    const size_t ops = 16 + strlen("all well"), op0 = ops + 4;
    refuse_result_u32(8, LM_E_COUNT_);
    refuse_result_u32(12, 5000);
    refuse_result_u32(ops, 0x40000000u);
    refuse_result_u32(op0, LM_MOVE_KINDS);
    refuse_result_u32(op0 + 4, LM_LEVELS);
    refuse_result_u32(op0 + 8, N_VERTS + LM_LANE_MAX_NEW_VERTS);
    refuse_result_u32(op0 + 20, 3);
    lm_lane_result r;
    make_result(&r);
    r.xs[1] = NAN;
    size_t len;
    uint8_t *buf = encode_result(&r, &len);
    assert_int_equal(decode_result(buf, len), LM_E_FORMAT);
    free(buf);
    lm_lane_result_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_request_round_trip), cmocka_unit_test(test_request_head_and_queue),
        cmocka_unit_test(test_result_round_trip),  cmocka_unit_test(test_truncated_and_flipped),
        cmocka_unit_test(test_hostile_fields),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
