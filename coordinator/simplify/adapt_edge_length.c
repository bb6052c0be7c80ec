/* coordinator/simplify/adapt_edge_length.c — the optimal edge length and the optimality value of
 * the shape-adaptive simplifier (see adapt_edge_length.h). */
#include "coordinator/simplify/adapt_edge_length.h"

#include <math.h>

double co_adapt_optimal_length(double kappa, double e, double cap)
{
    if (!(kappa > 0))
        return cap;
    double r = 1.0 / kappa;
    if (r < e)
        r = e;
    double l = 2.0 * sqrt(2.0 * e * r - e * e);
    return l < cap ? l : cap;
}

double co_adapt_optimality(double length, double kappa, double e, double cap)
{
    return length - co_adapt_optimal_length(kappa, e, cap);
}
