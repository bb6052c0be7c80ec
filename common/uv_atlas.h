/* common/uv_atlas.h — atlases for bakes onto meshes without usable texture coordinates.
 *
 * The packed chart atlas (lm_atlas_packed, the bakes' default): the charts of common/uv_charts.h
 * (adjacent triangles within LM_CHART_MAX_ANGLE degrees of their seed's normal, projected on its
 * plane without flips or overlaps), every chart at the same texel density (world area -> texel
 * area), shelf-packed tallest first into the square map with LM_ATLAS_GUTTER texels between
 * charts (half that from the map's sides), the density the largest that packs. Inside a chart a
 * vertex keeps one wedge (per normal and colour it has there); chart borders split wedges. Every
 * triangle of a chart runs counter-clockwise in UV (no mirrored frame), so a wedge's tangent
 * (common/tangents.h) is the sum of its chart triangles' frames made orthogonal to its normal,
 * which all project to the chart plane's one u axis: they differ only by the triangles' tilt out of
 * that plane, which the angle bound keeps small. Engines interpolate those tangents and the bake
 * follows them; lumesh's renderers take each triangle's own frame (equal on a planar chart, close
 * on a curved one; tests/unit/test_atlas.c measures it).
 *
 * The per-triangle atlas (lm_atlas_per_triangle, the fallback where charts do not pack), the
 * simplest honest atlas, for bakes onto meshes without usable texture
 * coordinates: one chart per triangle, each mapped to a right isosceles triangle in its own cell
 * of a square grid, LM_ATLAS_MARGIN texels from the cell's sides (room for the bake's gutters).
 * Limits: triangles are distorted (every one gets the same texel area and a right angle, whatever
 * its shape and size), half of each cell stays empty, and every edge is a chart border (filtered
 * maps show the seams the gutters only soften). Each corner gets a wedge of its own, so a
 * wedge's tangent (common/tangents.h) is its triangle's frame: renderers that use the triangle's
 * frame and engines that interpolate the stored tangents see the same map. */
#ifndef LM_COMMON_UV_ATLAS_H
#define LM_COMMON_UV_ATLAS_H

#include "common/error.h"
#include "common/mesh.h"

#define LM_ATLAS_MARGIN 5  /* texels between a chart and its cell's sides */
#define LM_ATLAS_MIN_LEG 4 /* a chart's legs must span at least this many texels */
#ifndef LM_ATLAS_GUTTER
#define LM_ATLAS_GUTTER 4 /* texels between the packed atlas's charts */
#endif

/* A copy of src (live elements, their order kept) whose triangles each have three wedges of
 * their own with the atlas's texture coordinates for a size x size map. Materials and parts are
 * copied. LM_E_INVALID when the grid's cells are too small at this size (one line). */
lm_status lm_atlas_per_triangle(const lm_mesh *src, int size, lm_mesh **out);

/* The side of the smallest square grid with `charts` cells (at least 1). */
uint32_t lm_atlas_cells(uint32_t charts);

/* LM_OK when cells of a grid `cells` a side leave a chart its LM_ATLAS_MIN_LEG at this size, else
 * LM_E_INVALID with one line naming the size needed (`charts`: the triangles, for the message). */
lm_status lm_atlas_fits(uint32_t charts, uint32_t cells, int size);

/* Corner k's texture coordinates of the chart in cell i of a grid `cells` a side, size x size:
 * the bits lm_atlas_per_triangle gives (maps in the loop rewrite a renderer's triangles with
 * them). */
void lm_atlas_cell_uv(uint32_t i, uint32_t cells, int size, int k, float uv[2]);

/* As lm_atlas_per_triangle, but triangle t's chart lies in cell t mod cells² of a grid `cells` a
 * side chosen by the caller (so that a triangle keeps its chart while its id lives: the optimizer's
 * maps in the loop, coordinator/job/bake_loop.h); the i-th live triangle of src is still the
 * copy's triangle i. LM_E_INVALID as lm_atlas_fits. */
lm_status lm_atlas_by_id(const lm_mesh *src, int size, uint32_t cells, lm_mesh **out);

/* A copy of src (live vertices and triangles, their order kept) with the packed chart atlas's
 * texture coordinates for a size x size map (*n_charts: its charts; may be NULL). Materials and
 * parts copied. LM_E_INVALID when the charts do not pack at any density (one line); LM_E_NOMEM.
 * Blocking, deterministic. */
lm_status lm_atlas_packed(const lm_mesh *src, int size, lm_mesh **out, uint32_t *n_charts);

#endif
