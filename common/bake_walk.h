/* common/bake_walk.h — the texel walk every bake shares (issue 39, point 2): the result's UV
 * triangles rasterised at texel centres (each texel's owning triangle), per owned texel the
 * result's surface point and tangent frame interpolated as engines do (the per-wedge tangents of
 * common/tangents.h, which the GLB writer stores as TANGENT, interpolated, then made orthogonal
 * to the interpolated normal), one line along the result's normal both ways to the original
 * (common/bvh.h; the closest point where the line meets nothing, or where the frame vanishes),
 * handed to each map's sink (bake_normal.h, bake_color.h); then gutters all the way: every texel
 * outside the triangles takes the value of a nearest chart texel (repeated 8-neighbour dilation),
 * so coarse mip levels mix charts with charts, never with a background. Double precision in a
 * fixed order without contracted multiply-adds: the same bytes on every host. */
#ifndef LM_COMMON_BAKE_WALK_H
#define LM_COMMON_BAKE_WALK_H

#include <math.h>
#include <stddef.h>
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

/* One owned texel as the sinks see it. */
typedef struct lm_bake_point {
    const lm_mesh *orig, *res;
    uint32_t tri; /* the result's owning triangle */
    double b[3];  /* its barycentrics at the texel centre (clamped to the triangle) */
    double p[3];  /* the result's point there */
    double f[9];  /* the result's unit frame T, B, N there (when framed) */
    int framed;   /* 0: the interpolated normal or tangent vanished */
    uint32_t hit; /* the original's triangle the line met (else the closest), LM_NONE when
                     the texel has no point (a UV triangle without area) */
    double hb[3]; /* the point there in barycentrics of hit's corners */
} lm_bake_point;

/* A map's per-texel work: texel i (row-major, rows top to bottom) of point pt. Runs on the
 * caller's thread, in texel order; never fails. */
typedef struct lm_bake_sink {
    void (*texel)(void *arg, const lm_bake_point *pt, size_t i);
    void *arg;
} lm_bake_sink;

/* Walks every owned texel of res's size x size map (res has normals and UVs that passed
 * lm_bake_uv_check, or an atlas's), one line to orig each, calling the sinks in order; then fills
 * the gutters of imgs[0..n_imgs) (size x size RGBA8 the sinks wrote; NULL entries skipped).
 * Texels no triangle owns keep what the caller put there until the gutters take them. stats
 * (may be NULL) counted. Blocking; LM_E_NOMEM on allocation failure. */
lm_status lm_bake_walk(const lm_mesh *orig, const lm_mesh *res, int size, const lm_bake_sink *sinks,
                       int n_sinks, lm_image *const *imgs, int n_imgs, lm_bake_stats *stats);

/* The bakes' vector arithmetic (double, in this order: the same bits on every host). */
static inline double lm_bake_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* v scaled to unit length; 0 (v unchanged) when it is (nearly) zero or not finite. */
static inline int lm_bake_unit3(double v[3])
{
    double len = sqrt(lm_bake_dot3(v, v));
    if (!(len > 1e-30) || !isfinite(len))
        return 0;
    for (int k = 0; k < 3; k++)
        v[k] /= len;
    return 1;
}

/* Texture img at (u, v) (v = 0 the bottom row), bilinear between texel centres, repeating:
 * RGBA in 0..255, not rounded. */
void lm_bake_sample(const lm_image *img, double u, double v, double px[4]);

#endif
