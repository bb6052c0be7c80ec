/* worker/render/shared/cover.h — whether a patch's added triangles certainly cover, in one view,
 * every pixel its removed triangles covered, and how far back they reach there. No GL here.
 *
 * The argument: a removed and an added triangle with bit-identical corner positions (a "twin"
 * pair, e.g. a neighbour whose normals changed) cover the same pixels at the same depths. For the
 * rest, the removed T and the added T': when they have the same boundary (as chains of directed 3D
 * edges, ∂T = ∂T') and, in the view, every one of them projects with the same orientation, the
 * number of triangles of T covering a pixel centre equals the number of T' covering it (both are
 * the winding number of the common boundary; a watertight rasteriser's fill rule cancels on the
 * shared inner edges). Orientations are taken with a margin larger than the rasteriser's snapping,
 * and only for triangles that no clipping touches (every corner in front of the near plane, before
 * the far plane and near the view), so that the rasteriser sees the same signs and the same edges.
 * Every move of the optimiser (vertex moves, collapses, splits, swaps) replaces a disk by a disk
 * with the same rim, so the boundary test holds for all of them. */
#ifndef LM_WORKER_COVER_H
#define LM_WORKER_COVER_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/patch.h"
#include "worker/render/shared/buckets.h"

/* What a patch's geometry allows, view-independent; owned by the caller (wk_cover_patch_free). */
typedef struct wk_cover_patch {
    int same_boundary; /* ∂T == ∂T' over the triangles that are not twins */
    uint8_t *twin;     /* [n_removed + n_added]: removed ones first, then added ones */
    size_t cap_twin;
    void *scratch;
    size_t cap_scratch;
} wk_cover_patch;

/* Twins and the boundary test of removed (records) and added triangles; corner positions compare
 * bit for bit. */
lm_status wk_cover_patch_prepare(wk_cover_patch *cp, const lm_tri_data *const *removed,
                                 uint32_t n_removed, const lm_tri_data *added, uint32_t n_added);
void wk_cover_patch_free(wk_cover_patch *cp);

/* The per-view test: the footprints of every removed and added triangle that is not a twin. */
typedef struct wk_cover_tri {
    wk_rect rect;
    float zmax; /* farthest window depth of its fragments (wk_footprint's zmax) */
    int sign;   /* its orientation in the view (+1, -1), 0 if clipped or (nearly) degenerate */
    int added;
} wk_cover_tri;

typedef struct wk_cover {
    int same_boundary; /* of the patch */
    wk_cover_tri *tris;
    size_t n, cap_bytes;
    int width, height;
} wk_cover;

/* Start the test of patch cp (of n_tris triangles in all) for a view of width x height pixels. */
lm_status wk_cover_begin(wk_cover *c, const wk_cover_patch *cp, size_t n_tris, int width,
                         int height);
void wk_cover_feed(wk_cover *c, const wk_footprint *f, int added);
void wk_cover_free(wk_cover *c);

/* Whether, at every pixel of rectangle r where the current surface is nearer than window depth z,
 * the surface after the patch is nearer than z too. Twins keep their depths; for the rest, the
 * non-twin triangles whose rectangles meet r are all unclipped with one orientation, so at each
 * pixel of r as many added as removed ones cover it, and the added ones there are nearer than z. */
int wk_cover_front_of(const wk_cover *c, const wk_rect *r, float z);

#endif
