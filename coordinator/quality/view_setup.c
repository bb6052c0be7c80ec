/* coordinator/quality/view_setup.c — view sets around a model and in-process views with a model
 * set. */
#include "coordinator/quality/view_setup.h"

#include <stdlib.h>
#include <time.h>

#include "common/patch.h"
#include "worker/views_local.h"

lm_status co_view_set_around(const lm_mesh *framing, uint32_t n, int size, int heldout,
                             lm_view_set **out)
{
    if (framing->live_tris == 0)
        return lm_fail(LM_E_INVALID, "the model has no triangles to frame");
    float c[3], r;
    lm_mesh_bounding_sphere(framing, c, &r);
    if (!(r > 0.0f))
        r = 1.0f; /* a single point: any frame will do */
    lm_view_set *vs = malloc(sizeof *vs);
    if (!vs)
        return lm_fail(LM_E_NOMEM, "out of memory for a view set");
    lm_status st =
        heldout ? lm_view_set_make_heldout(vs, size, c, r) : lm_view_set_make(vs, n, size, c, r);
    if (st != LM_OK) {
        free(vs);
        return st;
    }
    *out = vs;
    return LM_OK;
}

lm_status co_views_with_model(const lm_mesh *original, const lm_mesh *model,
                              const lm_view_set *views, const char *device, lm_views **out)
{
    lm_views *v = NULL;
    lm_tri_data *tris = NULL;
    size_t n = 0;
    lm_status st = wk_views_local_create(original, views, device, &v);
    if (st == LM_OK && model != original)
        st = wk_views_local_set_materials(v, model->materials, model->n_materials);
    if (st == LM_OK)
        st = lm_mesh_export_tris(model, &tris, &n);
    if (st == LM_OK)
        st = v->ops->set_mesh(v, tris, n);
    free(tris);
    if (st != LM_OK) {
        lm_views_destroy(v);
        return st;
    }
    *out = v;
    return LM_OK;
}

double co_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
