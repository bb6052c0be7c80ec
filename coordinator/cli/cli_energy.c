/* coordinator/cli/cli_energy.c — `lumesh energy ORIGINAL MODEL [--views N] [--size S] [--heldout]
 * [--device D]`: the image energy E = Σ (Ŷ - Y)² of MODEL against ORIGINAL over views framed by
 * the original's bounding sphere, printed as JSON (total, per view, mean squared error, the
 * silhouette coverage, and the renderer that made every image). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>

#include "common/mesh_io.h"
#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/job/progress.h"
#include "coordinator/quality/compare.h"
#include "coordinator/quality/view_setup.h"

#define CMD "energy"

typedef struct energy_args {
    const char *original, *model, *device;
    uint32_t views, size;
    int heldout;
} energy_args;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: lumesh energy ORIGINAL MODEL [--views N] [--size S] [--heldout] [--device D]\n"
            "Prints as JSON the image energy of MODEL against ORIGINAL: the sum over views and\n"
            "pixels of the squared difference of 8-bit luminance (total, per_view, mse), and\n"
            "the silhouette coverage: pixels where the original shows a surface (original_px),\n"
            "where MODEL shows background there instead (missing_px: holes, cracks) and where\n"
            "MODEL covers the original's background (extra_px), and the missing pixels well\n"
            "inside the original's silhouette (cracks_px: holes and cracks between parts, not a\n"
            "thinner outline; 2 pixels from its background at 256, more for larger views).\n"
            "  --views N     views around the original (default %u; 12 icosahedron, 20\n"
            "                dodecahedron, others a spherical Fibonacci set)\n"
            "  --size S      image side in pixels (default %d)\n"
            "  --heldout     the 24 held-out views instead (the paper's evaluation protocol)\n"
            "  --device D    auto (default), cpu, egl:N or host\n"
            "  -h, --help    this text\n",
            LM_DEFAULT_VIEWS, LM_DEFAULT_VIEW_SIZE);
}

static int parse_option(int c, char **argv, energy_args *a)
{
    switch (c) {
    case 'v':
        return co_arg_views(CMD, optarg, &a->views) ? 1 : -1;
    case 's':
        return co_arg_size(CMD, optarg, &a->size) ? 1 : -1;
    case 'H':
        a->heldout = 1;
        return -1;
    case 'd':
        a->device = optarg;
        return -1;
    case 'h':
        usage(stdout);
        return 0;
    default:
        return co_cli_bad_option(CMD, c, argv);
    }
}

static int parse(int argc, char **argv, energy_args *a)
{
    static const struct option opts[] = {
        {"views", required_argument, NULL, 'v'}, {"size", required_argument, NULL, 's'},
        {"heldout", no_argument, NULL, 'H'},     {"device", required_argument, NULL, 'd'},
        {"help", no_argument, NULL, 'h'},        {NULL, 0, NULL, 0}};
    int c, rc;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":h", opts, NULL)) != -1)
        if ((rc = parse_option(c, argv, a)) >= 0)
            return rc;
    if (optind + 2 > argc)
        return co_cli_usage_error(CMD, "expects ORIGINAL and MODEL (see --help)");
    if (optind + 2 < argc)
        return co_cli_usage_error(CMD, "unexpected argument '%s' (see --help)", argv[optind + 2]);
    a->original = argv[optind];
    a->model = argv[optind + 1];
    return -1;
}

static void print_json(const energy_args *a, const lm_view_set *vs, int64_t total,
                       const int64_t *per, const co_coverage *cov, const char *renderer)
{
    int size = vs->views[0].width;
    double pixels = (double)vs->count * size * size;
    printf("{\"total\": %lld, \"per_view\": [", (long long)total);
    for (uint32_t h = 0; h < vs->count; h++)
        printf("%s%lld", h ? ", " : "", (long long)per[h]);
    printf("], \"mse\": %.6f, \"views\": %u, \"size\": %d, \"heldout\": %s, \"coverage\": ",
           (double)total / pixels, vs->count, size, a->heldout ? "true" : "false");
    co_coverage_print_json(stdout, cov);
    printf(", \"renderer\": ");
    co_json_string(stdout, renderer);
    printf("}\n");
}

int co_cli_energy(int argc, char **argv)
{
    energy_args a = {.views = LM_DEFAULT_VIEWS, .size = LM_DEFAULT_VIEW_SIZE, .device = "auto"};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    lm_mesh *orig = NULL, *model = NULL;
    lm_view_set *vs = NULL;
    int64_t total = 0, per[LM_MAX_VIEWS];
    co_coverage cov;
    char renderer[128] = "";
    lm_status st = lm_mesh_load(a.original, NULL, &orig);
    if (st == LM_OK)
        st = lm_mesh_load(a.model, NULL, &model);
    if (st == LM_OK)
        st = co_view_set_around(orig, a.views, (int)a.size, a.heldout, &vs);
    const lm_mesh *const models[1] = {model};
    if (st == LM_OK)
        st = co_compare_energies(orig, vs, a.device, models, 1, &total, per, &cov, renderer);
    if (st == LM_OK)
        print_json(&a, vs, total, per, &cov, renderer);
    free(vs);
    lm_mesh_destroy(orig);
    lm_mesh_destroy(model);
    return st ? co_cli_fail(CMD, st) : 0;
}
