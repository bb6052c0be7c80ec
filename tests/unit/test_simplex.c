/* tests/unit/test_simplex.c — downhill simplex on known functions: a quadratic bowl and the
 * Rosenbrock function in 2-4 dimensions converge near their minima; the evaluation limit is
 * respected; the initial simplex (and shrinks) go out as batches; a known f(x0) is not
 * re-evaluated; errors from the callback stop the minimisation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/simplex.h"
#include "test_support.h"

typedef struct counter {
    double (*f)(const double *x, uint32_t n);
    uint32_t dim;
    uint32_t calls, points, first_batch, max_batch;
    uint32_t fail_after; /* 0 = never */
} counter;

static lm_status eval(void *ctx, const double *pts, uint32_t n, double *vals)
{
    counter *c = ctx;
    if (c->calls == 0)
        c->first_batch = n;
    if (n > c->max_batch)
        c->max_batch = n;
    c->calls++;
    c->points += n;
    if (c->fail_after && c->points > c->fail_after)
        return lm_fail(LM_E_DEVICE, "planted failure");
    for (uint32_t i = 0; i < n; i++)
        vals[i] = c->f(pts + (size_t)i * c->dim, c->dim);
    return LM_OK;
}

static double bowl(const double *x, uint32_t n)
{
    double s = 0;
    for (uint32_t i = 0; i < n; i++) {
        double d = x[i] - (0.3 + 0.1 * i);
        s += (1.0 + i) * d * d;
    }
    return s;
}

static double rosenbrock(const double *x, uint32_t n)
{
    double s = 0;
    for (uint32_t i = 0; i + 1 < n; i++)
        s += 100.0 * pow(x[i + 1] - x[i] * x[i], 2) + pow(1.0 - x[i], 2);
    return s;
}

static void test_bowl_converges(void **state)
{
    (void)state;
    lm_simplex *s;
    assert_int_equal(lm_simplex_create(8, &s), LM_OK);
    double x[3] = {0, 0, 0}, step[3] = {0.5, 0.5, 0.5};
    counter c = {.f = bowl, .dim = 3};
    lm_simplex_opts o = {.max_evals = 2000, .size_tol = 1e-5};
    lm_simplex_result r;
    assert_int_equal(lm_simplex_minimize(s, 3, x, step, NULL, &o, eval, &c, &r), LM_OK);
    assert_true(r.converged);
    for (int i = 0; i < 3; i++)
        assert_true(fabs(x[i] - (0.3 + 0.1 * i)) < 1e-3);
    assert_true(r.f_best < 1e-6);
    assert_int_equal(r.evals, c.points);
    assert_int_equal(c.first_batch, 4); /* the initial n+1 points in one batch */
    assert_true(bowl(x, 3) == r.f_best);
    lm_simplex_destroy(s);
}

static void rosen(uint32_t dim, uint32_t max_evals, double tol)
{
    lm_simplex *s;
    assert_int_equal(lm_simplex_create(dim, &s), LM_OK);
    double x[4], step[4];
    for (uint32_t i = 0; i < dim; i++) {
        x[i] = i % 2 ? 1.0 : -1.2;
        step[i] = 0.5;
    }
    counter c = {.f = rosenbrock, .dim = dim};
    lm_simplex_opts o = {.max_evals = max_evals, .size_tol = 1e-9, .f_tol = 1e-14};
    lm_simplex_result r;
    double start = rosenbrock(x, dim);
    /* restart from the best point, as Numerical Recipes recommends */
    for (int round = 0; round < 3; round++)
        assert_int_equal(lm_simplex_minimize(s, dim, x, step, NULL, &o, eval, &c, &r), LM_OK);
    assert_true(r.f_best < start);
    for (uint32_t i = 0; i < dim; i++)
        assert_true(fabs(x[i] - 1.0) < tol);
    lm_simplex_destroy(s);
}

static void test_rosenbrock_2d(void **state)
{
    (void)state;
    rosen(2, 2000, 1e-3);
}

static void test_rosenbrock_3d(void **state)
{
    (void)state;
    rosen(3, 6000, 1e-2);
}

static void test_rosenbrock_4d(void **state)
{
    (void)state;
    rosen(4, 10000, 1e-2);
}

static void test_eval_limit(void **state)
{
    (void)state;
    lm_simplex *s;
    assert_int_equal(lm_simplex_create(4, &s), LM_OK);
    for (uint32_t dim = 1; dim <= 4; dim++) {
        double x[4] = {-1.2, 1, -1.2, 1}, step[4] = {0.01, 0.01, 0.01, 0.01};
        counter c = {.f = rosenbrock, .dim = dim};
        lm_simplex_result r;
        /* default limit: 32 n evaluations; tiny steps on Rosenbrock never converge that fast */
        assert_int_equal(lm_simplex_minimize(s, dim, x, step, NULL, NULL, eval, &c, &r), LM_OK);
        assert_true(c.points <= 32 * dim);
        assert_int_equal(r.evals, c.points);
        assert_true(c.max_batch <= dim + 1);
        lm_simplex_opts o = {.max_evals = 7};
        counter c2 = {.f = bowl, .dim = dim};
        assert_int_equal(lm_simplex_minimize(s, dim, x, step, NULL, &o, eval, &c2, &r), LM_OK);
        assert_true(c2.points <= 7);
    }
    lm_simplex_destroy(s);
}

static void test_known_f0_and_dim0(void **state)
{
    (void)state;
    lm_simplex *s;
    assert_int_equal(lm_simplex_create(3, &s), LM_OK);
    double x[3] = {0, 0, 0}, step[3] = {0.2, 0.2, 0.2};
    double f0 = bowl(x, 3);
    counter c = {.f = bowl, .dim = 3};
    lm_simplex_result r;
    assert_int_equal(lm_simplex_minimize(s, 3, x, step, &f0, NULL, eval, &c, &r), LM_OK);
    assert_int_equal(c.first_batch, 3); /* x0 not re-evaluated */
    assert_true(r.f_best < f0);
    /* dim 0: one evaluation, or none when f0 is known */
    counter c0 = {.f = bowl, .dim = 0};
    assert_int_equal(lm_simplex_minimize(s, 0, x, step, NULL, NULL, eval, &c0, &r), LM_OK);
    assert_int_equal(c0.points, 1);
    assert_int_equal(r.evals, 1);
    counter c1 = {.f = bowl, .dim = 0};
    assert_int_equal(lm_simplex_minimize(s, 0, x, step, &f0, NULL, eval, &c1, &r), LM_OK);
    assert_int_equal(c1.points, 0);
    lm_simplex_destroy(s);
}

static double flat(const double *x, uint32_t n)
{
    (void)x;
    (void)n;
    return 5.0;
}

static void test_flat_stops_at_once(void **state)
{
    (void)state;
    lm_simplex *s;
    assert_int_equal(lm_simplex_create(6, &s), LM_OK);
    double x[6] = {0}, step[6] = {1, 1, 1, 1, 1, 1};
    counter c = {.f = flat, .dim = 6};
    lm_simplex_result r;
    assert_int_equal(lm_simplex_minimize(s, 6, x, step, NULL, NULL, eval, &c, &r), LM_OK);
    assert_true(r.converged);
    assert_int_equal(c.points, 7); /* all values agree after the initial batch */
    lm_simplex_destroy(s);
}

static void test_errors(void **state)
{
    (void)state;
    lm_simplex *s;
    assert_int_not_equal(lm_simplex_create(0, &s), LM_OK);
    assert_int_equal(lm_simplex_create(2, &s), LM_OK);
    double x[3] = {0, 0, 0}, step[3] = {1, 1, 1};
    counter c = {.f = bowl, .dim = 2, .fail_after = 5};
    lm_simplex_result r;
    assert_int_equal(lm_simplex_minimize(s, 2, x, step, NULL, NULL, eval, &c, &r), LM_E_DEVICE);
    assert_int_equal(lm_simplex_minimize(s, 3, x, step, NULL, NULL, eval, &c, &r), LM_E_RANGE);
    lm_simplex_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bowl_converges),     cmocka_unit_test(test_rosenbrock_2d),
        cmocka_unit_test(test_rosenbrock_3d),      cmocka_unit_test(test_rosenbrock_4d),
        cmocka_unit_test(test_eval_limit),         cmocka_unit_test(test_known_f0_and_dim0),
        cmocka_unit_test(test_flat_stops_at_once), cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
