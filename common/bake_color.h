/* common/bake_color.h — base-colour maps baked from an original mesh onto a simplified result
 * (issue 39, point 2; `--bake color`), on the texel walk of common/bake_walk.h (the same line per
 * texel as the normal map): per texel, the original's base colour where the line meets it, as
 * the renderers colour a pixel before lighting: the material's texture sampled at the
 * interpolated UV (bilinear, repeating, level 0) × the material's diffuse (base colour factor) ×
 * the interpolated vertex colour where the model has them, in the texture's own 8-bit encoding
 * (sRGB for glTF; the renderers multiply the bytes as they are). RGB = 255 c rounded, alpha 255
 * (the factor's alpha stays the material's). Gutters as every bake's. */
#ifndef LM_COMMON_BAKE_COLOR_H
#define LM_COMMON_BAKE_COLOR_H

#include "common/bake_walk.h"
#include "common/error.h"
#include "common/image.h"
#include "common/mesh.h"

/* The colour map's sink on img (size x size RGBA8, filled white here): *sink writes the
 * texels. */
void lm_bake_color_sink(lm_image *img, lm_bake_sink *sink);

/* orig's base colour at barycentrics b of its triangle t (corner k = tris[t].w[k]), RGB in
 * [0, 1] (not clamped). */
void lm_bake_color_at(const lm_mesh *orig, uint32_t t, const double b[3], double rgb[3]);

/* The base-colour map (size x size RGBA8) of `orig` on `res` (normals and UVs as
 * lm_bake_normal's); stats may be NULL. Caller destroys *out. Blocking; LM_E_NOMEM. */
lm_status lm_bake_color(const lm_mesh *orig, const lm_mesh *res, int size, lm_image **out,
                        lm_bake_stats *stats);

#endif
