/* coordinator/simplify/adapt_features.h — sharp features for the shape-adaptive simplifier: an
 * edge is a feature where its two triangles meet at a dihedral angle above a threshold (their
 * normals more than that apart), and also where the mesh must keep a line: a boundary, a
 * non-manifold edge, an attribute seam, a border between materials or parts. A vertex is smooth
 * (no feature edge), on a feature line (exactly 2) or a corner (1, or 3 and more). */
#ifndef LM_COORDINATOR_SIMPLIFY_ADAPT_FEATURES_H
#define LM_COORDINATOR_SIMPLIFY_ADAPT_FEATURES_H

#include "common/mesh.h"

enum { CO_ADAPT_SMOOTH, CO_ADAPT_LINE, CO_ADAPT_CORNER };

/* The default threshold: 30 degrees. */
#define CO_ADAPT_FEATURE_DEG 30.0

/* 1 when edge (a, b) of m is a feature edge for the threshold angle (its cosine, cos_max: the
 * normals' dot product below it is sharp). */
int co_adapt_is_feature_edge(const lm_mesh *m, uint32_t a, uint32_t b, double cos_max);

/* out[v] = CO_ADAPT_SMOOTH, _LINE or _CORNER for every vertex of m (n_verts entries). */
lm_status co_adapt_vertex_classes(const lm_mesh *m, double cos_max, uint8_t *out);

#endif
