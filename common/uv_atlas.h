/* common/uv_atlas.h — the simplest honest atlas, for bakes onto meshes without usable texture
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

/* A copy of src (live elements, their order kept) whose triangles each have three wedges of
 * their own with the atlas's texture coordinates for a size x size map. Materials and parts are
 * copied. LM_E_INVALID when the grid's cells are too small at this size (one line). */
lm_status lm_atlas_per_triangle(const lm_mesh *src, int size, lm_mesh **out);

#endif
