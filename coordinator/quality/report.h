/* coordinator/quality/report.h — the quality report: a self-contained HTML page (no network, no
 * scripts; images embedded, plots inline SVG) that shows how an optimised model compares with its
 * original and with the coarse mesh it started from, on the 24 held-out views no optimisation
 * sees: a contact sheet (original | initial | optimized | difference), the close-up of the worst
 * cracks where there are cracks, a table (held-out energy and per-pixel error, silhouette and
 * crack pixels, symmetric surface distance, vertex/triangle/part counts, the run's evaluations,
 * wall time and renderer) and plots (energy against evaluations with accepted moves by kind, from
 * the run's log; per-view error). Every number is measured on the files as written; the same
 * files and log give the same page, byte for byte. Given a level-of-detail manifest (lods.json of
 * `lumesh lod`) instead, the page shows its levels side by side: original | LOD0 | LOD1 | ... on
 * the sheet, every level measured in the table with the switch distance the manifest gives it.
 * Given the result before its maps were baked too (optimize --bake --report), the page shows it
 * as "unbaked" between the initial and the optimized (baked) model. */
#ifndef LM_COORDINATOR_REPORT_H
#define LM_COORDINATOR_REPORT_H

#include <stddef.h>

#include "common/error.h"
#include "common/io/mesh_io.h"
#include "common/view.h"
#include "coordinator/quality/run_log.h"

#define CO_REPORT_SHEET_VIEWS 4 /* held-out views on the contact sheet */
#define CO_REPORT_ZOOM 4        /* the close-up is rendered this many times larger */
/* The models a page compares: the original and every level of a manifest at most. */
#define CO_REPORT_MAX_MODELS (1 + LM_MESH_MAX_LODS)

typedef struct co_report_options {
    const char *original;  /* required */
    const char *initial;   /* the coarse mesh the optimisation started from; NULL = none */
    const char *optimized; /* required unless lods */
    const char *unbaked;   /* the optimized model before its maps were baked (optimize --bake
                              --report: shown beside the baked one); NULL = none */
    const char *lods;      /* a lods.json (`lumesh lod`): its levels instead of optimized and
                              initial (one file per level, paths relative to the manifest) */
    const co_run_log *log; /* the run (plots, evaluations, wall time); NULL = none */
    const char *device;    /* rendering device; NULL = "auto" */
    int size;              /* side of every view image; 0 = 256 */
    const char *dir;       /* output folder, created with its parents */
    lm_view_spec views;    /* the distribution the held-out views follow (lm_view_dist: the
                              sphere's, or mirrored into the upper hemisphere); count unused */
} co_report_options;

/* Write DIR/index.html (the page), and beside it the pieces it embeds: contact_sheet.png,
 * closeup.png (when a model shows cracks), energy.svg (when the log has samples), per_view.svg.
 * page (may be NULL) receives the path of index.html (cap bytes). */
lm_status co_report_write(const co_report_options *o, char *page, size_t cap);

#endif
