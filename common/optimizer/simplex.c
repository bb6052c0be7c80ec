/* common/optimizer/simplex.c — downhill simplex (Numerical Recipes' amoeba) with batched
 * evaluation of the initial simplex and of shrinks, size and value convergence tests and an
 * evaluation limit. */
#include "common/optimizer/simplex.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct lm_simplex {
    uint32_t max_dim;
    double *p;    /* (max_dim + 1) rows of dim coordinates */
    double *y;    /* max_dim + 1 values */
    double *psum; /* max_dim */
    double *ptry; /* max_dim */
};

typedef struct run {
    lm_simplex *s;
    uint32_t n;
    const double *step;
    lm_simplex_eval_fn fn;
    void *ctx;
    uint32_t evals, max_evals;
    double size_tol, f_tol, f_rtol;
} run;

lm_status lm_simplex_create(uint32_t max_dim, lm_simplex **out)
{
    if (max_dim == 0 || max_dim > 100000)
        return lm_fail(LM_E_RANGE, "simplex dimension %u out of range 1..100000", max_dim);
    lm_simplex *s = calloc(1, sizeof *s);
    if (!s)
        return lm_fail(LM_E_NOMEM, "out of memory creating a simplex");
    s->max_dim = max_dim;
    s->p = malloc((size_t)(max_dim + 1) * max_dim * sizeof *s->p);
    s->y = malloc((size_t)(max_dim + 1) * sizeof *s->y);
    s->psum = malloc((size_t)max_dim * sizeof *s->psum);
    s->ptry = malloc((size_t)max_dim * sizeof *s->ptry);
    if (!s->p || !s->y || !s->psum || !s->ptry) {
        lm_simplex_destroy(s);
        return lm_fail(LM_E_NOMEM, "out of memory creating a %u-dimensional simplex", max_dim);
    }
    *out = s;
    return LM_OK;
}

void lm_simplex_destroy(lm_simplex *s)
{
    if (!s)
        return;
    free(s->p);
    free(s->y);
    free(s->psum);
    free(s->ptry);
    free(s);
}

static double *row(const run *r, uint32_t i)
{
    return r->s->p + (size_t)i * r->n;
}

static lm_status eval(run *r, const double *pts, uint32_t k, double *vals)
{
    r->evals += k;
    return r->fn(r->ctx, pts, k, vals);
}

static lm_status init_simplex(run *r, const double *x, const double *f0)
{
    for (uint32_t i = 0; i <= r->n; i++) {
        memcpy(row(r, i), x, (size_t)r->n * sizeof *x);
        if (i > 0)
            row(r, i)[i - 1] += r->step[i - 1];
    }
    if (!f0)
        return eval(r, row(r, 0), r->n + 1, r->s->y);
    r->s->y[0] = *f0;
    return eval(r, row(r, 1), r->n, r->s->y + 1);
}

static void compute_psum(run *r)
{
    for (uint32_t j = 0; j < r->n; j++) {
        double sum = 0;
        for (uint32_t i = 0; i <= r->n; i++)
            sum += row(r, i)[j];
        r->s->psum[j] = sum;
    }
}

/* Lowest, highest and next-highest vertex (NR's tie rules). */
static void rank(const run *r, uint32_t *ilo, uint32_t *ihi, uint32_t *inhi)
{
    const double *y = r->s->y;
    *ilo = 0;
    if (y[0] > y[1]) {
        *ihi = 0;
        *inhi = 1;
    } else {
        *ihi = 1;
        *inhi = 0;
    }
    for (uint32_t i = 0; i <= r->n; i++) {
        if (y[i] <= y[*ilo])
            *ilo = i;
        if (y[i] > y[*ihi]) {
            *inhi = *ihi;
            *ihi = i;
        } else if (y[i] > y[*inhi] && i != *ihi) {
            *inhi = i;
        }
    }
}

static int converged(const run *r, uint32_t ilo, uint32_t ihi)
{
    const double *y = r->s->y;
    double spread = y[ihi] - y[ilo];
    if (isfinite(spread) && spread <= fmax(r->f_tol, r->f_rtol * fabs(y[ilo])))
        return 1;
    const double *best = row(r, ilo);
    for (uint32_t i = 0; i <= r->n; i++) {
        const double *p = row(r, i);
        for (uint32_t j = 0; j < r->n; j++)
            if (!(fabs(p[j] - best[j]) <= r->size_tol * fabs(r->step[j])))
                return 0;
    }
    return 1;
}

/* Extrapolate through the face opposite ihi by `fac`; replace ihi if better. */
static lm_status try_point(run *r, uint32_t ihi, double fac, double *ytry)
{
    double fac1 = (1.0 - fac) / r->n, fac2 = fac1 - fac;
    double *hi = row(r, ihi), *pt = r->s->ptry;
    for (uint32_t j = 0; j < r->n; j++)
        pt[j] = r->s->psum[j] * fac1 - hi[j] * fac2;
    lm_status s = eval(r, pt, 1, ytry);
    if (s)
        return s;
    if (*ytry < r->s->y[ihi]) {
        r->s->y[ihi] = *ytry;
        for (uint32_t j = 0; j < r->n; j++) {
            r->s->psum[j] += pt[j] - hi[j];
            hi[j] = pt[j];
        }
    }
    return LM_OK;
}

/* Contract every vertex halfway towards the best one; the n new vertices go out as one batch. */
static lm_status shrink(run *r, uint32_t ilo)
{
    if (ilo != 0) {
        for (uint32_t j = 0; j < r->n; j++) {
            double t = row(r, 0)[j];
            row(r, 0)[j] = row(r, ilo)[j];
            row(r, ilo)[j] = t;
        }
        double t = r->s->y[0];
        r->s->y[0] = r->s->y[ilo];
        r->s->y[ilo] = t;
    }
    const double *best = row(r, 0);
    for (uint32_t i = 1; i <= r->n; i++)
        for (uint32_t j = 0; j < r->n; j++)
            row(r, i)[j] = 0.5 * (row(r, i)[j] + best[j]);
    return eval(r, row(r, 1), r->n, r->s->y + 1);
}

/* One amoeba step. Sets *stop when the evaluation budget does not allow the next move. */
static lm_status amoeba_step(run *r, uint32_t ilo, uint32_t ihi, uint32_t inhi, int *stop)
{
    double ytry;
    lm_status s = try_point(r, ihi, -1.0, &ytry);
    if (s)
        return s;
    if (ytry <= r->s->y[ilo]) {
        if (r->evals < r->max_evals)
            s = try_point(r, ihi, 2.0, &ytry);
        return s;
    }
    if (ytry < r->s->y[inhi])
        return LM_OK;
    double ysave = r->s->y[ihi];
    if (r->evals >= r->max_evals) {
        *stop = 1;
        return LM_OK;
    }
    if ((s = try_point(r, ihi, 0.5, &ytry)))
        return s;
    if (ytry < ysave)
        return LM_OK;
    if (r->evals + r->n > r->max_evals) {
        *stop = 1;
        return LM_OK;
    }
    s = shrink(r, ilo);
    compute_psum(r);
    return s;
}

static lm_status amoeba(run *r, uint32_t *best, int *conv)
{
    compute_psum(r);
    for (;;) {
        uint32_t ilo, ihi, inhi;
        rank(r, &ilo, &ihi, &inhi);
        *best = ilo;
        if (converged(r, ilo, ihi)) {
            *conv = 1;
            return LM_OK;
        }
        if (r->evals >= r->max_evals)
            return LM_OK;
        int stop = 0;
        lm_status s = amoeba_step(r, ilo, ihi, inhi, &stop);
        if (s || stop) {
            rank(r, &ilo, &ihi, &inhi);
            *best = ilo;
            return s;
        }
    }
}

lm_status lm_simplex_minimize(lm_simplex *s, uint32_t dim, double *x, const double *step,
                              const double *f0, const lm_simplex_opts *opts, lm_simplex_eval_fn fn,
                              void *ctx, lm_simplex_result *res)
{
    static const lm_simplex_opts none = {0};
    const lm_simplex_opts *o = opts ? opts : &none;
    if (dim > s->max_dim)
        return lm_fail(LM_E_RANGE, "simplex of %u dimensions exceeds its capacity %u", dim,
                       s->max_dim);
    run r = {.s = s, .n = dim, .step = step, .fn = fn, .ctx = ctx};
    r.max_evals = o->max_evals ? o->max_evals : (dim ? 32 * dim : 1);
    r.size_tol = o->size_tol > 0 ? o->size_tol : 1.0 / 16;
    r.f_tol = o->f_tol;
    r.f_rtol = o->f_rtol;
    memset(res, 0, sizeof *res);
    if (dim == 0) {
        lm_status st = f0 ? LM_OK : eval(&r, x, 1, &res->f_best);
        if (f0)
            res->f_best = *f0;
        res->evals = r.evals;
        res->converged = 1;
        return st;
    }
    lm_status st = init_simplex(&r, x, f0);
    uint32_t best = 0;
    if (!st)
        st = amoeba(&r, &best, &res->converged);
    memcpy(x, row(&r, best), (size_t)dim * sizeof *x);
    res->f_best = s->y[best];
    res->evals = r.evals;
    return st;
}
