/* tests/unit/test_fiber.c — fibers (common/optimizer/fiber.h), as the lanes use them: each
 * resume runs a fiber exactly up to its next yield, several fibers interleave in the order they
 * are resumed with their own stacks and locals intact, a fiber whose function returns says so, a
 * deep call chain fits in a lane's stack, and a suspended or never started fiber can be destroyed.
 */
#include <stdint.h>
#include <string.h>

#include "common/optimizer/fiber.h"
#include "test_support.h"

typedef struct walker {
    lm_fiber *f;
    int id, steps;
    int *log, *n_log;
} walker;

static void walk(void *arg)
{
    walker *w = arg;
    volatile int mine = w->id * 1000; /* a local that must survive every switch */
    for (int i = 0; i < w->steps; i++) {
        w->log[(*w->n_log)++] = mine + i;
        lm_fiber_yield(w->f);
    }
}

static void test_interleave(void **state)
{
    (void)state;
    int log[64], n_log = 0;
    walker w[3];
    for (int k = 0; k < 3; k++) {
        w[k] = (walker){.id = k + 1, .steps = k + 2, .log = log, .n_log = &n_log};
        assert_int_equal(lm_fiber_create(LM_FIBER_STACK_BYTES, walk, &w[k], &w[k].f), LM_OK);
    }
    int done[3] = {0};
    for (int round = 0; round < 5; round++)
        for (int k = 0; k < 3; k++)
            if (!done[k])
                done[k] = lm_fiber_resume(w[k].f);
    /* walker k logs k+2 steps, then returns on the resume after its last yield */
    int want[] = {1000, 2000, 3000, 1001, 2001, 3001, 2002, 3002, 3003};
    assert_int_equal(n_log, 9);
    assert_memory_equal(log, want, sizeof want);
    for (int k = 0; k < 3; k++) {
        assert_true(done[k]);
        lm_fiber_destroy(w[k].f);
    }
}

static uint64_t deep(int n)
{
    volatile uint8_t buf[512];
    memset((void *)buf, n & 0xff, sizeof buf);
    return n == 0 ? 1 : deep(n - 1) + buf[n % sizeof buf];
}

typedef struct digger {
    uint64_t result;
    lm_fiber *self;
} digger;

static void dig(void *arg)
{
    digger *d = arg;
    d->result = deep(4000); /* some 2-3 MB of stack, more under sanitizers */
    lm_fiber_yield(d->self);
}

static void test_deep_stack_and_destroy(void **state)
{
    (void)state;
    digger d = {0, NULL};
    assert_int_equal(lm_fiber_create(LM_FIBER_STACK_BYTES, dig, &d, &d.self), LM_OK);
    assert_int_equal(lm_fiber_resume(d.self), 0); /* suspended in its yield */
    assert_true(d.result == deep(4000));
    lm_fiber_destroy(d.self); /* suspended: dropped */
    lm_fiber *never = NULL;
    assert_int_equal(lm_fiber_create(0, dig, &d, &never), LM_OK); /* the least stack */
    lm_fiber_destroy(never);
    lm_fiber_destroy(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_interleave),
        cmocka_unit_test(test_deep_stack_and_destroy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
