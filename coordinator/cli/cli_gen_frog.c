/* coordinator/cli/cli_gen_frog.c — `lumesh gen-frog -o OUT [--tris N] [--seed S]`: write the
 * procedural frog-style demo model (common/frog.h) with its texture, atomically. */
#include <stdio.h>
#include <time.h>

#include "common/folders.h"
#include "common/io/mesh_io.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/frog/frog.h"

#define CMD "gen-frog"

typedef struct frog_args {
    const char *output;
    uint32_t tris;
    uint64_t seed;
} frog_args;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: lumesh gen-frog -o OUT [--tris N] [--seed S]\n"
            "Writes a procedural frog-style model: body, four legs and two eyes as seven separate\n"
            "closed parts that interpenetrate, with UV charts and a generated 1024x1024 texture.\n"
            "OUT is .obj (with .mtl and the texture as PNG beside it), .ply or .glb.\n"
            "  -o, --output OUT   the file to write (atomically; missing folders are created)\n"
            "  -t, --tris N       triangles, about (default 20000; %u to %u)\n"
            "  -s, --seed S       varies the spots, stripes and small shape details (default 1)\n"
            "  -h, --help         this text\n",
            CO_FROG_MIN_TRIS, CO_FROG_MAX_TRIS);
}

static const co_cli_spec spec = {CMD, usage, 0, 0, NULL, NULL, 1};

static int parse(int argc, char **argv, frog_args *a)
{
    const co_opt opts[] = {CO_OPT_OUTPUT_NEEDED(&a->output, "missing -o OUT (see --help)"),
                           CO_OPT_U32("tris", 't', &a->tris, CO_FROG_MIN_TRIS, CO_FROG_MAX_TRIS),
                           CO_OPT_U64("seed", 's', &a->seed, 0, UINT64_MAX)};
    return co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int co_cli_gen_frog(int argc, char **argv)
{
    frog_args a = {.tris = 20000, .seed = 1};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    lm_mesh *m = NULL;
    double t0 = now_s();
    lm_status s = co_frog_generate(a.tris, a.seed, &m);
    double t1 = now_s();
    if (!s)
        s = lm_make_parent_folders(a.output);
    if (!s)
        s = lm_mesh_save(a.output, m);
    double t2 = now_s();
    if (!s)
        printf("lumesh gen-frog: %u vertices / %u triangles, %u parts, seed %llu (generate %.2f s, "
               "write %.2f s) -> %s\n",
               m->live_verts, m->live_tris, lm_mesh_count_components(m), (unsigned long long)a.seed,
               t1 - t0, t2 - t1, a.output);
    lm_mesh_destroy(m);
    return s ? co_cli_fail(CMD, s) : 0;
}
