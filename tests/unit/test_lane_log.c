/* tests/unit/test_lane_log.c — what isolated lanes build on (lanes.h): a copy of the collapse
 * queue pops the same sequence as the original and changes independently of it; its observer is
 * told every change (set, reset, remove, pop) with the entry as left, and is not copied; a lane's
 * log replays its queue changes with vertex ids mapped, dropping what names a vertex of no mesh or
 * an edge not in the mesh (removals always), and its statistics adds in order, to the same bits as
 * the adds made directly. */
#include <string.h>

#include "common/mesh_topology.h"
#include "common/optimizer/collapse_queue.h"
#include "common/optimizer/lane_log.h"
#include "test_support.h"

static lm_cq *queue_of(int n)
{
    lm_cq *q;
    assert_int_equal(lm_cq_create(&q), LM_OK);
    uint64_t s = 7;
    for (int i = 0; i < n; i++)
        assert_int_equal(lm_cq_set(q, (uint32_t)i, (uint32_t)i + 1 + (uint32_t)(lmt_urand(&s) * 5),
                                   (int64_t)(lmt_urand(&s) * 100) - 50, i % 4, i % 7 != 0),
                         LM_OK);
    return q;
}

/* Pops q dry into out (at most cap), returns the count. */
static uint32_t drain(lm_cq *q, lm_cq_entry *out, uint32_t cap)
{
    uint32_t n = 0;
    while (n < cap && lm_cq_pop(q, &out[n]))
        n++;
    return n;
}

static void test_copy_pops_the_same(void **state)
{
    (void)state;
    lm_cq *a = queue_of(3000), *b = queue_of(10), *c;
    assert_int_equal(lm_cq_create(&c), LM_OK);
    for (uint32_t i = 0; i < 3000; i += 5)
        lm_cq_remove(a, i, i + 1);
    assert_int_equal(lm_cq_copy(b, a), LM_OK); /* into a smaller one, and an empty one */
    assert_int_equal(lm_cq_copy(c, a), LM_OK);
    assert_int_equal(lm_cq_count(b), lm_cq_count(a));
    static lm_cq_entry ea[4000], eb[4000], ec[4000];
    assert_int_equal(lm_cq_set(b, 1, 2, -1000, 0, 1), LM_OK); /* the copy changes alone */
    lm_cq_entry e;
    assert_true(lm_cq_peek(b, &e) && e.a == 1 && e.est == -1000);
    assert_true(lm_cq_peek(a, &e) && !(e.a == 1 && e.b == 2 && e.est == -1000));
    assert_int_equal(lm_cq_pop(b, &e), 1);
    uint32_t na = drain(a, ea, 4000), nb = drain(b, eb, 4000), nc = drain(c, ec, 4000);
    assert_true(na > 100);
    assert_int_equal(na, nc);
    assert_memory_equal(ea, ec, na * sizeof *ea);
    /* b: the same, less (1, 2) which its pop took */
    uint32_t j = 0;
    for (uint32_t i = 0; i < na; i++)
        if (!(ea[i].a == 1 && ea[i].b == 2))
            assert_memory_equal(&ea[i], &eb[j++], sizeof *ea);
    assert_int_equal(j, nb);
    lm_cq_destroy(a);
    lm_cq_destroy(b);
    lm_cq_destroy(c);
}

/* The lane's new vertex 100 is *ctx in the mesh (UINT32_MAX: none); the others keep their ids. */
static uint32_t map_new(const void *ctx, uint32_t v)
{
    return v == 100 ? *(const uint32_t *)ctx : v;
}

static void test_observer_and_replay(void **state)
{
    (void)state;
    lm_cq *q, *copy, *target;
    assert_int_equal(lm_cq_create(&q), LM_OK);
    assert_int_equal(lm_cq_create(&copy), LM_OK);
    assert_int_equal(lm_cq_create(&target), LM_OK);
    lm_lane_log log;
    lm_lane_log_init(&log);
    lm_cq_observe(q, lm_lane_log_queue, &log);
    assert_int_equal(lm_cq_set(q, 2, 1, 40, 1, 1), LM_OK);
    assert_int_equal(lm_cq_reset(q, 0, 1), LM_OK);
    assert_int_equal(lm_cq_set(q, 1, 100, 5, 2, 1), LM_OK); /* 100: a vertex the lane made */
    assert_int_equal(lm_cq_set(q, 0, 15, 5, 2, 1), LM_OK);  /* not an edge of the grid */
    lm_cq_entry e;
    assert_int_equal(lm_cq_pop(q, &e), 1); /* (0, 1): est 0 */
    lm_cq_remove(q, 1, 2);
    assert_int_equal(log.n_queue, 6);
    assert_true(log.queue[0].present && log.queue[0].e.a == 1 && log.queue[0].e.b == 2);
    assert_true(log.queue[4].present && log.queue[4].e.a == 0 && !log.queue[4].e.in_heap);
    assert_true(!log.queue[5].present && log.queue[5].e.a == 1 && log.queue[5].e.b == 2);
    /* a copy is not observed */
    assert_int_equal(lm_cq_copy(copy, q), LM_OK);
    assert_int_equal(lm_cq_set(copy, 4, 5, 1, 0, 1), LM_OK);
    assert_int_equal(log.n_queue, 6);
    /* replay: 100 -> 5 (an edge (1, 5) of the 4x4 grid), (0, 15) dropped; (1, 2) set then removed
     */
    lm_mesh *m = lmt_make_grid(4);
    assert_int_equal(lm_cq_set(target, 1, 2, 9, 0, 1), LM_OK);
    uint32_t map_to = 5;
    assert_true(lm_mesh_edge_exists(m, 1, 5) && !lm_mesh_edge_exists(m, 0, 15));
    assert_int_equal(lm_lane_log_replay_queue(&log, target, m, map_new, &map_to), LM_OK);
    assert_false(lm_cq_get(target, 1, 2, &e));
    assert_true(lm_cq_get(target, 1, 5, &e) && e.est == 5 && e.level == 2);
    assert_true(lm_cq_get(target, 0, 1, &e) && e.est == 0 && e.level == -1 && !e.in_heap);
    assert_false(lm_cq_get(target, 0, 15, &e));
    assert_int_equal(lm_cq_count(target), 2);
    /* a lane whose changes were not kept: its new vertex is none, the entry dropped */
    map_to = UINT32_MAX;
    lm_cq_clear(target);
    assert_int_equal(lm_lane_log_replay_queue(&log, target, m, map_new, &map_to), LM_OK);
    assert_int_equal(lm_cq_count(target), 1); /* (0, 1) */
    lm_mesh_destroy(m);
    lm_lane_log_free(&log);
    lm_cq_destroy(q);
    lm_cq_destroy(copy);
    lm_cq_destroy(target);
}

static void test_stats_replay(void **state)
{
    (void)state;
    lm_move_stats direct, replayed;
    lm_move_stats_init(&direct, 20000, 1);
    replayed = direct;
    lm_stat imp_direct[LM_LEVELS] = {0}, imp_replayed[LM_LEVELS] = {0};
    lm_lane_log log;
    lm_lane_log_init(&log);
    uint64_t s = 3, now = 1000;
    for (int i = 0; i < 200; i++) {
        double x = lmt_urand(&s) * 1e5 - 7e4, t = 1 + (int)(lmt_urand(&s) * 60);
        now += (uint64_t)t;
        lm_move_kind k = (lm_move_kind)(i % 3);
        int level = (i / 3) % LM_LEVELS;
        lm_move_stats_add(&direct, k, level, x, t, now);
        assert_int_equal(lm_lane_log_add(&log, k, level, x, t, now), LM_OK);
        lm_stat_add(&imp_direct[level], -x, t, now, 50000);
        assert_int_equal(lm_lane_log_add(&log, LM_LANE_LOG_IMPROVE, level, -x, t, now), LM_OK);
    }
    lm_lane_log_replay_stats(&log, &replayed, imp_replayed, 50000);
    assert_memory_equal(&direct, &replayed, sizeof direct);
    assert_memory_equal(imp_direct, imp_replayed, sizeof imp_direct);
    lm_lane_log_clear(&log);
    assert_int_equal(log.n_adds, 0);
    lm_lane_log_free(&log);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_copy_pops_the_same),
        cmocka_unit_test(test_observer_and_replay),
        cmocka_unit_test(test_stats_replay),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
