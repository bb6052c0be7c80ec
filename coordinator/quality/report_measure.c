/* coordinator/quality/report_measure.c — the report's numbers: load the original and the models
 * from their files, then on the 24 held-out views their image energies (total and per view),
 * silhouette coverage and cracks, and against the original's surface their symmetric surface
 * distance; and the vertex, triangle and part counts. */
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "coordinator/quality/report_internal.h"
#include "coordinator/quality/view_setup.h"

lm_status co_report_load_model(co_report_model *m, const char *label, const char *path)
{
    m->label = label;
    m->path = path;
    m->switch_distance = -1.0;
    lm_status s = lm_mesh_load(path, NULL, &m->mesh);
    if (s)
        return s;
    m->verts = m->mesh->live_verts;
    m->tris = m->mesh->live_tris;
    m->parts = lm_mesh_count_parts(m->mesh);
    return LM_OK;
}

static lm_status load_all(co_report *r)
{
    const co_report_options *o = r->o;
    if (o->lods)
        return co_report_load_levels(r);
    lm_status s = co_report_load_model(&r->model[0], "original", o->original);
    r->n_models = 1;
    if (!s && o->initial) {
        s = co_report_load_model(&r->model[r->n_models++], "initial", o->initial);
        r->has_initial = 1;
    }
    if (!s && o->unbaked) {
        s = co_report_load_model(&r->model[r->n_models++], "unbaked", o->unbaked);
        r->has_unbaked = 1;
    }
    if (!s)
        s = co_report_load_model(&r->model[r->n_models++], "optimized", o->optimized);
    return s;
}

/* Energies and coverage of the models against the original on the held-out views. */
static lm_status judge(co_report *r)
{
    uint32_t n = r->n_models - 1, views = r->heldout->count;
    const lm_mesh *models[CO_REPORT_MAX_MODELS] = {0};
    int64_t energy[CO_REPORT_MAX_MODELS], *per_view = malloc((size_t)n * views * sizeof *per_view);
    co_coverage cov[CO_REPORT_MAX_MODELS];
    if (!per_view)
        return lm_fail(LM_E_NOMEM, "out of memory for per-view energies");
    for (uint32_t i = 0; i < n; i++)
        models[i] = r->model[i + 1].mesh;
    lm_status s = co_compare_energies(r->model[0].mesh, r->heldout, r->o->device, models, n, energy,
                                      per_view, cov, r->renderer);
    for (uint32_t i = 0; !s && i < n; i++) {
        co_report_model *m = &r->model[i + 1];
        m->energy = energy[i];
        m->cov = cov[i];
        m->per_view = malloc((size_t)views * sizeof *m->per_view);
        if (!m->per_view)
            s = lm_fail(LM_E_NOMEM, "out of memory for per-view energies");
        else
            memcpy(m->per_view, per_view + (size_t)i * views, (size_t)views * sizeof *per_view);
    }
    free(per_view);
    return s;
}

lm_status co_report_measure(co_report *r)
{
    lm_status s = load_all(r);
    r->size = r->o->size ? r->o->size : 256;
    if (!s)
        s = co_view_set_of(r->model[0].mesh, &r->o->views, r->size, LM_VIEWS_HELDOUT, &r->heldout);
    if (!s)
        s = judge(r);
    for (uint32_t i = 1; !s && i < r->n_models; i++)
        s = co_surface_distance_measure(r->model[0].mesh, r->model[i].mesh, 0, &r->model[i].dist);
    for (uint32_t i = 0; !s && i < CO_REPORT_SHEET_VIEWS; i++)
        r->sheet_view[i] = i * r->heldout->count / CO_REPORT_SHEET_VIEWS;
    return s;
}

void co_report_free(co_report *r)
{
    for (uint32_t i = 0; i < CO_REPORT_MAX_MODELS; i++) {
        lm_mesh_destroy(r->model[i].mesh);
        free(r->model[i].per_view);
        free(r->model[i].level_path);
    }
    free(r->heldout);
    lm_image_destroy(r->sheet);
    lm_image_destroy(r->closeup);
    memset(r, 0, sizeof *r);
}
