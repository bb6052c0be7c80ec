/* common/bake_normal.h — tangent-space normal maps baked from an original mesh onto a simplified
 * result through the result's texture coordinates (issue 39, point 2), on the texel walk of
 * common/bake_walk.h: per texel, the original's interpolated normal where the result's line meets
 * it, expressed in the result's frame and encoded RGB = 255 (n / 2 + 1 / 2) (glTF normalTexture,
 * OpenGL convention: +Y along increasing v); flat (128, 128, 255) where the frame vanishes. Also
 * the colour transfer that goes with an atlas: the result's own textures resampled into it. */
#ifndef LM_COMMON_BAKE_NORMAL_H
#define LM_COMMON_BAKE_NORMAL_H

#include <stdint.h>

#include "common/bake_walk.h"
#include "common/error.h"
#include "common/image.h"
#include "common/mesh.h"

/* With a bake onto an atlas (common/uv_atlas.h) of a textured mesh: `from`, the mesh the atlas
 * was made of (its i-th live triangle is the atlas's triangle i), and out[mat] for each of the
 * atlas's materials, filled with `from`'s texture of that material resampled (bilinear, repeating)
 * through the atlas's coordinates, gutters included (NULL for materials without a texture). */
typedef struct lm_bake_colour {
    const lm_mesh *from;
    lm_image **out;     /* [res->n_materials], NULL entries on entry; caller destroys them */
    uint32_t *from_tri; /* internal: [res->n_tris] the triangle of `from` (lm_bake_transfer_*) */
} lm_bake_colour;

/* The normal map's sink on img (size x size RGBA8, filled flat here): *sink writes the texels. */
void lm_bake_normal_sink(lm_image *img, lm_bake_sink *sink);

/* The colour transfer's sink: c->out[] created (size x size) for `from`'s textured materials and
 * c->from_tri made; *sink fills them. LM_E_INTERNAL when `from` is not res's atlas source,
 * LM_E_NOMEM. lm_bake_transfer_end frees from_tri (out[] stays the caller's), also on failure. */
lm_status lm_bake_transfer_begin(const lm_mesh *res, int size, lm_bake_colour *c,
                                 lm_bake_sink *sink);
void lm_bake_transfer_end(lm_bake_colour *c);

/* The normal map (size x size RGBA8, alpha 255) of `orig` on `res` (which has normals and UVs
 * that passed lm_bake_uv_check, or an atlas's); colour (may be NULL) as above; stats may be NULL.
 * Caller destroys *out. */
lm_status lm_bake_normal(const lm_mesh *orig, const lm_mesh *res, int size, lm_bake_colour *colour,
                         lm_image **out, lm_bake_stats *stats);

#endif
