/* coordinator/cli/cli_compare.c — `lumesh compare ORIGINAL MODEL... -o IMAGE [--views N |
 * --heldout]
 * [--size S] [--closeup SIDE] [--device D]`: judges one or more models against the original
 * (image energy and silhouette coverage, as JSON on stdout) and writes a picture grid with the
 * columns original | model 1 | model 2 ...: one row per view, or with --closeup the SIDE x SIDE
 * window where the first model shows the most cracks and holes. */
#include <getopt.h>
#include <stdio.h>

#include "common/folders.h"
#include "common/image.h"
#include "common/io/image_io.h"
#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/job/progress.h"
#include "coordinator/quality/compare.h"
#include "coordinator/quality/view_setup.h"

#define CMD "compare"
#define MAX_MODELS 16
#define TOO_MANY "at most " CO_STR(MAX_MODELS) " models"

typedef struct compare_args {
    const char *original, *output, *device;
    const char *models[MAX_MODELS];
    lm_view_spec views;
    uint32_t n_models, size, closeup;
    int heldout;
} compare_args;

static void usage(FILE *f)
{
    fprintf(
        f,
        "usage: lumesh compare ORIGINAL MODEL... -o IMAGE [--views N | --heldout] [--size S]\n"
        "                      [--closeup SIDE] [--device D]\n"
        "Judges up to 16 models against ORIGINAL and writes a picture grid to IMAGE (PNG or any\n"
        "format OpenImageIO writes): columns original | MODEL 1 | MODEL 2 ..., one row per\n"
        "view. Prints JSON: per model the image energy and the silhouette coverage (see\n"
        "lumesh energy --help), and where the close-up was taken.\n"
        "  -o, --output IMAGE  the picture grid (written atomically; missing folders are made)\n"
        "  --views N           views around the original (default 4); upper[:N]: on the\n"
        "                      hemisphere above it (+Y up)\n"
        "  --views-from FILE   the cameras of a JSON file instead (as lumesh optimize)\n"
        "  --heldout           the 24 held-out views instead (with --views upper: mirrored\n"
        "                      into the upper hemisphere)\n"
        "  --size S            image side in pixels (default %d)\n"
        "  --closeup SIDE      one SIDE x SIDE window instead of whole views: the one, over all\n"
        "                      views, where the first MODEL shows the most cracks and holes\n"
        "                      (pixels inside the original's silhouette left uncovered); render\n"
        "                      with --size larger than SIDE to magnify\n"
        "  --device D          auto (default), cpu, egl:N or host\n"
        "  -h, --help          this text\n",
        LM_DEFAULT_VIEW_SIZE);
}

static const co_cli_spec spec = {
    CMD,      usage, 2, 1 + MAX_MODELS, "expects ORIGINAL and at least one MODEL (see --help)",
    TOO_MANY, 0};

static int parse(int argc, char **argv, compare_args *a)
{
    const co_opt opts[] = {CO_OPT_OUTPUT_NEEDED(&a->output, "needs -o IMAGE (see --help)"),
                           CO_OPT_VIEWS(&a->views),
                           CO_OPT_FLAG("heldout", 0, &a->heldout),
                           CO_OPT_SIZE(&a->size),
                           CO_OPT_U32("closeup", 0, &a->closeup, 8, LM_MAX_VIEW_SIZE),
                           CO_OPT_DEVICE(&a->device)};
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    if (a->closeup > a->size)
        return co_cli_usage_error(CMD, "--closeup %u is larger than --size %u", a->closeup,
                                  a->size);
    a->original = argv[optind];
    for (int i = optind + 1; i < argc; i++)
        a->models[a->n_models++] = argv[i];
    return -1;
}

static void print_json(const compare_args *a, uint32_t n_views, const int64_t *energy,
                       const co_coverage *cov, const co_crop *crop, uint64_t crop_cracks,
                       const char *renderer)
{
    printf("{\"models\": [");
    for (uint32_t i = 0; i < a->n_models; i++) {
        printf("%s{\"file\": ", i ? ", " : "");
        co_json_string(stdout, a->models[i]);
        printf(", \"energy\": %lld, \"coverage\": ", (long long)energy[i]);
        co_coverage_print_json(stdout, &cov[i]);
        printf("}");
    }
    printf("], \"views\": %u, \"heldout\": %s, \"size\": %u, \"image\": ", n_views,
           a->heldout ? "true" : "false", a->size);
    co_json_string(stdout, a->output);
    if (crop)
        printf(", \"closeup\": {\"view\": %u, \"x\": %d, \"y\": %d, \"side\": %d, "
               "\"cracks_px\": %llu}",
               crop->view, crop->x, crop->y, crop->w, (unsigned long long)crop_cracks);
    co_json_end_with_renderer(stdout, renderer);
}

/* Energies and coverage, then the grid (whole views or the close-up), then the JSON. */
static lm_status run(void *ctx, const lm_mesh *orig, const lm_mesh *const *models,
                     const lm_view_set *vs)
{
    const compare_args *a = ctx;
    int64_t energy[MAX_MODELS];
    co_coverage cov[MAX_MODELS];
    char renderer[128] = "";
    co_crop crop = {0, 0, 0, 0, 0};
    uint64_t crop_cracks = 0;
    lm_image *grid = NULL;
    lm_status st =
        co_compare_energies(orig, vs, a->device, models, a->n_models, energy, NULL, cov, renderer);
    if (st == LM_OK && a->closeup)
        st = co_compare_find_cracks(orig, vs, a->device, models[0], (int)a->closeup, &crop,
                                    &crop_cracks);
    if (st == LM_OK)
        st = co_compare_grid(orig, vs, a->device, models, a->n_models, a->closeup ? &crop : NULL,
                             &grid);
    if (st == LM_OK)
        st = lm_make_parent_folders(a->output);
    if (st == LM_OK)
        st = lm_image_write(a->output, grid);
    lm_image_destroy(grid);
    if (st == LM_OK)
        print_json(a, vs->count, energy, cov, a->closeup ? &crop : NULL, crop_cracks, renderer);
    return st;
}

int co_cli_compare(int argc, char **argv)
{
    compare_args a = {.views = {.count = 4}, .size = LM_DEFAULT_VIEW_SIZE, .device = "auto"};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    lm_view_set_kind kind = a.heldout ? LM_VIEWS_HELDOUT : LM_VIEWS_TRAINING;
    lm_status st =
        co_judge_files(a.original, a.models, a.n_models, &a.views, (int)a.size, kind, run, &a);
    return st ? co_cli_fail(CMD, st) : 0;
}
