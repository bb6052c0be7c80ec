/* coordinator/quality/report_internal.h — what the report's stages share: the models and their
 * measurements (report_measure.c), the pictures (report_sheet.c), the plots (report_plots.c) and
 * the page (report_html.c). Private to the report. */
#ifndef LM_COORDINATOR_REPORT_INTERNAL_H
#define LM_COORDINATOR_REPORT_INTERNAL_H

#include <stdio.h>

#include "common/image.h"
#include "common/mesh.h"
#include "common/view.h"
#include "coordinator/quality/compare.h"
#include "coordinator/quality/report.h"
#include "coordinator/quality/surface_distance.h"

/* One model of the report and what was measured of it against the original. */
typedef struct co_report_model {
    const char *label; /* "original", "initial", "optimized", or a level's "LOD0", ... */
    const char *path;
    char level_label[16];   /* a level's label (label points here) */
    char *level_path;       /* a level's file, resolved against the manifest's folder (owned) */
    double switch_distance; /* a level's, as its manifest gives it; < 0: none */
    lm_mesh *mesh;
    uint32_t verts, tris, parts;
    int64_t energy;           /* held-out energy (not for the original) */
    int64_t *per_view;        /* [heldout->count] */
    co_coverage cov;          /* silhouette and cracks */
    co_surface_distance dist; /* against the original */
} co_report_model;

typedef struct co_report {
    const co_report_options *o;
    co_report_model model[CO_REPORT_MAX_MODELS]; /* the original, [the initial,] the optimized;
                                                    or the original and every level */
    uint32_t n_models;
    int levels;           /* the models after the original are a manifest's levels */
    int has_initial;      /* model[1] is the initial mesh */
    int has_unbaked;      /* the model before the optimized one is the unbaked result */
    lm_view_set *heldout; /* the 24 held-out views */
    int size;
    char renderer[128];
    uint32_t sheet_view[CO_REPORT_SHEET_VIEWS]; /* which held-out views the sheet shows */
    lm_image *sheet;                            /* contact sheet */
    lm_image *closeup;                          /* NULL when there are no cracks */
    const co_report_model *closeup_of;          /* the model whose cracks it shows */
    co_crop crop;
    uint64_t crop_cracks;
    int zoom; /* the close-up's views are rendered at size * zoom */
} co_report;

/* report_measure.c: load the models and measure them (energies, coverage, distances, counts). */
lm_status co_report_measure(co_report *r);
/* Load the model of file `path` into m with its label and counts (no switch distance). */
lm_status co_report_load_model(co_report_model *m, const char *label, const char *path);
void co_report_free(co_report *r);
/* The models after the original (initial if any, unbaked if any, then optimized). */
static inline const co_report_model *co_report_optimized(const co_report *r)
{
    return &r->model[r->n_models - 1];
}
static inline const co_report_model *co_report_initial(const co_report *r)
{
    return !r->levels && r->has_initial ? &r->model[1] : NULL;
}
static inline const co_report_model *co_report_unbaked(const co_report *r)
{
    return !r->levels && r->has_unbaked ? &r->model[r->n_models - 2] : NULL;
}

/* report_levels.c: load the original and the levels of the manifest o->lods. */
lm_status co_report_load_levels(co_report *r);

/* report_sheet.c: the contact sheet and the close-up. */
lm_status co_report_pictures(co_report *r);

/* report_plots.c: the two plots as SVG documents. */
void co_report_plot_energy(FILE *fp, const co_run_log *log);
void co_report_plot_per_view(FILE *fp, const co_report *r);

/* report_html.c: the page. */
lm_status co_report_write_page(const co_report *r, const char *path, const char *energy_svg,
                               const char *per_view_svg);

#endif
