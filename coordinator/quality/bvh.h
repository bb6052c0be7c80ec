/* coordinator/quality/bvh.h — a bounding-volume hierarchy over a mesh's live triangles for
 * closest-point queries (the surface distances of the quality report). Built once (median splits
 * on the longest axis, at most CO_BVH_LEAF triangles a leaf), read-only afterwards, so queries may
 * run from several threads. Distances in double precision. */
#ifndef LM_COORDINATOR_BVH_H
#define LM_COORDINATOR_BVH_H

#include "common/mesh.h"

#define CO_BVH_LEAF 4

typedef struct co_bvh co_bvh;

/* A hierarchy over m's live triangles (at least one). Caller destroys *out. */
lm_status co_bvh_create(const lm_mesh *m, co_bvh **out);
void co_bvh_destroy(co_bvh *b);

/* Squared distance from p to the closest point of the surface. */
double co_bvh_closest_sq(const co_bvh *b, const double p[3]);

/* Squared distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection 5.1.5);
 * exposed for tests, which compare the hierarchy against every triangle. */
double co_point_triangle_sq(const double p[3], const double a[3], const double b[3],
                            const double c[3]);

#endif
