/* tests/unit/test_binio.c — binio's memory streams (binio.h) give the bytes a FILE stream gives and
 * read them back the same (truncation sticky, lm_bin_left; a reader is not written to), and the
 * collapse queue's export (collapse_queue.h) is in (a, b) order after sets and removes (its slots
 * reused). */
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/binio.h"
#include "common/optimizer/collapse_queue.h"
#include "test_support.h"

static void put_all(lm_bin *b)
{
    lm_put_u32(b, 0xdeadbeefu);
    lm_put_u64(b, 0x0123456789abcdefull);
    lm_put_i64(b, -42);
    lm_put_f32(b, 1.5f);
    lm_put_f64(b, -0.25);
    const char text[] = "lanes";
    lm_put_bytes(b, text, sizeof text);
    for (uint32_t i = 0; i < 5000; i++) /* past the writer's first 4,096 bytes */
        lm_put_u32(b, i * 2654435761u);
}

static void test_same_bytes(void **state)
{
    (void)state;
    char *fbuf = NULL;
    size_t flen = 0;
    FILE *fp = open_memstream(&fbuf, &flen);
    assert_non_null(fp);
    lm_bin f;
    lm_bin_init(&f, fp, "file");
    put_all(&f);
    assert_int_equal(f.status, LM_OK);
    fclose(fp);

    lm_bin m;
    lm_bin_init_writer(&m, "memory");
    put_all(&m);
    uint8_t *mbuf = NULL;
    size_t mlen = 0;
    assert_int_equal(lm_bin_take(&m, &mbuf, &mlen), LM_OK);
    assert_int_equal(mlen, flen);
    assert_memory_equal(mbuf, fbuf, flen);

    lm_bin r;
    lm_bin_init_reader(&r, mbuf, mlen, "back");
    assert_int_equal(lm_get_u32(&r), 0xdeadbeefu);
    assert_true(lm_get_u64(&r) == 0x0123456789abcdefull);
    assert_true(lm_get_i64(&r) == -42);
    assert_true(lm_get_f32(&r) == 1.5f);
    assert_true(lm_get_f64(&r) == -0.25);
    char text[6];
    lm_get_bytes(&r, text, sizeof text);
    assert_string_equal(text, "lanes");
    assert_int_equal(lm_bin_left(&r), 5000u * 4);
    for (uint32_t i = 0; i < 5000; i++)
        assert_int_equal(lm_get_u32(&r), i * 2654435761u);
    assert_int_equal(lm_bin_left(&r), 0);
    assert_int_equal(r.status, LM_OK);
    free(mbuf);
    free(fbuf);
}

static void test_truncated_and_empty(void **state)
{
    (void)state;
    const uint8_t three[3] = {1, 2, 3};
    lm_bin r;
    lm_bin_init_reader(&r, three, sizeof three, "three bytes");
    assert_int_equal(lm_get_u32(&r), 0); /* truncated: zero, and sticky */
    assert_int_equal(r.status, LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "three bytes is truncated"));
    uint8_t one = 7;
    lm_get_bytes(&r, &one, 1);
    assert_int_equal(one, 0);

    lm_bin_init_reader(&r, three, sizeof three, "a reader");
    lm_put_u32(&r, 1); /* not written to: refused, sticky */
    assert_int_equal(r.status, LM_E_INTERNAL);
    assert_int_equal(lm_get_u32(&r), 0);

    lm_bin w;
    lm_bin_init_writer(&w, "nothing");
    uint8_t *buf = NULL;
    size_t len = 99;
    assert_int_equal(lm_bin_take(&w, &buf, &len), LM_OK);
    assert_non_null(buf);
    assert_int_equal(len, 0);
    free(buf);
}

static int cmp_pair(const void *x, const void *y)
{
    const lm_cq_entry *a = x, *b = y;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

static void test_queue_export_order(void **state)
{
    (void)state;
    lm_cq *q;
    assert_int_equal(lm_cq_create(&q), LM_OK);
    uint32_t x = 12345;
    for (uint32_t i = 0; i < 3000; i++) {
        x = x * 1103515245u + 12345u;
        uint32_t a = (x >> 8) % 500, b = a + 1 + (x >> 20) % 7;
        assert_int_equal(lm_cq_set(q, a, b, (int64_t)(x % 1000) - 500, (int)(x % 4) - 1, 1), LM_OK);
        if (i % 3 == 0) /* a remove frees a slot the next set reuses */
            lm_cq_remove(q, (x >> 12) % 500, (x >> 12) % 500 + 1 + (x >> 3) % 7);
    }
    lm_cq_entry *e = NULL;
    uint32_t n = 0;
    assert_int_equal(lm_cq_export(q, &e, &n), LM_OK);
    assert_int_equal(n, lm_cq_count(q));
    lm_cq_entry *sorted = malloc((n + 1) * sizeof *sorted);
    memcpy(sorted, e, n * sizeof *e);
    qsort(sorted, n, sizeof *sorted, cmp_pair);
    assert_memory_equal(e, sorted, n * sizeof *e); /* already in (a, b) order */
    for (uint32_t i = 0; i < n; i++) {
        lm_cq_entry g;
        assert_true(lm_cq_get(q, e[i].a, e[i].b, &g));
        assert_true(g.est == e[i].est && g.level == e[i].level);
        assert_true(i == 0 || cmp_pair(&e[i - 1], &e[i]) < 0);
    }
    free(sorted);
    free(e);
    lm_cq_destroy(q);
}

/* Sparse ids (a checkpoint's queue may name any vertex id): the export must not count over the
 * largest id (16 GiB here), and keeps (a, b) order. */
static void test_queue_export_sparse(void **state)
{
    (void)state;
    lm_cq *q;
    assert_int_equal(lm_cq_create(&q), LM_OK);
    assert_int_equal(lm_cq_set(q, 4000000000u, 4000000001u, 1, 0, 1), LM_OK);
    assert_int_equal(lm_cq_set(q, 5, 9, 2, 0, 1), LM_OK);
    assert_int_equal(lm_cq_set(q, 5, 6, 3, 0, 1), LM_OK);
    lm_cq_entry *e = NULL;
    uint32_t n = 0;
    assert_int_equal(lm_cq_export(q, &e, &n), LM_OK);
    assert_int_equal(n, 3);
    assert_true(e[0].a == 5 && e[0].b == 6 && e[1].a == 5 && e[1].b == 9);
    assert_true(e[2].a == 4000000000u && e[2].b == 4000000001u);
    free(e);
    lm_cq_destroy(q);
}

/* A fan: one vertex with many edges, set in falling order of b (the worst order for a per-vertex
 * insertion sort), exports in (a, b) order. */
static void test_queue_export_fan(void **state)
{
    (void)state;
    lm_cq *q;
    assert_int_equal(lm_cq_create(&q), LM_OK);
    const uint32_t n_fan = 20000;
    for (uint32_t i = 0; i < n_fan; i++)
        assert_int_equal(lm_cq_set(q, 7, 8 + n_fan - i, (int64_t)i, 0, 1), LM_OK);
    assert_int_equal(lm_cq_set(q, 3, 4, 1, 0, 1), LM_OK);
    lm_cq_entry *e = NULL;
    uint32_t n = 0;
    assert_int_equal(lm_cq_export(q, &e, &n), LM_OK);
    assert_int_equal(n, n_fan + 1);
    assert_true(e[0].a == 3 && e[0].b == 4);
    for (uint32_t i = 1; i < n; i++)
        assert_true(e[i].a == 7 && e[i].b == 8 + i);
    free(e);
    lm_cq_destroy(q);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_bytes),          cmocka_unit_test(test_truncated_and_empty),
        cmocka_unit_test(test_queue_export_order),  cmocka_unit_test(test_queue_export_fan),
        cmocka_unit_test(test_queue_export_sparse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
