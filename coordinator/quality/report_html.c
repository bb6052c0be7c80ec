/* coordinator/quality/report_html.c — the report page: one HTML file with its images embedded
 * (PNG as base64 data URIs) and its plots inline (SVG), styled by a few CSS rules, no scripts.
 * Every number in the table carries a data-key attribute ("optimized.heldout_energy", ...) so
 * tools and tests can read the page. */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/atomic_file.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
#include "coordinator/quality/report_internal.h"

static void html_text(FILE *fp, const char *s)
{
    for (; s && *s; s++) {
        switch (*s) {
        case '<':
            fputs("&lt;", fp);
            break;
        case '>':
            fputs("&gt;", fp);
            break;
        case '&':
            fputs("&amp;", fp);
            break;
        case '"':
            fputs("&quot;", fp);
            break;
        default:
            fputc(*s, fp);
        }
    }
}

static void base64(FILE *fp, const uint8_t *d, size_t n)
{
    static const char a[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)d[i] << 16 | (i + 1 < n ? (uint32_t)d[i + 1] << 8 : 0) |
                     (i + 2 < n ? d[i + 2] : 0);
        char out[4] = {a[v >> 18], a[(v >> 12) & 63], i + 1 < n ? a[(v >> 6) & 63] : '=',
                       i + 2 < n ? a[v & 63] : '='};
        fwrite(out, 1, 4, fp);
    }
}

static lm_status embed_png(FILE *fp, const lm_image *img, const char *alt)
{
    uint8_t *png = NULL;
    size_t n = 0;
    lm_status s = lm_image_encode_png_memory(img, &png, &n);
    if (s)
        return s;
    fprintf(fp, "<img width=\"%d\" height=\"%d\" alt=\"", img->width, img->height);
    html_text(fp, alt);
    fputs("\" src=\"data:image/png;base64,", fp);
    base64(fp, png, n);
    fputs("\">\n", fp);
    free(png);
    return LM_OK;
}

static const char co_report_css[] =
    "body{font-family:sans-serif;margin:24px auto;max-width:1200px;color:#222;background:#fff}"
    "h1{font-size:22px}h2{font-size:17px;margin-top:28px;border-bottom:1px solid #ddd}"
    "table{border-collapse:collapse;font-size:14px}td,th{border:1px solid #ccc;padding:4px 10px}"
    "td.n{text-align:right;font-variant-numeric:tabular-nums}th{background:#f2f2f2}"
    "figure{margin:8px 0}figcaption{font-size:13px;color:#555}img{max-width:100%;height:auto;"
    "image-rendering:pixelated}.lead{font-size:16px}code{background:#f4f4f4}";

static void head(FILE *fp, const co_report *r)
{
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>lumesh "
          "report: ",
          fp);
    html_text(fp, r->levels ? r->o->lods : co_report_optimized(r)->path);
    fprintf(fp, "</title>\n<style>%s</style>\n</head>\n<body>\n<h1>lumesh quality report</h1>\n",
            co_report_css);
    fputs("<table>\n", fp);
    for (uint32_t i = 0; i < r->n_models; i++) {
        fprintf(fp, "<tr><th>%s</th><td><code>", r->model[i].label);
        html_text(fp, r->model[i].path);
        fputs("</code></td></tr>\n", fp);
    }
    fputs("</table>\n", fp);
}

static double pct(double a, double b)
{
    return b > 0 ? 100.0 * a / b : 0.0;
}

/* A level set in one sentence: its levels' vertex counts and held-out energies. */
static void lead_levels(FILE *fp, const co_report *r)
{
    const co_report_model *first = &r->model[1], *last = co_report_optimized(r);
    fprintf(fp,
            "<p class=\"lead\">%u levels of detail, %u to %u vertices; on the %u held-out views "
            "their image energy goes from %" PRId64 " to %" PRId64 ".</p>\n",
            r->n_models - 1, first->verts, last->verts, r->heldout->count, first->energy,
            last->energy);
}

/* One sentence of what changed, on the views the optimisation never saw. */
static void lead(FILE *fp, const co_report *r)
{
    const co_report_model *i = co_report_initial(r), *o = co_report_optimized(r);
    if (r->levels) {
        lead_levels(fp, r);
        return;
    }
    fputs("<p class=\"lead\">", fp);
    if (i) {
        fprintf(fp,
                "On the %u held-out views the optimized model's image energy is <b>%.1f%%</b> "
                "of the initial mesh's",
                r->heldout->count, pct((double)o->energy, (double)i->energy));
        if (o->cov.measured)
            fprintf(fp, "; crack and hole pixels %" PRIu64 " &rarr; %" PRIu64, i->cov.cracks_px,
                    o->cov.cracks_px);
        fputs(".", fp);
    } else {
        fprintf(fp, "Held-out image energy of the optimized model over %u views: %" PRId64 ".",
                r->heldout->count, o->energy);
    }
    const co_report_model *u = co_report_unbaked(r);
    if (u)
        fprintf(fp, " With its maps baked it is <b>%.1f%%</b> of the unbaked result's.",
                pct((double)o->energy, (double)u->energy));
    fputs("</p>\n", fp);
}

static lm_status pictures(FILE *fp, const co_report *r)
{
    fprintf(fp, "<h2>Held-out views</h2>\n<figure>\n");
    lm_status s = embed_png(fp, r->sheet, "contact sheet");
    fputs("<figcaption>Columns: original", fp);
    for (uint32_t k = 1; k < r->n_models; k++)
        fprintf(fp, " | %s", r->model[k].label);
    fprintf(fp,
            " | difference (|luminance of original &minus; %s| &times;2: black none, red, "
            "yellow, white most). Rows: held-out views",
            co_report_optimized(r)->label);
    for (uint32_t k = 0; k < CO_REPORT_SHEET_VIEWS; k++)
        fprintf(fp, "%s %u", k ? "," : "", r->sheet_view[k]);
    fprintf(fp, ", %d&times;%d pixels.</figcaption>\n</figure>\n", r->size, r->size);
    if (s || !r->closeup)
        return s;
    fprintf(fp, "<h2>Cracks close-up</h2>\n<figure>\n");
    s = embed_png(fp, r->closeup, "cracks close-up");
    fprintf(fp,
            "<figcaption>The %dx%d window (of held-out view %u rendered at %dx%d) with the most "
            "crack pixels of the %s mesh: %" PRIu64 ". Columns as above.</figcaption>\n"
            "</figure>\n",
            r->crop.w, r->crop.h, r->sheet_view[r->crop.view], r->size * r->zoom, r->size * r->zoom,
            r->closeup_of->label, r->crop_cracks);
    return s;
}

typedef enum cell_kind { CELL_I64, CELL_U64, CELL_REAL, CELL_PCT } cell_kind;

/* A table cell carrying its number: data-key MODEL.KEY, data-value the number itself. */
static void cell(FILE *fp, const char *model, const char *key, cell_kind k, double v, int64_t i)
{
    fprintf(fp, "<td class=\"n\" data-key=\"%s.%s\" data-value=\"", model, key);
    if (k == CELL_I64 || k == CELL_U64)
        fprintf(fp, "%" PRId64 "\">%" PRId64, i, i);
    else if (k == CELL_REAL)
        fprintf(fp, "%.6f\">%.6f", v, v);
    else
        fprintf(fp, "%.9g\">%.4f%%", v, 100.0 * v);
    fputs("</td>", fp);
}

static void blank(FILE *fp)
{
    fputs("<td class=\"n\">&mdash;</td>", fp);
}

/* Rows of the table: one measure, a cell per model (the original's where it has one). */
typedef enum row_source {
    ROW_ENERGY,
    ROW_MSE,
    ROW_ORIGINAL_PX,
    ROW_MISSING,
    ROW_EXTRA,
    ROW_CRACKS,
    ROW_DIST_MEAN,
    ROW_DIST_RMS,
    ROW_DIST_MAX,
    ROW_VERTS,
    ROW_TRIS,
    ROW_PARTS,
    ROW_SWITCH, /* levels only */
} row_source;

typedef struct row_def {
    row_source src;
    const char *key, *label;
} row_def;

static const row_def rows[] = {
    {ROW_ENERGY, "heldout_energy",
     "held-out image energy (sum of squared 8-bit luminance differences)"},
    {ROW_MSE, "mse", "per-pixel error (energy / pixels)"},
    {ROW_ORIGINAL_PX, "original_px", "pixels the original covers"},
    {ROW_MISSING, "missing_px",
     "silhouette: pixels missing (original's surface, model's background)"},
    {ROW_EXTRA, "extra_px", "silhouette: extra pixels (model's surface, original's background)"},
    {ROW_CRACKS, "cracks_px", "cracks and holes (missing pixels well inside the silhouette)"},
    {ROW_DIST_MEAN, "dist_mean", "surface distance, mean (of the bounding-box diagonal)"},
    {ROW_DIST_RMS, "dist_rms", "surface distance, RMS"},
    {ROW_DIST_MAX, "dist_max", "surface distance, max (sampled Hausdorff)"},
    {ROW_VERTS, "verts", "vertices"},
    {ROW_TRIS, "tris", "triangles"},
    {ROW_PARTS, "parts", "parts"},
    {ROW_SWITCH, "switch_distance",
     "shown from this distance on (the manifest's switch distance for its screen)"},
};

/* The number of measure src for model m: its kind and value; 0 when it has none. */
static int row_value(const co_report *r, const co_report_model *m, row_source src, cell_kind *k,
                     double *v, int64_t *i)
{
    int orig = m == &r->model[0];
    const co_coverage *c = orig ? &r->model[1].cov : &m->cov;
    double px = (double)r->heldout->count * r->size * r->size, diag = m->dist.diagonal;
    *k = CELL_U64;
    *v = 0;
    *i = 0;
    if (src <= ROW_MSE && orig)
        return 0;
    if (src >= ROW_ORIGINAL_PX && src <= ROW_CRACKS &&
        (!c->measured || orig != (src == ROW_ORIGINAL_PX)))
        return 0;
    if (src >= ROW_DIST_MEAN && src <= ROW_DIST_MAX && orig)
        return 0;
    if (src == ROW_SWITCH && m->switch_distance < 0)
        return 0;
    switch (src) {
    case ROW_ENERGY:
        *i = m->energy;
        break;
    case ROW_MSE:
        *k = CELL_REAL;
        *v = (double)m->energy / px;
        break;
    case ROW_ORIGINAL_PX:
        *i = (int64_t)c->original_px;
        break;
    case ROW_MISSING:
        *i = (int64_t)c->missing_px;
        break;
    case ROW_EXTRA:
        *i = (int64_t)c->extra_px;
        break;
    case ROW_CRACKS:
        *i = (int64_t)c->cracks_px;
        break;
    case ROW_DIST_MEAN:
        *k = CELL_PCT;
        *v = m->dist.mean / diag;
        break;
    case ROW_DIST_RMS:
        *k = CELL_PCT;
        *v = m->dist.rms / diag;
        break;
    case ROW_DIST_MAX:
        *k = CELL_PCT;
        *v = m->dist.max / diag;
        break;
    case ROW_VERTS:
        *i = m->verts;
        break;
    case ROW_TRIS:
        *i = m->tris;
        break;
    case ROW_PARTS:
        *i = m->parts;
        break;
    case ROW_SWITCH:
        *k = CELL_REAL;
        *v = m->switch_distance;
        break;
    }
    return 1;
}

static void row_cell(FILE *fp, const co_report *r, const co_report_model *m, row_source src,
                     const char *key)
{
    cell_kind k;
    double v;
    int64_t i;
    if (row_value(r, m, src, &k, &v, &i))
        cell(fp, m->label, key, k, v, i);
    else
        blank(fp);
}

static void table(FILE *fp, const co_report *r)
{
    fprintf(fp,
            "<h2>Numbers</h2>\n<p>Held-out: %u views of %d&times;%d pixels%s that no "
            "optimisation uses, rendered by <span data-key=\"report.renderer\">",
            r->heldout->count, r->size, r->size,
            r->o->views.dist == LM_VIEW_DIST_UPPER ? " (mirrored into the upper hemisphere)" : "");
    html_text(fp, r->renderer);
    fputs("</span>.</p>\n<table>\n<tr><th>measure</th>", fp);
    for (uint32_t i = 0; i < r->n_models; i++)
        fprintf(fp, "<th>%s</th>", r->model[i].label);
    fputs("</tr>\n", fp);
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; k++) {
        if (rows[k].src == ROW_SWITCH && !r->levels)
            continue;
        fprintf(fp, "<tr><td>%s</td>", rows[k].label);
        for (uint32_t i = 0; i < r->n_models; i++)
            row_cell(fp, r, &r->model[i], rows[k].src, rows[k].key);
        fputs("</tr>\n", fp);
    }
    fputs("</table>\n", fp);
}

/* The run's totals from its log, when it has a summary. */
static void run(FILE *fp, const co_run_log *log)
{
    fputs("<h2>The run</h2>\n", fp);
    if (!log || !log->has_summary) {
        fputs("<p>No run log was given (<code>lumesh report --log RUN.jsonl</code> takes the "
              "output of <code>lumesh optimize --json</code>).</p>\n",
              fp);
        return;
    }
    fputs("<table>\n", fp);
    fprintf(fp, "<tr><td>evaluations</td>");
    cell(fp, "run", "evals", CELL_U64, 0, (int64_t)log->evals);
    fprintf(fp, "</tr>\n<tr><td>wall time, load to output (s)</td>");
    cell(fp, "run", "wall_s", CELL_REAL, log->wall_s, 0);
    fprintf(fp,
            "</tr>\n<tr><td>energy on the optimisation views, start &rarr; end</td>"
            "<td class=\"n\">%" PRId64 " &rarr; %" PRId64 "</td></tr>\n",
            log->energy_start, log->energy_end);
    fputs("<tr><td>stopped by</td><td>", fp);
    html_text(fp, log->stop_reason);
    fputs("</td></tr>\n<tr><td>renderer</td><td data-key=\"run.renderer\">", fp);
    html_text(fp, log->renderer);
    fputs("</td></tr>\n</table>\n", fp);
}

static void plots(FILE *fp, const char *energy_svg, const char *per_view_svg)
{
    if (energy_svg) {
        fputs("<h2>Energy during the run</h2>\n<figure>\n", fp);
        fputs(energy_svg, fp);
        fputs("<figcaption>Energy relative to the start on the optimisation views, and the "
              "accepted moves by kind, against evaluations (from the run log).</figcaption>\n"
              "</figure>\n",
              fp);
    }
    fputs("<h2>Per-view error</h2>\n<figure>\n", fp);
    fputs(per_view_svg, fp);
    fputs("</figure>\n", fp);
}

static const char co_report_methods[] =
    "<h2>How these are measured</h2>\n<ul>\n"
    "<li>Image energy: the sum over views and pixels of the squared difference of 8-bit "
    "luminance, Y = (77 R + 150 G + 29 B + 128) / 256, between the original's image and the "
    "model's (<code>lumesh energy ORIGINAL MODEL --heldout</code> gives the same numbers).</li>\n"
    "<li>Silhouette and cracks: pixels where the original shows a surface and the model the "
    "background (missing), the reverse (extra), and the missing pixels with no background of the "
    "original within a few pixels (cracks and holes between parts rather than a thinner "
    "outline); <code>lumesh compare --heldout</code> gives them too.</li>\n"
    "<li>Surface distance: points spread over each surface in proportion to area, each one's "
    "distance to the closest point of the other surface; mean, RMS and max over both sets, as "
    "fractions of the original's bounding-box diagonal.</li>\n"
    "</ul>\n";

lm_status co_report_write_page(const co_report *r, const char *path, const char *energy_svg,
                               const char *per_view_svg)
{
    lm_atomic_file f;
    lm_status s = lm_atomic_open(&f, path);
    if (s)
        return s;
    FILE *fp = f.fp;
    head(fp, r);
    lead(fp, r);
    s = pictures(fp, r);
    if (!s) {
        table(fp, r);
        if (!r->levels)
            run(fp, r->o->log);
        plots(fp, energy_svg, per_view_svg);
        fputs(co_report_methods, fp);
        fputs("</body>\n</html>\n", fp);
        return lm_atomic_commit(&f);
    }
    lm_atomic_abort(&f);
    return s;
}
