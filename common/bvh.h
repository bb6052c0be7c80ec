/* common/bvh.h — a bounding-volume hierarchy over a mesh's live triangles for
 * closest-point and line queries (the surface distances of the quality report, the optimizer's
 * geometric term). Built once (median splits on the longest axis, at most LM_BVH_LEAF triangles a
 * leaf), read-only afterwards, so queries may run from several threads. Distances in double
 * precision, compiled without contracted multiply-adds: the same point gives the same bits on every
 * platform (the optimizer's decisions depend on them). */
#ifndef LM_COMMON_BVH_H
#define LM_COMMON_BVH_H

#include "common/mesh.h"

#define LM_BVH_LEAF 4

typedef struct lm_bvh lm_bvh;

/* A hierarchy over m's live triangles (at least one). Caller destroys *out. */
lm_status lm_bvh_create(const lm_mesh *m, lm_bvh **out);
void lm_bvh_destroy(lm_bvh *b);

/* Squared distance from p to the closest point of the surface. */
double lm_bvh_closest_sq(const lm_bvh *b, const double p[3]);

/* 1 when some triangle is within squared distance r2 of p (lm_bvh_closest_sq(b, p) <= r2,
 * answered at the first such triangle). */
int lm_bvh_within(const lm_bvh *b, const double p[3], double r2);

/* lm_bvh_closest_sq that also says where: the mesh's id of the closest triangle (the first
 * in the hierarchy's order at a tie) and p's closest point on it in barycentric coordinates of
 * its corners (corner k = lm_tri_vertex(m, tri, k)). */
double lm_bvh_closest_tri(const lm_bvh *b, const double p[3], uint32_t *tri, double bary[3]);

/* Ray queries (common/bvh_ray.c): the triangle the line o + t d meets (both ways, |t| <= tmax)
 * nearest to o, i.e. at the least |t| (ties: the first one met, a fixed order). Returns 1 and
 * its mesh id, t and the hit's barycentrics (corner k = lm_tri_vertex(m, tri, k)); 0 when the
 * line meets none within tmax. With facing 0 triangles are two-sided, else only those whose
 * front (counter-clockwise) faces along d count (a bake's line along the result's normal then
 * meets the original's outside surfaces, not parts inside it). d need not be unit (t is in its
 * units). */
int lm_bvh_line_hit(const lm_bvh *b, const double o[3], const double d[3], double tmax, int facing,
                    uint32_t *tri, double *t, double bary[3]);

/* Squared distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection 5.1.5);
 * exposed for tests, which compare the hierarchy against every triangle. */
double lm_point_triangle_sq(const double p[3], const double a[3], const double b[3],
                            const double c[3]);
/* The same distance and the closest point's barycentric coordinates (for a, b, c) in bary. */
double lm_point_triangle_bary(const double p[3], const double a[3], const double b[3],
                              const double c[3], double bary[3]);

#endif
