/* common/tangents.h — tangent frames for tangent-space normal maps (glTF normalTexture, OpenGL
 * convention: +X along increasing u, +Y along increasing v with lumesh's bottom-left UV origin,
 * +Z along the normal), in the spirit of MikkTSpace: each triangle's frame from the derivatives
 * of its positions by its texture coordinates (both unit), accumulated per wedge weighted by the
 * corner's angle, then made orthogonal to the wedge's normal (Gram–Schmidt) with the handedness w
 * = ±1 saying whether w · (normal × tangent) points along the bitangent. Tangents are not stored
 * on the mesh: they are derived on demand (the GLB writer's TANGENT; the renderers' frames, from
 * the one triangle a renderer sees, which equal the wedges' wherever neighbouring triangles share
 * one frame, e.g. a planar chart). Double precision in a fixed order, no fused multiply-adds
 * (common/CMakeLists.txt): the same bits on every host. */
#ifndef LM_COMMON_TANGENTS_H
#define LM_COMMON_TANGENTS_H

#include "common/error.h"
#include "common/mesh.h"

/* Triangle (p[k], uv[k]), k = 0..2: its unit tangent t (∂p/∂u) and bitangent b (∂p/∂v); both zero
 * where the texture coordinates or the positions are degenerate. */
void lm_tri_tangent_frame(const float p[3][3], const float uv[3][2], double t[3], double b[3]);

/* The tangent (xyz unit, w = ±1) at a corner of normal n from accumulated frame t, b: t made
 * orthogonal to n and unit; where that vanishes, a fixed unit vector orthogonal to n. */
void lm_tangent_orthogonal(const float n[3], const double t[3], const double b[3], float out[4]);

/* The unit frame at such a corner: T (as lm_tangent_orthogonal's xyz), B = w (N × T), N = n made
 * unit ((0, 0, 1) where n is zero): out = T, B, N. */
void lm_tangent_basis(const float n[3], const double t[3], const double b[3], double out[9]);

/* Tangents of every wedge of m (out: [m->n_wedges][4]; dead and unused wedges get a valid frame of
 * their normal too). */
lm_status lm_mesh_tangents(const lm_mesh *m, float (**out)[4]);

#endif
