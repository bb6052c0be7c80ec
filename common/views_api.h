/* common/views_api.h — the narrow interface between the optimizer and "the views".
 *
 * The optimizer (coordinator/) never renders: it holds the mesh, turns candidate moves into
 * patches (common/patch.h) and asks the views for exact integer energy changes. Behind this table
 * stand the in-process renderer (worker/render/views_local.c), a split over several backends that
 * each own a range of the views (coordinator/views/views_split.c), and lumesh-worker processes over
 * the wire (coordinator/views/views_remote.c). Because every number is an int64 sum over pixels,
 * results do not depend on how the views are split, nor on who computed which part.
 *
 * One constructor makes every kind from one description: co_views_create (coordinator/views/).
 *
 * The state behind the table: the target images (fixed at creation), a material table for the
 * current mesh, the current mesh with its images and, where the backend prices it, the geometric
 * term's scale (surface_term). Every op below is BLOCKING: it returns when the whole answer is
 * known (a remote backend has then heard from every worker it needed).
 *
 * Sequence number: every change of state (set_mesh, set_materials, commit, surface_term) advances
 * `seq` (info) by one (a remote backend's surface_term may re-send the mesh too: two). Replicas
 * of the state (worker processes) are tagged with it; a replica that missed a change is detected
 * by its sequence number and re-sent the state, never priced against.
 *
 * Failure: an op that fails returns a status with a one-line message (common/error.h). Evaluate,
 * energy, potentials, read_image and info never change the state, whatever they return. When
 * set_mesh, set_materials, commit or surface_term fail, the state is unknown: the caller must set
 * the mesh again (and its materials, if they failed) before the next evaluation. Recovery inside a
 * backend: a backend that keeps replicas (remote) re-sends the mesh and materials to a replica that
 * lost them on its own; the caller sees an error only when no replica can be made to serve.
 *
 * Ownership: the views object is created by co_views_create (or a backend's *_create) and released
 * with lm_views_destroy(). Everything passed in stays owned by the caller and may be reused as
 * soon as the op returns. */
#ifndef LM_COMMON_VIEWS_API_H
#define LM_COMMON_VIEWS_API_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/mesh.h"
#include "common/patch.h"

typedef struct lm_views lm_views;

typedef struct lm_views_info {
    uint32_t n_views;
    int width, height;
    uint64_t seq; /* changes of state so far (set_mesh, set_materials, commit) */
    /* Work done so far, where the backend counts it (0 otherwise): patches evaluated through this
     * object, and summed over its parts the view regions redrawn, their pixels and the triangles
     * drawn. */
    uint64_t evaluations, regions, region_pixels, tris_drawn;
    /* 1 where the caller's own work while an evaluation is out (evaluate_overlapped) takes
     * processor time from the evaluation: the backend's workers busy every processor of this
     * machine. 0 where it is free, or nothing is out meanwhile (in process). */
    int overlap_costs;
    char renderer[128]; /* device and driver that made every image, e.g. "EGL llvmpipe
                           (Mesa 22.3.6)" */
} lm_views_info;

/* What read_image copies out (width*height bytes per pixel as listed, bottom row first). */
typedef enum lm_image_kind {
    LM_IMAGE_TARGET_LUMA,  /* 1 byte: the original's luminance */
    LM_IMAGE_CURRENT_LUMA, /* 1 byte: the current mesh's luminance */
    LM_IMAGE_RGBA,         /* 4 bytes: the colour image of the last full render (right after
                              creation the original's, right after set_mesh/set_materials the
                              current mesh's) */
    LM_IMAGE_COVERAGE,     /* 1 byte: 1 where the last full render drew a surface, 0 where the
                              background shows */
    LM_IMAGE_TRIANGLE,     /* 4 bytes: the id (uint32_t, this machine's byte order) of the current
                              mesh's triangle the last full render drew there, LM_NONE where the
                              background shows. The CPU renderer only (its exact keys): other
                              backends answer LM_E_UNSUPPORTED, and it never travels to workers */
} lm_image_kind;

typedef struct lm_views_ops {
    /* Replace the current mesh: all triangles (ids distinct, materials in the current table), a
     * full re-render of every current image. */
    lm_status (*set_mesh)(lm_views *v, const lm_tri_data *tris, size_t n);
    /* Use these materials (copied; textures too) for the current mesh's material ids instead of
     * the original's (the default). A mesh already set is re-rendered with them. */
    lm_status (*set_materials)(lm_views *v, const lm_material *mats, uint32_t n);
    /* For each patch i: delta[i] = E(mesh with patch i applied) - E(current mesh), exactly.
     * Patches are independent alternatives (each against the current mesh). Nothing changes. */
    lm_status (*evaluate)(lm_views *v, const lm_patch *patches, uint32_t n, int64_t *delta);
    /* Optional (NULL = not offered; lm_views_evaluate_overlapped stands in): evaluate as above,
     * calling overlap(ctx) once meanwhile, while other processes compute the answer (a remote
     * backend calls it after its requests are out and before it waits for the replies, once
     * however often it has to redo them). overlap is the caller's own work: it must not call
     * into v. It has been called when the op returns LM_OK; after a failure it may not have. */
    lm_status (*evaluate_overlapped)(lm_views *v, const lm_patch *patches, uint32_t n,
                                     int64_t *delta, void (*overlap)(void *ctx), void *ctx);
    /* Apply a patch to the current mesh and images (incrementally). */
    lm_status (*commit)(lm_views *v, const lm_patch *patch);
    /* Total energy and optionally per-view energies (per_view has n_views entries). */
    lm_status (*energy)(lm_views *v, int64_t *total, int64_t *per_view);
    /* Oracle: recompute blurred difference images, then for each world point the sum over views
     * of the blurred squared difference at its projection (0 where it projects outside). */
    lm_status (*potentials)(lm_views *v, const float (*points)[3], size_t n, int64_t *out);
    /* Copy one image of view `view` (0..n_views-1) into out (sized as lm_image_kind says).
     * LM_E_UNSUPPORTED where the backend or its device cannot give that kind. */
    lm_status (*read_image)(lm_views *v, lm_image_kind kind, uint32_t view, uint8_t *out);
    void (*info)(lm_views *v, lm_views_info *out);
    void (*destroy)(lm_views *v);
    /* Optional (NULL = not offered): make the current images the targets, so that E becomes 0 and
     * the next evaluations price a change against the mesh as it is now (Pfeiffer's incremental
     * difference; the shard simplifier). A change of state. In-process backends offer it. */
    lm_status (*retarget)(lm_views *v);
    /* Optional (NULL = not offered; then so is evaluate_surface): the backend holds the
     * geometric term at scale k (> 0) against `surface` (common/surface_table.h) from now on,
     * where the images are made (a remote backend: on its workers, each group of views a share
     * of the triangle ids, their tables following set_mesh and commit), so that evaluate_surface
     * can price it. A change of state; a later call sets another k. LM_E_UNSUPPORTED where the
     * backend cannot (`surface` is not the original its targets are images of). Recovery: a
     * backend that re-sends its state to a replica re-sends the term with it. */
    lm_status (*surface_term)(lm_views *v, const lm_mesh *surface, double k);
    /* Evaluate as above, with the geometric term's ΔE_geo of each patch added by the backend (the
     * same bits as one table over the whole mesh). Only after surface_term; energy, potentials
     * and read_image stay the images' alone (the caller keeps E_geo). */
    lm_status (*evaluate_surface)(lm_views *v, const lm_patch *patches, uint32_t n, int64_t *delta);
} lm_views_ops;

struct lm_views {
    const lm_views_ops *ops;
};

static inline void lm_views_destroy(lm_views *v)
{
    if (v)
        v->ops->destroy(v);
}

/* The retarget op, or LM_E_UNSUPPORTED where the backend does not offer it. */
lm_status lm_views_retarget(lm_views *v);

/* The evaluate_overlapped op, or where the backend does not offer it, overlap(ctx) then
 * evaluate: the caller's own work done while a remote backend waits, and in turn elsewhere. */
lm_status lm_views_evaluate_overlapped(lm_views *v, const lm_patch *patches, uint32_t n,
                                       int64_t *delta, void (*overlap)(void *ctx), void *ctx);

/* The surface_term op, or LM_E_UNSUPPORTED where the backend does not offer it (the caller then
 * prices the term itself, and must not call evaluate_surface). */
lm_status lm_views_surface_term(lm_views *v, const lm_mesh *surface, double k);

/* Bytes per pixel of an image kind (1 or 4). */
static inline size_t lm_image_kind_bpp(lm_image_kind kind)
{
    return kind == LM_IMAGE_RGBA || kind == LM_IMAGE_TRIANGLE ? 4 : 1;
}

/* The current mesh's triangles (all alive ones, in id order) sent to the views: the one way the
 * coordinator replaces the views' mesh. */
lm_status lm_views_set_mesh_from(lm_views *v, const lm_mesh *m);

#endif
