/* coordinator/cli/cli_pm_extract.c — `lumesh pm-extract FILE.pm -o OUT --verts N` (or --info):
 * rebuild the mesh of N vertices from a progressive mesh written by `lumesh simplify --pm`
 * (coordinator/simplify/pm.h) and write it atomically; the bytes are those `simplify` writes when
 * it stops at N vertices. --info prints the range of counts the file holds. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "common/folders.h"
#include "common/io/mesh_io.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/job/progress.h"
#include "coordinator/simplify/pm.h"

#define CMD "pm-extract"

typedef struct pm_args {
    const char *input, *output;
    uint32_t verts; /* 0: --verts not given */
    int info;
} pm_args;

static void usage(FILE *f)
{
    fputs(
        "usage: lumesh pm-extract FILE.pm -o OUT --verts N\n"
        "       lumesh pm-extract FILE.pm --info\n"
        "Rebuilds the mesh of N vertices from a progressive mesh (the coarsest mesh and its\n"
        "vertex splits, written by lumesh simplify --method image|shard --pm FILE.pm) and writes\n"
        "it to OUT (.obj with .mtl and PNG textures, .ply or .glb): byte for byte what simplify\n"
        "writes when it stops at N vertices. N may be any count from the coarsest mesh's up to\n"
        "the mesh the image-driven collapses started from.\n"
        "  -o, --output OUT   the file to write (atomically; missing folders are made)\n"
        "  -n, --verts N      the vertex count wanted\n"
        "  --info             print the counts the file holds as JSON and write nothing\n"
        "  -h, --help         this text\n",
        f);
}

static const co_cli_spec spec = {CMD, usage, 1, 1, "missing FILE.pm (see --help)", NULL, 1};

static int parse(int argc, char **argv, pm_args *a)
{
    const co_opt opts[] = {CO_OPT_OUTPUT(&a->output),
                           CO_OPT_U32("verts", 'n', &a->verts, 1, LM_MESH_MAX_VERTS),
                           CO_OPT_FLAG("info", 0, &a->info)};
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    a->input = argv[optind];
    if (a->info)
        return -1;
    if (!a->output)
        return co_cli_usage_error(CMD, "missing -o OUT (see --help)");
    if (!a->verts) /* --verts is at least 1 */
        return co_cli_usage_error(CMD, "missing --verts N (see --help)");
    return -1;
}

static lm_status extract(const pm_args *a, co_pm *pm, uint32_t *tris)
{
    lm_mesh *m = NULL;
    lm_status st = co_pm_extract(pm, a->verts, &m);
    if (st == LM_OK)
        st = lm_make_parent_folders(a->output);
    if (st == LM_OK)
        st = lm_mesh_save(a->output, m);
    if (st == LM_OK)
        *tris = m->live_tris;
    lm_mesh_destroy(m);
    return st;
}

int co_cli_pm_extract(int argc, char **argv)
{
    pm_args a = {0};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    co_pm *pm = NULL;
    lm_status st = co_pm_read(a.input, &pm);
    if (st)
        return co_cli_fail(CMD, st);
    uint32_t lo, hi, tris = 0;
    co_pm_range(pm, &lo, &hi);
    if (a.info) {
        printf("{\"file\": ");
        co_json_string(stdout, a.input);
        printf(", \"min_verts\": %u, \"max_verts\": %u, \"splits\": %u}\n", lo, hi, hi - lo);
    } else if ((st = extract(&a, pm, &tris)) == LM_OK) {
        printf("lumesh pm-extract: %s (%u..%u vertices) -> %u vertices / %u triangles -> %s\n",
               a.input, lo, hi, a.verts, tris, a.output);
    }
    co_pm_destroy(pm);
    return st ? co_cli_fail(CMD, st) : 0;
}
