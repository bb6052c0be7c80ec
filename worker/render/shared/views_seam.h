/* worker/render/shared/views_seam.h — the views_api.h seam of both in-process backends, once: a
 * backend fills a wk_views_backend table with what it does its own way (rendering, evaluating,
 * committing, its colour and coverage images, its name) and views_seam.c answers every
 * views_api.h call from that table and the wk_views_core its object starts with: set_mesh,
 * set_materials and commit counted as changes of state, evaluate and commit refused before a
 * mesh is set, energy and the oracle's potentials from the image store, the luminance images,
 * info, retarget, destroy. */
#ifndef LM_WORKER_RENDER_SHARED_VIEWS_SEAM_H
#define LM_WORKER_RENDER_SHARED_VIEWS_SEAM_H

#include <stddef.h>
#include <stdint.h>

#include "common/views_api.h"
#include "worker/render/shared/views_core.h"

struct wk_views_backend {
    /* set_mesh, set_materials and commit as views_api.h has them; the seam counts a success as
     * a change of state */
    lm_status (*set_mesh)(wk_views_core *c, const lm_tri_data *tris, size_t n);
    lm_status (*set_materials)(wk_views_core *c, const lm_material *mats, uint32_t n);
    /* commit and evaluate are called once wk_views_core_ready succeeded (and, for evaluate, with
     * delta zeroed) */
    lm_status (*commit)(wk_views_core *c, const lm_patch *patch);
    lm_status (*evaluate)(wk_views_core *c, const lm_patch *patches, uint32_t n, int64_t *delta);
    /* LM_IMAGE_RGBA and LM_IMAGE_COVERAGE of view `view` (checked: one of c's) */
    lm_status (*read_rgba)(wk_views_core *c, uint32_t view, uint8_t *out);
    lm_status (*read_coverage)(wk_views_core *c, uint32_t view, uint8_t *out);
    /* Optional (NULL: LM_E_UNSUPPORTED): LM_IMAGE_TRIANGLE of view `view` (checked) */
    lm_status (*read_triangles)(wk_views_core *c, uint32_t view, uint32_t *out);
    /* the device and driver that make the images (lm_views_info's renderer) */
    const char *(*renderer)(const wk_views_core *c);
    /* wk_views_local_set_occlusion */
    lm_status (*set_occlusion)(wk_views_core *c, int on);
    /* Optional (NULL: retarget is not offered): the current images became the targets; forget
     * what priced the old ones */
    void (*retargeted)(wk_views_core *c);
    /* frees the backend's own parts (then the seam frees the core's and the object) */
    void (*destroy)(wk_views_core *c);
};

/* Make c answer views_api.h through backend b (a table that outlives c). */
void wk_views_seam_attach(wk_views_core *c, const wk_views_backend *b);
/* The end of a backend's creation: on LM_OK *out is c's views object, else c is destroyed (what
 * is there of it) and st returned. */
lm_status wk_views_seam_created(wk_views_core *c, lm_status st, lm_views **out);
/* Whether v is such an object (then it is a wk_views_core). */
int wk_views_seam_is(const lm_views *v);

#endif
