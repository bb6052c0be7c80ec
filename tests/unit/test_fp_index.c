/* tests/unit/test_fp_index.c — the footprint index (coordinator/simplify/fp_index.c) names every
 * entry whose latest footprint meets a query's in some view (co_fp_meet, tested against all of
 * them): random small rectangles, rectangles past the image's edges and far beyond, the whole
 * plane, empty ones; footprints replaced and dropped; enough churn to sweep the stale records. */
#include <stdlib.h>
#include <string.h>

#include "coordinator/simplify/fp_index.h"
#include "test_support.h"

#define N_ENTRIES 600
#define N_VIEWS 5

typedef struct named {
    uint8_t hit[N_ENTRIES];
} named;

static void on_hit(void *ctx, uint32_t i)
{
    named *n = ctx;
    assert_true(i < N_ENTRIES);
    n->hit[i] = 1;
}

static int32_t coord(int size)
{
    switch (rand() % 8) {
    case 0:
        return -3 - rand() % 50; /* just before the image */
    case 1:
        return size + rand() % 50; /* just after it */
    case 2:
        return rand() % 2 ? -900000 : 900000; /* far beyond */
    default:
        return rand() % size;
    }
}

/* A random footprint: per view empty, a small box, one reaching past an edge, or the plane. */
static void random_fp(co_rect *fp, const lm_view_set *vs)
{
    co_fp_clear(fp, vs->count);
    for (uint32_t h = 0; h < vs->count; h++) {
        int w = vs->views[h].width, r = rand() % 10;
        if (r == 0)
            continue;
        if (r == 1) {
            co_fp_grow_plane(&fp[h]);
            continue;
        }
        int32_t x = r < 4 ? coord(w) : rand() % w, y = r < 4 ? coord(w) : rand() % w;
        int32_t dx = rand() % (r == 4 ? 60 : 6), dy = rand() % (r == 4 ? 60 : 6);
        fp[h] = (co_rect){x, y, x + dx, y + dy};
    }
}

static void check_queries(co_fpx *x, co_rect (*latest)[N_VIEWS], const uint8_t *alive,
                          const lm_view_set *vs)
{
    for (int q = 0; q < 200; q++) {
        co_rect fp[N_VIEWS];
        random_fp(fp, vs);
        named n;
        memset(&n, 0, sizeof n);
        co_fpx_query(x, fp, on_hit, &n);
        for (uint32_t i = 0; i < N_ENTRIES; i++)
            if (alive[i] && co_fp_meet(latest[i], fp, vs->count))
                assert_true(n.hit[i]);
    }
}

static void names_every_entry_that_meets(void **state)
{
    (void)state;
    lm_view_set vs;
    float centre[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(&vs, N_VIEWS, 100, centre, 1.0f), LM_OK);
    vs.views[1].width = 37; /* sizes that are not a whole number of cells */
    vs.views[1].height = 53;
    co_fpx *x = NULL;
    assert_int_equal(co_fpx_create(&vs, &x), LM_OK);
    static co_rect latest[N_ENTRIES][N_VIEWS];
    static uint8_t alive[N_ENTRIES];
    memset(alive, 0, sizeof alive);
    srand(7);
    for (int round = 0; round < 40; round++) {
        for (int k = 0; k < N_ENTRIES / 2; k++) {
            uint32_t i = (uint32_t)rand() % N_ENTRIES;
            if (rand() % 5 == 0) {
                co_fpx_drop(x, i);
                alive[i] = 0;
                continue;
            }
            random_fp(latest[i], &vs);
            assert_int_equal(co_fpx_put(x, i, latest[i]), LM_OK);
            alive[i] = 1;
        }
        check_queries(x, latest, alive, &vs);
    }
    co_fpx_destroy(x);
}

typedef struct dropping {
    co_fpx *x;
    named n;
} dropping;

static void drop_hit(void *ctx, uint32_t i)
{
    dropping *d = ctx;
    d->n.hit[i] = 1;
    co_fpx_drop(d->x, i);
}

/* The loop drops the entries it marks stale while the query runs: named then, never again. */
static void drops_during_a_query(void **state)
{
    (void)state;
    lm_view_set vs;
    float centre[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(&vs, N_VIEWS, 64, centre, 1.0f), LM_OK);
    dropping d = {0};
    assert_int_equal(co_fpx_create(&vs, &d.x), LM_OK);
    static co_rect fp[N_ENTRIES][N_VIEWS];
    srand(11);
    for (uint32_t i = 0; i < N_ENTRIES; i++) {
        random_fp(fp[i], &vs);
        assert_int_equal(co_fpx_put(d.x, i, fp[i]), LM_OK);
    }
    co_rect q[N_VIEWS];
    random_fp(q, &vs);
    co_fpx_query(d.x, q, drop_hit, &d);
    uint32_t met = 0;
    for (uint32_t i = 0; i < N_ENTRIES; i++)
        if (co_fp_meet(fp[i], q, vs.count)) {
            assert_true(d.n.hit[i]);
            met++;
        }
    assert_true(met > 0);
    named again;
    memset(&again, 0, sizeof again);
    co_fpx_query(d.x, q, on_hit, &again);
    for (uint32_t i = 0; i < N_ENTRIES; i++)
        assert_false(d.n.hit[i] && again.hit[i]);
    co_fpx_destroy(d.x);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(names_every_entry_that_meets),
        cmocka_unit_test(drops_during_a_query),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
