/* tests/unit/test_lane_delta.c — a start mesh record or a collapse queue as a delta against an
 * earlier one (lane_delta.h): applied to its base it gives the record bit for bit (a few vertices
 * moved: a small delta; new slots, which grow the arrays: still small; queue entries added,
 * dropped, changed: a delta of those entries; unrelated bytes; empty buffers); a
 * delta for another base, every truncation, a trailing byte, ops past the base or the result are
 * refused with LM_E_FORMAT and one line, and no flipped byte crashes the apply. */
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/lane_delta.h"
#include "common/optimizer/lane_start.h"
#include "common/optimizer/lane_wire.h"
#include "test_support.h"

static uint8_t *record(const lm_mesh *m, size_t *n)
{
    uint8_t *buf = NULL;
    assert_int_equal(lm_lane_mesh_encode(m, &buf, n), LM_OK);
    return buf;
}

/* delta(base -> cur) applied to base gives cur; returns the delta's length. */
static size_t round_trip(const uint8_t *base, size_t n_base, const uint8_t *cur, size_t n_cur)
{
    uint8_t *d = NULL, *out = NULL;
    size_t n_d = 0, n_out = 0;
    assert_int_equal(lm_lane_delta_encode(base, n_base, cur, n_cur, &d, &n_d), LM_OK);
    assert_int_equal(lm_lane_delta_apply(base, n_base, d, n_d, &out, &n_out), LM_OK);
    assert_int_equal(n_out, n_cur);
    assert_true(n_cur == 0 || memcmp(out, cur, n_cur) == 0);
    free(d);
    free(out);
    return n_d;
}

static void test_moved_vertices(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(4);
    size_t n_base, n_cur;
    uint8_t *base = record(m, &n_base);
    for (uint32_t v = 0; v < m->n_verts; v += m->n_verts / 5) {
        m->pos[v][0] *= 1.01f;
        m->pos[v][2] += 0.001f;
    }
    uint8_t *cur = record(m, &n_cur);
    size_t n_d = round_trip(base, n_base, cur, n_cur);
    assert_true(n_d < n_cur / 50); /* a few records, not the mesh */
    assert_int_equal(round_trip(base, n_base, base, n_base) <= 32, 1); /* unchanged: one copy */
    free(cur);
    /* a new vertex slot grows the arrays: the sections after it are not shifted */
    uint32_t v;
    const float p[3] = {0.5f, 0.25f, 2};
    assert_int_equal(lm_mesh_add_vertex(m, p, &v), LM_OK);
    cur = record(m, &n_cur);
    assert_true(n_cur > n_base);
    n_d = round_trip(base, n_base, cur, n_cur);
    assert_true(n_d < n_cur / 50);
    free(base);
    free(cur);
    lm_mesh_destroy(m);
}

static void test_any_bytes(void **state)
{
    (void)state;
    uint64_t seed = 7;
    for (int t = 0; t < 200; t++) {
        size_t n_base = (size_t)(lmt_urand(&seed) * 3000),
               n_cur = (size_t)(lmt_urand(&seed) * 3000);
        uint8_t *base = malloc(n_base + 1), *cur = malloc(n_cur + 1);
        for (size_t i = 0; i < n_base; i++)
            base[i] = (uint8_t)(lmt_urand(&seed) * 4); /* few symbols: runs match by chance */
        for (size_t i = 0; i < n_cur; i++)
            cur[i] =
                i < n_base && lmt_urand(&seed) < 0.9 ? base[i] : (uint8_t)(lmt_urand(&seed) * 4);
        round_trip(base, n_base, cur, n_cur);
        free(base);
        free(cur);
    }
    round_trip(NULL, 0, NULL, 0);
}

/* A queue's section (lane_wire.h) of n entries: edges (i, i + 1 + i % 3) scaled by `stride`. */
static uint8_t *queue_section(uint32_t n, uint32_t stride, int64_t est_add, size_t *len)
{
    lm_cq_entry *e = calloc(n + 1, sizeof *e);
    for (uint32_t i = 0; i < n; i++)
        e[i] = (lm_cq_entry){i * stride, i * stride + 1 + i % 3, (int64_t)i * 10 + est_add, 1, 1};
    uint8_t *buf = NULL;
    assert_int_equal(lm_lane_queue_encode(e, n, &buf, len), LM_OK);
    free(e);
    return buf;
}

/* delta(base -> cur) for queues applied to base gives cur; returns the delta's length. */
static size_t queue_trip(const uint8_t *base, size_t n_base, const uint8_t *cur, size_t n_cur)
{
    uint8_t *d = NULL, *out = NULL;
    size_t n_d = 0, n_out = 0;
    assert_int_equal(lm_lane_queue_delta_encode(base, n_base, cur, n_cur, &d, &n_d), LM_OK);
    assert_int_equal(lm_lane_delta_apply(base, n_base, d, n_d, &out, &n_out), LM_OK);
    assert_int_equal(n_out, n_cur);
    assert_true(n_cur == 0 || memcmp(out, cur, n_cur) == 0);
    free(d);
    free(out);
    return n_d;
}

/* Entries removed, added and changed in the middle of a sorted queue: a delta of those entries,
 * not of everything after them (the entries shift by whole records). */
static void test_queue(void **state)
{
    (void)state;
    size_t n_base, n_cur;
    uint8_t *base = queue_section(3000, 4, 0, &n_base);
    assert_true(queue_trip(base, n_base, base, n_base) <= 40); /* unchanged: one copy */
    /* the same edges with every 100th est changed, entry 1500 dropped, one edge added */
    lm_cq_entry *e = NULL;
    uint32_t n = 0;
    assert_int_equal(lm_lane_queue_decode(base, n_base, 4 * 3000 + 8, &e, &n), LM_OK);
    assert_int_equal(n, 3000);
    for (uint32_t i = 0; i < n; i += 100)
        e[i].est -= 5;
    memmove(e + 1500, e + 1501, (n - 1501) * sizeof *e); /* dropped */
    n--;
    e = realloc(e, (n + 1) * sizeof *e);
    memmove(e + 11, e + 10, (n - 10) * sizeof *e); /* added between entries 9 and 10 */
    e[10] = (lm_cq_entry){39, 40, 7, 0, 1};
    n++;
    uint8_t *cur = NULL;
    assert_int_equal(lm_lane_queue_encode(e, n, &cur, &n_cur), LM_OK);
    free(e);
    size_t n_d = queue_trip(base, n_base, cur, n_cur);
    assert_true(n_d < 40 * (12 + 24)); /* ~32 changed entries, an op each */
    free(cur);
    /* fewer and more entries, other edges altogether, empty, not a queue at all */
    uint8_t *other = queue_section(500, 7, 3, &n_cur);
    queue_trip(base, n_base, other, n_cur);
    queue_trip(other, n_cur, base, n_base);
    free(other);
    other = queue_section(0, 1, 0, &n_cur);
    queue_trip(base, n_base, other, n_cur);
    queue_trip(other, n_cur, base, n_base);
    queue_trip(base, n_base - 3, base, n_base);
    queue_trip(base, n_base, base + 5, n_base - 5);
    queue_trip(NULL, 0, NULL, 0);
    free(other);
    free(base);
}

static void refused(const uint8_t *base, size_t n_base, const uint8_t *d, size_t n_d)
{
    uint8_t *out = (uint8_t *)1;
    size_t n_out = 1;
    assert_int_equal(lm_lane_delta_apply(base, n_base, d, n_d, &out, &n_out), LM_E_FORMAT);
    assert_null(out);
    assert_int_equal(n_out, 0);
    assert_true(lm_last_error()[0] != '\0');
    lm_clear_error();
}

static void put32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static void test_hostile(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2);
    size_t n_base, n_cur, n_d;
    uint8_t *base = record(m, &n_base), *d = NULL;
    m->pos[3][1] += 0.25f;
    uint8_t *cur = record(m, &n_cur);
    assert_int_equal(lm_lane_delta_encode(base, n_base, cur, n_cur, &d, &n_d), LM_OK);
    for (size_t n = 0; n < n_d; n++) /* every truncation */
        refused(base, n_base, d, n);
    uint8_t *longer = malloc(n_d + 1);
    memcpy(longer, d, n_d);
    longer[n_d] = 0;
    refused(base, n_base, longer, n_d + 1); /* a trailing byte */
    refused(base, n_base - 1, d, n_d);      /* another base */
    /* one op that copies past the base / skips past it / names a longer result */
    uint8_t op[28] = {0};
    put32(op, 0x4c444e4cu), put32(op + 4, 8), put32(op + 8, 9), put32(op + 12, 1);
    put32(op + 20, 9);
    refused(base, 8, op, sizeof op);
    put32(op + 16, 9), put32(op + 20, 0);
    refused(base, 8, op, sizeof op);
    put32(op + 16, 0), put32(op + 20, 8), put32(op + 8, 9);
    refused(base, 8, op, sizeof op); /* the result it names is longer than what it makes */
    put32(op + 12, 0x7fffffffu);
    refused(base, 8, op, sizeof op); /* more ops than its bytes hold */
    /* no single flipped byte crashes it (refused, or some record the hash check then refuses) */
    for (size_t i = 0; i < n_d; i++)
        for (int bit = 0; bit < 8; bit++) {
            memcpy(longer, d, n_d);
            longer[i] ^= (uint8_t)(1u << bit);
            uint8_t *out = NULL;
            size_t n_out = 0;
            lm_status st = lm_lane_delta_apply(base, n_base, longer, n_d, &out, &n_out);
            assert_true(st == LM_OK || st == LM_E_FORMAT);
            free(out);
            lm_clear_error();
        }
    free(longer);
    free(d);
    free(base);
    free(cur);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_moved_vertices),
        cmocka_unit_test(test_any_bytes),
        cmocka_unit_test(test_queue),
        cmocka_unit_test(test_hostile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
