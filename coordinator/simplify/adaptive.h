/* coordinator/simplify/adaptive.h — shape-adaptive simplification (Park, Lee & Lee 2003):
 * half-edge collapses ordered by the optimality Omega = L - L_opt of each edge (the least optimal
 * first), where L_opt comes from the directional curvature along the edge and the tolerance
 * (adapt_curvature.h, adapt_edge_length.h); sharp features kept (adapt_features.h). The loop is
 * in simplify_adaptive.c; co_simplify(..., CO_SIMPLIFY_ADAPTIVE, N) is its --target-verts form. */
#ifndef LM_COORDINATOR_SIMPLIFY_ADAPTIVE_H
#define LM_COORDINATOR_SIMPLIFY_ADAPTIVE_H

#include "common/mesh.h"

/* Where --target-verts searches the tolerance (fractions of the bounding-box diagonal). */
#define CO_ADAPT_SEARCH_START 1e-3
#define CO_ADAPT_SEARCH_MIN 1e-7
#define CO_ADAPT_SEARCH_MAX 0.5
#define CO_ADAPT_SEARCH_STEPS 5 /* bisection steps (in log) once the target is bracketed */
/* The checks hold the points they test within this share of the tolerance, so that the surface
 * between them (a sampled distance) stays within the whole tolerance too. */
#define CO_ADAPT_CHECK_SHARE 0.97
/* Points on the original's features (feature-line and corner vertices, feature-edge midpoints)
 * are held within this share of the tolerance: sharp edges kept tighter than smooth parts. */
#define CO_ADAPT_FEATURE_SHARE 0.25
#define CO_ADAPT_SAMPLE_STEPS 4     /* a changed triangle's sample grid: at least 12 points */
#define CO_ADAPT_SAMPLE_SPACING 3.0 /* and a step at most this x the tolerance */
#define CO_ADAPT_MAX_VALENCE 12     /* the paper's limit on edges at a vertex after a collapse */

typedef struct co_adapt_stats {
    double tolerance;   /* the tolerance used (fraction of the diagonal) */
    uint32_t runs;      /* simplification passes (the --target-verts search makes several) */
    uint32_t collapses; /* collapses kept in the final pass */
    uint32_t refused;   /* collapses tried and undone in the final pass */
    int soft_features;  /* 1 when --target-verts could not be reached with corners fixed and
                           feature-line vertices moving along their lines only: then features
                           are held by CO_ADAPT_FEATURE_SHARE of the tolerance alone */
} co_adapt_stats;

/* Simplify `in` (validated, with triangles). tolerance > 0: every collapse that keeps the surface
 * within tolerance x diagonal (see SIMPLIFY.md, "Shape-adaptive"), target_verts ignored.
 * tolerance 0: the smallest tolerance (searched) whose pass reaches target_verts (>= 4), stopped
 * at exactly target_verts (where the features' rules stop short of the target at any tolerance,
 * a scan's noise, the search runs again with the features held by the tolerance alone);
 * LM_E_RANGE with the best mesh when no tolerance reaches it. The
 * result keeps materials, attributes and parts (co_simplify_keep_parts). stats may be NULL. */
lm_status co_simplify_adaptive(const lm_mesh *in, double tolerance, uint32_t target_verts,
                               co_adapt_stats *stats, lm_mesh **out);

#endif
