/* common/views_api.h — the narrow interface between the optimizer and "the views".
 *
 * The optimizer (coordinator/) never renders: it holds the mesh, turns candidate moves into
 * patches (common/patch.h) and asks the views for exact integer energy changes. Behind this table
 * stands today the in-process EGL renderer (worker/views_local.c); later a pool of lumesh-worker
 * processes over the wire, each owning a subset of the views, summing partial int64 results.
 * Because every number is an int64 sum over pixels, results do not depend on how views are split.
 *
 * Ownership: the views object is created by its backend's *_create and released with
 * lm_views_destroy(). Patches passed in stay owned by the caller. */
#ifndef LM_COMMON_VIEWS_API_H
#define LM_COMMON_VIEWS_API_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/patch.h"

typedef struct lm_views lm_views;

typedef struct lm_views_info {
    uint32_t n_views;
    int width, height;
    char renderer[128]; /* device and driver that made every image, e.g. "EGL llvmpipe
                           (Mesa 22.3.6)" */
} lm_views_info;

typedef struct lm_views_ops {
    /* Replace the current mesh (all triangles, full re-render of every current image). */
    lm_status (*set_mesh)(lm_views *v, const lm_tri_data *tris, size_t n);
    /* For each patch i: delta[i] = E(mesh with patch i applied) - E(current mesh), exactly.
     * Patches are independent alternatives (each against the current mesh). Nothing changes. */
    lm_status (*evaluate)(lm_views *v, const lm_patch *patches, uint32_t n, int64_t *delta);
    /* Apply a patch to the current mesh and images (incrementally). */
    lm_status (*commit)(lm_views *v, const lm_patch *patch);
    /* Total energy and optionally per-view energies (per_view has n_views entries). */
    lm_status (*energy)(lm_views *v, int64_t *total, int64_t *per_view);
    /* Oracle: recompute blurred difference images, then for each world point the sum over views
     * of the blurred squared difference at its projection (0 where it projects outside). */
    lm_status (*potentials)(lm_views *v, const float (*points)[3], size_t n, int64_t *out);
    void (*info)(lm_views *v, lm_views_info *out);
    void (*destroy)(lm_views *v);
} lm_views_ops;

struct lm_views {
    const lm_views_ops *ops;
};

static inline void lm_views_destroy(lm_views *v)
{
    if (v)
        v->ops->destroy(v);
}

#endif
