/* coordinator/quality/report_plots.c — the report's two plots as standalone SVG documents: the
 * energy relative to the start against evaluations, with the accepted moves by kind (cumulative)
 * in a panel below; and the per-pixel error of every held-out view, initial beside optimized.
 * Plain SVG 1.1 (lines, rectangles, text): any browser shows it, without scripts. */
#include <math.h>
#include <string.h>

#include "coordinator/quality/report_internal.h"

#define PLOT_W 760
#define PLOT_LEFT 72
#define PLOT_RIGHT 740

typedef struct panel {
    double x0, x1, y0, y1; /* data ranges */
    int top, bottom;       /* pixel rows of the plotting area */
} panel;

static double px_x(const panel *p, double x)
{
    return PLOT_LEFT + (x - p->x0) / (p->x1 - p->x0) * (PLOT_RIGHT - PLOT_LEFT);
}

static double px_y(const panel *p, double y)
{
    return p->bottom - (y - p->y0) / (p->y1 - p->y0) * (p->bottom - p->top);
}

/* A round step giving about `ticks` intervals over `range` (1, 2 or 5 times a power of ten). */
static double nice_step(double range, int ticks)
{
    double raw = range / ticks, mag = pow(10, floor(log10(raw))), f = raw / mag;
    return (f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10) * mag;
}

/* 12000 -> "12k", 1500000 -> "1.5M", 0.25 -> "0.25". */
static void fmt_num(double v, char *out, size_t cap)
{
    double a = fabs(v);
    if (a >= 1e6)
        snprintf(out, cap, "%gM", v / 1e6);
    else if (a >= 1e4)
        snprintf(out, cap, "%gk", v / 1e3);
    else
        snprintf(out, cap, "%g", v);
}

static void svg_begin(FILE *fp, int h, const char *title)
{
    fprintf(fp,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d "
            "%d\" font-family=\"sans-serif\" font-size=\"12\">\n<title>%s</title>\n"
            "<rect width=\"%d\" height=\"%d\" fill=\"#ffffff\"/>\n",
            PLOT_W, h, PLOT_W, h, title, PLOT_W, h);
}

/* Grid lines and labels of both axes, the frame, and the axis titles. */
static void axes(FILE *fp, const panel *p, const char *xtitle, const char *ytitle, int xlabels)
{
    double sy = nice_step(p->y1 - p->y0, 4), sx = nice_step(p->x1 - p->x0, 6);
    char buf[32];
    for (double y = ceil(p->y0 / sy) * sy; y <= p->y1 + 1e-9 * sy; y += sy) {
        fmt_num(y, buf, sizeof buf);
        fprintf(fp,
                "<line x1=\"%d\" y1=\"%.1f\" x2=\"%d\" y2=\"%.1f\" stroke=\"#e4e4e4\"/>"
                "<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%s</text>\n",
                PLOT_LEFT, px_y(p, y), PLOT_RIGHT, px_y(p, y), PLOT_LEFT - 6, px_y(p, y) + 4, buf);
    }
    for (double x = ceil(p->x0 / sx) * sx; xlabels && x <= p->x1 + 1e-9 * sx; x += sx) {
        fmt_num(x, buf, sizeof buf);
        fprintf(fp,
                "<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"#e4e4e4\"/>"
                "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%s</text>\n",
                px_x(p, x), p->top, px_x(p, x), p->bottom, px_x(p, x), p->bottom + 16, buf);
    }
    fprintf(fp,
            "<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\" fill=\"none\" stroke=\"#555\"/>\n",
            PLOT_LEFT, p->top, PLOT_RIGHT - PLOT_LEFT, p->bottom - p->top);
    if (xtitle)
        fprintf(fp, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">%s</text>\n",
                (PLOT_LEFT + PLOT_RIGHT) / 2, p->bottom + 34, xtitle);
    fprintf(fp,
            "<text transform=\"translate(16 %d) rotate(-90)\" text-anchor=\"middle\">%s</text>\n",
            (p->top + p->bottom) / 2, ytitle);
}

static const char *const kind_colour[] = {"#999999", "#1f77b4", "#2ca02c", "#d62728",
                                          "#9467bd", "#8c564b", "#e377c2", "#17becf"};

/* One series as a polyline: y(i) of the log's samples. */
static void series(FILE *fp, const panel *p, const co_run_log *log, int kind, const char *colour)
{
    fprintf(fp, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"", colour);
    for (uint32_t i = 0; i < log->n; i++) {
        const co_run_sample *s = &log->samples[i];
        double y = kind < 0 ? s->energy_rel : (double)s->accepted[kind];
        fprintf(fp, "%s%.1f,%.1f", i ? " " : "", px_x(p, (double)s->evals), px_y(p, y));
    }
    fputs("\"/>\n", fp);
}

static void legend(FILE *fp, int x, int y, const char *colour, const char *text)
{
    fprintf(fp,
            "<rect x=\"%d\" y=\"%d\" width=\"14\" height=\"4\" fill=\"%s\"/>"
            "<text x=\"%d\" y=\"%d\">%s</text>\n",
            x, y - 4, colour, x + 18, y, text);
}

void co_report_plot_energy(FILE *fp, const co_run_log *log)
{
    double xmax = 1, ymax = 1, amax = 1;
    for (uint32_t i = 0; i < log->n; i++) {
        const co_run_sample *s = &log->samples[i];
        xmax = (double)s->evals > xmax ? (double)s->evals : xmax;
        ymax = s->energy_rel > ymax ? s->energy_rel : ymax;
        for (uint32_t k = 0; k < log->n_kinds; k++)
            amax = (double)s->accepted[k] > amax ? (double)s->accepted[k] : amax;
    }
    svg_begin(fp, 480, "energy and accepted moves against evaluations");
    panel e = {0, xmax, 0, ymax, 30, 250}, a = {0, xmax, 0, amax, 300, 420};
    fprintf(fp,
            "<text x=\"%d\" y=\"18\" font-weight=\"bold\">image energy relative to the "
            "start (optimisation views)</text>\n",
            PLOT_LEFT);
    axes(fp, &e, NULL, "energy / start", 1);
    series(fp, &e, log, -1, "#000000");
    axes(fp, &a, "evaluations", "accepted moves", 1);
    int x = PLOT_LEFT + 180;
    fprintf(fp, "<text x=\"%d\" y=\"%d\" font-weight=\"bold\">accepted moves by kind</text>\n",
            PLOT_LEFT, a.top - 8);
    for (uint32_t k = 0; k < log->n_kinds; k++) {
        const char *c = kind_colour[k % (sizeof kind_colour / sizeof kind_colour[0])];
        series(fp, &a, log, (int)k, c);
        legend(fp, x, a.top - 8, c, log->kinds[k]);
        x += 24 + 8 * (int)strlen(log->kinds[k]);
    }
    fputs("</svg>\n", fp);
}

/* Per-pixel error of view h of model m (energy / pixels of a view). */
static double view_error(const co_report *r, const co_report_model *m, uint32_t h)
{
    return (double)m->per_view[h] / ((double)r->size * r->size);
}

/* The models the per-view plot shows, with their colours: the initial (grey), the unbaked result
 * (orange) and the optimized (blue), or every level. */
static uint32_t per_view_models(const co_report *r, const co_report_model **m, const char **colour)
{
    static const char *const level_colour[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                               "#9467bd", "#8c564b", "#e377c2", "#17becf"};
    uint32_t c = 0;
    if (r->levels) {
        for (uint32_t k = 1; k < r->n_models; k++, c++) {
            m[c] = &r->model[k];
            colour[c] = level_colour[c % (sizeof level_colour / sizeof level_colour[0])];
        }
        return c;
    }
    const co_report_model *ini = co_report_initial(r), *unbaked = co_report_unbaked(r);
    if (ini) {
        m[c] = ini;
        colour[c++] = "#b0b0b0";
    }
    if (unbaked) {
        m[c] = unbaked;
        colour[c++] = "#ff7f0e";
    }
    m[c] = co_report_optimized(r);
    colour[c++] = "#1f77b4";
    return c;
}

static void per_view_legend(FILE *fp, const co_report *r, const co_report_model *const *m,
                            const char *const *colour, uint32_t c)
{
    if (!r->levels) {
        for (uint32_t j = 0; j < c; j++)
            legend(fp, PLOT_RIGHT - 100 - 80 * (int)(c - 1 - j), 18, colour[j], m[j]->label);
        return;
    }
    for (uint32_t j = 0; j < c; j++)
        legend(fp, PLOT_RIGHT - 64 * (int)(c - j), 18, colour[j], m[j]->label);
}

void co_report_plot_per_view(FILE *fp, const co_report *r)
{
    const co_report_model *m[CO_REPORT_MAX_MODELS];
    const char *colour[CO_REPORT_MAX_MODELS];
    uint32_t c = per_view_models(r, m, colour), n = r->heldout->count;
    double ymax = 1e-9;
    for (uint32_t h = 0; h < n; h++)
        for (uint32_t j = 0; j < c; j++)
            ymax = fmax(ymax, view_error(r, m[j], h));
    svg_begin(fp, 300, "per-pixel error of every held-out view");
    panel p = {0, n, 0, ymax * 1.05, 30, 240};
    fprintf(fp,
            "<text x=\"%d\" y=\"18\" font-weight=\"bold\">squared luminance error per pixel, "
            "held-out views</text>\n",
            PLOT_LEFT);
    axes(fp, &p, "held-out view", "error per pixel", 0);
    double slot = (PLOT_RIGHT - PLOT_LEFT) / (double)n, w = slot * (c == 1   ? 0.7
                                                                    : c == 2 ? 0.4
                                                                             : 0.76 / c);
    for (uint32_t h = 0; h < n; h++) {
        double x = PLOT_LEFT + slot * h + slot * 0.12;
        for (uint32_t j = 0; j < c; j++, x += w) {
            double y = px_y(&p, view_error(r, m[j], h));
            fprintf(fp, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"%s\"/>",
                    x, y, w, p.bottom - y, colour[j]);
        }
        fprintf(fp, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%u</text>\n",
                PLOT_LEFT + slot * (h + 0.5), p.bottom + 16, h);
    }
    per_view_legend(fp, r, m, colour, c);
    fputs("</svg>\n", fp);
}
