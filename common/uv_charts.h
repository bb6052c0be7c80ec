/* common/uv_charts.h — the charts of the packed atlas (common/uv_atlas.h): the live triangles cut
 * into charts of adjacent triangles, each flattened by projection onto its seed triangle's plane.
 * A chart grows breadth-first over shared edges (an edge of exactly two live triangles of the same
 * material and part, traversed in opposite directions) while each new triangle's normal stays
 * within LM_CHART_MAX_ANGLE degrees of the seed's, its projection keeps its orientation (no flip)
 * and does not overlap (separating axes, shared edges and corners allowed) any triangle already in
 * the chart, up to LM_CHART_MAX_TRIS triangles. Seeds and growth in triangle order, no hashing: the
 * same charts on every host. The flattened chart is turned so its bounding rectangle is the
 * smallest over its convex hull's edge directions, and laid with its longer side along x. Double
 * precision, no contracted multiply-adds. */
#ifndef LM_COMMON_UV_CHARTS_H
#define LM_COMMON_UV_CHARTS_H

#include "common/error.h"
#include "common/mesh.h"

#ifndef LM_CHART_MAX_ANGLE
#define LM_CHART_MAX_ANGLE 30.0 /* degrees between a chart triangle's normal and its seed's */
#endif
/* a chart's triangles at most (the overlap test is linear in them) */
#define LM_CHART_MAX_TRIS 2048

typedef struct lm_charts {
    uint32_t n_tris;    /* live triangles of the mesh */
    uint32_t *tri;      /* [n_tris] the mesh's triangle id of the i-th live one */
    uint32_t *chart;    /* [n_tris] its chart */
    double (*xy)[3][2]; /* [n_tris] its corners in its chart's frame (world units, from 0) */
    uint32_t n_charts;
    double (*extent)[2]; /* [n_charts] width >= height of each chart's rectangle (world units) */
    double area;         /* the charts' flattened area summed (world units²) */
} lm_charts;

/* m's charts into *c (caller frees with lm_charts_free). Blocking; LM_E_NOMEM. */
lm_status lm_charts_make(const lm_mesh *m, lm_charts *c);
void lm_charts_free(lm_charts *c);

/* 1 when 2-D triangles a and b overlap in more than an edge or a corner (separating axes with a
 * tolerance of 1e-7 of the longer edge); triangles without area never overlap. */
int lm_tri2_overlap(const double a[3][2], const double b[3][2]);

#endif
