/* coordinator/simplify/adapt_edge_length.h — the optimal edge length of Park, Lee & Lee 2003
 * (equations 3, 5, 10): the longest chord of a circle of radius r whose arc stays within e of it,
 * L_opt = 2 sqrt(2 e r - e^2), and the optimality of an edge, Omega = L - L_opt (equation 11;
 * negative: shorter than it may be, a candidate to simplify). */
#ifndef LM_COORDINATOR_SIMPLIFY_ADAPT_EDGE_LENGTH_H
#define LM_COORDINATOR_SIMPLIFY_ADAPT_EDGE_LENGTH_H

/* L_opt for curvature kappa (1/r) and tolerance e > 0, at most cap (flat: kappa 0 gives cap). A
 * radius below e is taken as e (the chord formula needs r >= e; such a tight bend gets the
 * shortest optimal length, 2e). */
double co_adapt_optimal_length(double kappa, double e, double cap);

/* Omega = length - L_opt. */
double co_adapt_optimality(double length, double kappa, double e, double cap);

#endif
