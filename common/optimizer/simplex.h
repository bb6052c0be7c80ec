/* common/optimizer/simplex.h — downhill simplex (Nelder–Mead, as Numerical Recipes' amoeba)
 * over n parameters, the paper's §5.1 continuous optimisation. The objective is a callback that
 * evaluates a BATCH of points: the initial n+1 vertices and a shrink's n new vertices go out as one
 * batch (the views answer a batch with one GPU synchronisation). Stops after max_evals evaluations
 * (32n by default), when the simplex has shrunk below a size tolerance (relative to the initial
 * step of each coordinate), or when all its values agree within a tolerance.
 * All work memory is allocated once by lm_simplex_create; minimising allocates nothing. */
#ifndef LM_COMMON_OPTIMIZER_SIMPLEX_H
#define LM_COMMON_OPTIMIZER_SIMPLEX_H

#include <stdint.h>

#include "common/error.h"

/* values[i] = f(points + i*dim) for i < n_points. A non-zero status aborts the minimisation. */
typedef lm_status (*lm_simplex_eval_fn)(void *ctx, const double *points, uint32_t n_points,
                                        double *values);

/* Zero means default for every field. */
typedef struct lm_simplex_opts {
    uint32_t max_evals; /* 0 = 32 * dim (at least 1) */
    double size_tol;    /* converged when every vertex lies within size_tol * |step_j| of the best
                           one in every coordinate j; 0 = 1/16 */
    double f_tol;       /* converged when f_max - f_min <= max(f_tol, f_rtol * |f_min|); 0 = 0 */
    double f_rtol;      /* 0 = 0 */
} lm_simplex_opts;

typedef struct lm_simplex_result {
    double f_best;
    uint32_t evals; /* evaluations requested through the callback */
    int converged;  /* 1 if a tolerance (not the evaluation limit) stopped it */
} lm_simplex_result;

typedef struct lm_simplex lm_simplex;

lm_status lm_simplex_create(uint32_t max_dim, lm_simplex **out);
void lm_simplex_destroy(lm_simplex *s);

/* Minimise from x (dim <= max_dim) with the initial simplex x, x + step_j e_j. If f0 is not NULL
 * it is f(x), known already, and not evaluated again. On return x holds the best point found and
 * res its value. dim == 0 evaluates x once (unless f0 is given). */
lm_status lm_simplex_minimize(lm_simplex *s, uint32_t dim, double *x, const double *step,
                              const double *f0, const lm_simplex_opts *opts, lm_simplex_eval_fn fn,
                              void *ctx, lm_simplex_result *res);

#endif
