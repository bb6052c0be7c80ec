/* common/bake_normal.h — tangent-space normal maps baked from an original mesh onto a simplified
 * result through the result's texture coordinates (issue 39, point 2). Per texel of a chart: the
 * result's surface point, normal and tangent frame interpolated as engines do (the per-wedge
 * tangents of common/tangents.h, which the GLB writer stores as TANGENT, interpolated, then made
 * orthogonal to the interpolated normal per texel), a line along the result's normal both ways to
 * the original (common/bvh.h; the closest point where the line meets nothing), the original's
 * interpolated normal there expressed in that frame and encoded RGB = 255 (n / 2 + 1 / 2)
 * (glTF normalTexture, OpenGL convention: +Y along increasing v). Gutters all the way: every
 * texel outside the triangles takes the value of a nearest chart texel (repeated 8-neighbour
 * dilation), so coarse mip levels mix charts with charts, never with a background. Double precision
 * in a fixed order without contracted multiply-adds: the same bytes on every host. */
#ifndef LM_COMMON_BAKE_NORMAL_H
#define LM_COMMON_BAKE_NORMAL_H

#include <stdint.h>

#include "common/error.h"
#include "common/image.h"
#include "common/mesh.h"

typedef struct lm_bake_stats {
    uint64_t texels;   /* texels whose centre lies in a triangle of the result's UVs */
    uint64_t overlaps; /* of those, texels strictly inside two or more triangles */
    uint64_t hits;     /* texels whose line met the original (the others: its closest point) */
} lm_bake_stats;

/* LM_OK when m's texture coordinates can carry a bake of size x size texels: m has UVs, every
 * live triangle's lie in [0, 1]², and no texel centre lies strictly inside (barycentrics above
 * 1e-6) two triangles' UV triangles (rasterised at that size, so overlaps smaller than a texel
 * pass). Else LM_E_INVALID saying which (stats->overlaps counted; stats may be NULL). */
lm_status lm_bake_uv_check(const lm_mesh *m, int size, lm_bake_stats *stats);

/* With a bake onto an atlas (common/uv_atlas.h) of a textured mesh: `from`, the mesh the atlas
 * was made of (its i-th live triangle is the atlas's triangle i), and out[mat] for each of the
 * atlas's materials, filled with `from`'s texture of that material resampled (bilinear, repeating)
 * through the atlas's coordinates, gutters included (NULL for materials without a texture). */
typedef struct lm_bake_colour {
    const lm_mesh *from;
    lm_image **out; /* [res->n_materials], NULL entries on entry; caller destroys them */
} lm_bake_colour;

/* The normal map (size x size RGBA8, alpha 255) of `orig` on `res` (which has normals and UVs
 * that passed lm_bake_uv_check, or an atlas's); colour (may be NULL) as above; stats may be NULL.
 * Caller destroys *out. */
lm_status lm_bake_normal(const lm_mesh *orig, const lm_mesh *res, int size, lm_bake_colour *colour,
                         lm_image **out, lm_bake_stats *stats);

#endif
