/* tests/unit/test_indexed_heap.c — the indexed min-heap (common/indexed_heap.h): after any mix of
 * sets, re-keys, removes and pops its top is the least (prio, tie) of the ids in it, as a plain
 * scan of a model finds it; ids leave and come back; clear empties it. */
#include <stdlib.h>

#include "common/indexed_heap.h"
#include "test_support.h"

enum { IDS = 600 };

typedef struct model {
    int in[IDS];
    int64_t prio[IDS];
    uint64_t tie[IDS];
} model;

/* The model's least id, LM_IHEAP_OUT when empty. */
static uint32_t model_top(const model *m)
{
    uint32_t best = LM_IHEAP_OUT;
    for (uint32_t i = 0; i < IDS; i++) {
        if (!m->in[i])
            continue;
        if (best == LM_IHEAP_OUT || m->prio[i] < m->prio[best] ||
            (m->prio[i] == m->prio[best] && m->tie[i] < m->tie[best]))
            best = i;
    }
    return best;
}

static uint32_t model_count(const model *m)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < IDS; i++)
        n += m->in[i] != 0;
    return n;
}

static void check(const lm_iheap *h, const model *m)
{
    assert_int_equal(lm_iheap_top(h), model_top(m));
    assert_int_equal(lm_iheap_count(h), model_count(m));
}

static void test_top_is_least(void **state)
{
    (void)state;
    lm_iheap h;
    lm_iheap_init(&h);
    assert_true(lm_iheap_reserve(&h, IDS));
    assert_true(h.cap >= IDS);
    model m = {0};
    uint64_t seed = 11;
    for (int step = 0; step < 20000; step++) {
        uint32_t id = (uint32_t)(lmt_urand(&seed) * IDS);
        double r = lmt_urand(&seed);
        if (r < 0.55) {
            /* few distinct priorities so the ties decide often; ties distinct per id */
            m.prio[id] = (int64_t)(lmt_urand(&seed) * 8) - 4;
            m.tie[id] = (uint64_t)(IDS - id) << 32 | id;
            m.in[id] = 1;
            lm_iheap_set(&h, id, m.prio[id], m.tie[id]);
        } else if (r < 0.8) {
            m.in[id] = 0;
            lm_iheap_remove(&h, id);
        } else {
            uint32_t t = lm_iheap_top(&h);
            if (t != LM_IHEAP_OUT) {
                m.in[t] = 0;
                lm_iheap_remove(&h, t);
            }
        }
        assert_int_equal(lm_iheap_has(&h, id), m.in[id]);
        check(&h, &m);
    }
    /* drained, the ids come out in key order */
    for (uint32_t t; (t = lm_iheap_top(&h)) != LM_IHEAP_OUT;) {
        assert_int_equal(t, model_top(&m));
        m.in[t] = 0;
        lm_iheap_remove(&h, t);
    }
    check(&h, &m);
    lm_iheap_free(&h);
}

static void test_clear_and_grow(void **state)
{
    (void)state;
    lm_iheap h;
    lm_iheap_init(&h);
    assert_int_equal(lm_iheap_top(&h), LM_IHEAP_OUT);
    for (uint32_t id = 0; id < 5000; id++) {
        assert_true(lm_iheap_reserve(&h, id + 1));
        assert_false(lm_iheap_has(&h, id));
        lm_iheap_set(&h, id, -(int64_t)id, 0);
        assert_int_equal(lm_iheap_top(&h), id);
    }
    lm_iheap_clear(&h);
    assert_int_equal(lm_iheap_count(&h), 0);
    assert_int_equal(lm_iheap_top(&h), LM_IHEAP_OUT);
    for (uint32_t id = 0; id < 5000; id++)
        assert_false(lm_iheap_has(&h, id));
    lm_iheap_set(&h, 42, 7, 1);
    lm_iheap_set(&h, 41, 7, 2);
    assert_int_equal(lm_iheap_top(&h), 42);
    lm_iheap_set(&h, 42, 8, 1); /* re-keyed down the heap */
    assert_int_equal(lm_iheap_top(&h), 41);
    lm_iheap_remove(&h, 41);
    lm_iheap_remove(&h, 41); /* not in it: nothing */
    assert_int_equal(lm_iheap_top(&h), 42);
    assert_int_equal(lm_iheap_count(&h), 1);
    lm_iheap_free(&h);
    assert_int_equal(h.cap, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_top_is_least),
        cmocka_unit_test(test_clear_and_grow),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
