/* coordinator/quality/view_setup.c — view sets around a model, in-process views with a model
 * set, and models loaded from their files to be judged. */
#include "coordinator/quality/view_setup.h"

#include <stdlib.h>
#include <time.h>

#include "common/io/mesh_io.h"
#include "coordinator/views/views.h"

lm_status co_view_set_of(const lm_mesh *framing, const lm_view_spec *spec, int size,
                         lm_view_set_kind kind, lm_view_set **out)
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
    lm_view_spec s = *spec;
    if (!s.count)
        s.count = LM_DEFAULT_VIEWS;
    lm_status st = lm_view_set_make_spec(vs, &s, kind, size, c, r);
    if (st != LM_OK) {
        free(vs);
        return st;
    }
    *out = vs;
    return LM_OK;
}

lm_status co_view_set_around(const lm_mesh *framing, uint32_t n, int size, lm_view_set_kind kind,
                             lm_view_set **out)
{
    lm_view_spec sphere = {.count = n};
    return co_view_set_of(framing, &sphere, size, kind, out);
}

lm_status co_views_with_model(const lm_mesh *original, const lm_mesh *model,
                              const lm_view_set *views, const char *device, lm_views **out)
{
    co_views_desc d = {.original = original, .views = views, .device = device, .mesh = model};
    if (model != original) {
        d.materials = model->materials;
        d.n_materials = model->n_materials;
    }
    return co_views_create(&d, out);
}

lm_status co_judge_files(const char *original, const char *const *models, uint32_t n,
                         const lm_view_spec *views, int size, lm_view_set_kind kind,
                         co_judge_fn judge, void *ctx)
{
    lm_mesh *orig = NULL, **m = calloc(n ? n : 1, sizeof *m);
    lm_view_set *vs = NULL;
    lm_status st = m ? lm_mesh_load(original, NULL, &orig) : lm_fail(LM_E_NOMEM, "out of memory");
    for (uint32_t i = 0; st == LM_OK && i < n; i++)
        st = lm_mesh_load(models[i], NULL, &m[i]);
    if (st == LM_OK)
        st = co_view_set_of(orig, views, size, kind, &vs);
    if (st == LM_OK)
        st = judge(ctx, orig, (const lm_mesh *const *)m, vs);
    free(vs);
    lm_mesh_destroy(orig);
    for (uint32_t i = 0; m && i < n; i++)
        lm_mesh_destroy(m[i]);
    free(m);
    return st;
}

double co_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
