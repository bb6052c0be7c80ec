/* coordinator/simplify/adapt_curvature.h — curvature estimation for the shape-adaptive simplifier
 * (Park, Lee & Lee 2003): unit vertex normals of a mesh (area-weighted triangle normals) and the
 * directional curvature along an edge, from the circle through both ends tangent to the surface
 * there (the two-point form of the paper's circle fit to the edge's polyline: exact on a sphere,
 * 0 along a cylinder's ruling, 1/R across it). */
#ifndef LM_COORDINATOR_SIMPLIFY_ADAPT_CURVATURE_H
#define LM_COORDINATOR_SIMPLIFY_ADAPT_CURVATURE_H

#include "common/mesh.h"

/* n = (p1 - p0) x (p2 - p0) of triangle t (twice its area long), in double precision. */
void co_adapt_tri_cross(const lm_mesh *m, uint32_t t, double n[3]);

/* out[v] = unit area-weighted normal of vertex v over its live triangles ((0,0,0) where none or
 * degenerate). out holds m->n_verts entries. */
void co_adapt_vertex_normals(const lm_mesh *m, double (*out)[3]);

/* Curvature (1 / radius) of the surface along the direction a -> b: the mean over both ends of
 * 2 |n . (other - this)| / |b - a|^2 (the circle through a and b tangent to the plane of the
 * normal there). 0 for a zero-length edge. */
double co_adapt_edge_curvature(const double a[3], const double na[3], const double b[3],
                               const double nb[3]);

#endif
