/* coordinator/cli/cli_energy.c — `lumesh energy ORIGINAL MODEL... [--views N] [--size S]
 * [--heldout | --dense] [--distance] [--device D]`: the image energy E = Σ (Ŷ - Y)² of each MODEL
 * against ORIGINAL over views framed by the original's bounding sphere, printed as JSON (total,
 * per view, mean squared error, the silhouette coverage, the renderer that made every image and,
 * with --distance, the symmetric surface distance), one line per model. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>

#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/job/progress.h"
#include "coordinator/quality/compare.h"
#include "coordinator/quality/surface_distance.h"
#include "coordinator/quality/view_setup.h"

#define CMD "energy"
#define MAX_MODELS 64
#define TOO_MANY "at most " CO_STR(MAX_MODELS) " models at once"

typedef struct energy_args {
    const char *original, *device;
    const char *model[MAX_MODELS];
    uint32_t n_models;
    lm_view_spec views;
    uint32_t size;
    lm_view_set_kind kind;
    int distance;
} energy_args;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: lumesh energy ORIGINAL MODEL... [--views N] [--size S] [--heldout | --dense]\n"
            "                     [--distance] [--device D]\n"
            "Prints as JSON, one line per MODEL, the image energy of MODEL against ORIGINAL: the\n"
            "sum over views and pixels of the squared difference of 8-bit luminance (total,\n"
            "per_view, mse), and the silhouette coverage: pixels where the original shows a\n"
            "surface (original_px), where MODEL shows background there instead (missing_px:\n"
            "holes, cracks) and where MODEL covers the original's background (extra_px), and the\n"
            "missing pixels well inside the original's silhouette (cracks_px: holes and cracks\n"
            "between parts, not a thinner outline; 2 pixels from its background at 256, more for\n"
            "larger views). The original's images are rendered once for all models.\n"
            "  --views N     views around the original (default %u; 12 icosahedron, 20\n"
            "                dodecahedron, others a spherical Fibonacci set); upper or upper:N:\n"
            "                Fibonacci views on the hemisphere above it (+Y up), and with\n"
            "                --heldout or --dense those sets mirrored into that hemisphere\n"
            "  --views-from FILE  the cameras of a JSON file (as lumesh optimize; --heldout and\n"
            "                --dense stay the sphere's)\n"
            "  --size S      image side in pixels (default %d)\n"
            "  --heldout     the 24 held-out views instead (the paper's evaluation protocol)\n"
            "  --dense       the dense check instead: %u views, a third each at 2, 3 and 5\n"
            "                bounding-sphere radii, none of them an optimisation or held-out view\n"
            "  --distance    also the symmetric surface distance to ORIGINAL (mean, rms, max and\n"
            "                the original's bounding-box diagonal, in the models' units; %u\n"
            "                samples a surface, from a fixed seed), and its two sides' means:\n"
            "                mean_to_original (the model's points to the original's surface)\n"
            "                and mean_from_original (the original's points to the model's)\n"
            "  --device D    auto (default), cpu, egl:N or host\n"
            "  -h, --help    this text\n",
            LM_DEFAULT_VIEWS, LM_DEFAULT_VIEW_SIZE, LM_DENSE_VIEWS, CO_DISTANCE_SAMPLES);
}

/* --heldout or --dense: one of them, once. */
static int set_kind(energy_args *a, lm_view_set_kind kind)
{
    if (a->kind != LM_VIEWS_TRAINING)
        return co_cli_usage_error(CMD, "--heldout and --dense exclude each other");
    a->kind = kind;
    return -1;
}

static int heldout(void *a, const char *val)
{
    (void)val;
    return set_kind(a, LM_VIEWS_HELDOUT);
}

static int dense(void *a, const char *val)
{
    (void)val;
    return set_kind(a, LM_VIEWS_DENSE);
}

static const co_cli_spec spec = {
    CMD, usage, 2, 1 + MAX_MODELS, "expects ORIGINAL and MODEL (see --help)", TOO_MANY, 0};

static int parse(int argc, char **argv, energy_args *a)
{
    const co_opt opts[] = {CO_OPT_VIEWS(&a->views),
                           CO_OPT_SIZE(&a->size),
                           CO_OPT_CALL_FLAG("heldout", heldout, a),
                           CO_OPT_CALL_FLAG("dense", dense, a),
                           CO_OPT_FLAG("distance", 0, &a->distance),
                           CO_OPT_DEVICE(&a->device)};
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    a->original = argv[optind];
    for (int i = optind + 1; i < argc; i++)
        a->model[a->n_models++] = argv[i];
    return -1;
}

static void print_distance(const co_surface_distance *d)
{
    printf(", \"distance\": {\"mean\": %.9g, \"rms\": %.9g, \"max\": %.9g, \"diagonal\": %.9g, "
           "\"samples\": %u, \"mean_to_original\": %.9g, \"mean_from_original\": %.9g}",
           d->mean, d->rms, d->max, d->diagonal, d->samples, d->mean_to_original,
           d->mean_from_original);
}

static void print_json(const energy_args *a, uint32_t i, const lm_view_set *vs, int64_t total,
                       const int64_t *per, const co_coverage *cov, const char *renderer,
                       const co_surface_distance *dist)
{
    int size = vs->views[0].width;
    double pixels = (double)vs->count * size * size;
    printf("{\"model\": ");
    co_json_string(stdout, a->model[i]);
    printf(", \"total\": %lld, \"per_view\": [", (long long)total);
    for (uint32_t h = 0; h < vs->count; h++)
        printf("%s%lld", h ? ", " : "", (long long)per[h]);
    printf("], \"mse\": %.6f, \"views\": %u, \"size\": %d, \"heldout\": %s, \"dense\": %s, "
           "\"coverage\": ",
           (double)total / pixels, vs->count, size, a->kind == LM_VIEWS_HELDOUT ? "true" : "false",
           a->kind == LM_VIEWS_DENSE ? "true" : "false");
    co_coverage_print_json(stdout, cov);
    if (dist)
        print_distance(dist);
    co_json_end_with_renderer(stdout, renderer);
}

/* Energies (and distances) of every model, one JSON line each. */
static lm_status measure(void *ctx, const lm_mesh *orig, const lm_mesh *const *models,
                         const lm_view_set *vs)
{
    const energy_args *a = ctx;
    uint32_t n = a->n_models;
    int64_t *total = calloc(n, sizeof *total);
    int64_t *per = calloc((size_t)n * vs->count, sizeof *per);
    co_coverage *cov = calloc(n, sizeof *cov);
    char renderer[128] = "";
    lm_status st = total && per && cov ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory");
    if (st == LM_OK)
        st = co_compare_energies(orig, vs, a->device, models, n, total, per, cov, renderer);
    for (uint32_t i = 0; i < n && st == LM_OK; i++) {
        co_surface_distance d;
        if (a->distance)
            st = co_surface_distance_measure(orig, models[i], 0, &d);
        if (st == LM_OK)
            print_json(a, i, vs, total[i], per + (size_t)i * vs->count, &cov[i], renderer,
                       a->distance ? &d : NULL);
    }
    free(total);
    free(per);
    free(cov);
    return st;
}

int co_cli_energy(int argc, char **argv)
{
    energy_args a = {
        .views = {.count = LM_DEFAULT_VIEWS}, .size = LM_DEFAULT_VIEW_SIZE, .device = "auto"};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    lm_status st =
        co_judge_files(a.original, a.model, a.n_models, &a.views, (int)a.size, a.kind, measure, &a);
    return st ? co_cli_fail(CMD, st) : 0;
}
