/* coordinator/quality/report.c — co_report_write: measure, draw, plot, write. The pieces the page
 * embeds are written beside it too; pieces a previous report left in the folder that this one
 * does not make (a close-up, an energy plot) are removed so the folder never mixes two reports. */
#include "coordinator/quality/report.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/folders.h"
#include "common/io/atomic_file.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
#include "coordinator/quality/report_internal.h"

typedef struct report_paths {
    char page[4096], sheet[4096], closeup[4096], energy[4096], per_view[4096];
} report_paths;

static lm_status make_paths(const char *dir, report_paths *p)
{
    int n = snprintf(p->page, sizeof p->page, "%s/index.html", dir);
    snprintf(p->sheet, sizeof p->sheet, "%s/contact_sheet.png", dir);
    snprintf(p->closeup, sizeof p->closeup, "%s/closeup.png", dir);
    snprintf(p->energy, sizeof p->energy, "%s/energy.svg", dir);
    snprintf(p->per_view, sizeof p->per_view, "%s/per_view.svg", dir);
    if (n < 0 || (size_t)n + 8 >= sizeof p->page)
        return lm_fail(LM_E_INVALID, "folder name '%s' is too long", dir);
    return lm_make_folders(dir);
}

/* An SVG document in memory (*out, malloc'ed) and in its file. */
static lm_status plot(const co_report *r, int energy, const char *path, char **out)
{
    size_t n = 0;
    FILE *mem = open_memstream(out, &n);
    if (!mem)
        return lm_fail(LM_E_NOMEM, "out of memory for a plot");
    if (energy)
        co_report_plot_energy(mem, r->o->log);
    else
        co_report_plot_per_view(mem, r);
    if (fclose(mem) != 0)
        return lm_fail(LM_E_NOMEM, "out of memory for a plot");
    lm_atomic_file f;
    lm_status s = lm_atomic_open(&f, path);
    if (s)
        return s;
    fwrite(*out, 1, n, f.fp);
    return lm_atomic_commit(&f);
}

static lm_status write_files(const co_report *r, const report_paths *p)
{
    char *energy = NULL, *per_view = NULL;
    int has_energy = r->o->log && r->o->log->n > 0;
    lm_status s = lm_image_write(p->sheet, r->sheet);
    if (!s && r->closeup)
        s = lm_image_write(p->closeup, r->closeup);
    else if (!s)
        unlink(p->closeup);
    if (!s && has_energy)
        s = plot(r, 1, p->energy, &energy);
    else if (!s)
        unlink(p->energy);
    if (!s)
        s = plot(r, 0, p->per_view, &per_view);
    if (!s)
        s = co_report_write_page(r, p->page, energy, per_view);
    free(energy);
    free(per_view);
    return s;
}

lm_status co_report_write(const co_report_options *o, char *page, size_t cap)
{
    if (!o->original || !(o->optimized || o->lods) || !o->dir)
        return lm_fail(LM_E_INVALID,
                       "a report needs the original, the optimized model or levels and a folder");
    report_paths *p = malloc(sizeof *p);
    co_report r = {.o = o};
    lm_status s = p ? make_paths(o->dir, p) : lm_fail(LM_E_NOMEM, "out of memory");
    if (!s)
        s = co_report_measure(&r);
    if (!s)
        s = co_report_pictures(&r);
    if (!s)
        s = write_files(&r, p);
    if (!s && page)
        snprintf(page, cap, "%s", p->page);
    co_report_free(&r);
    free(p);
    return s;
}
