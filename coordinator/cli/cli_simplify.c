/* coordinator/cli/cli_simplify.c — `lumesh simplify ORIGINAL -o OUT --target-verts N
 * [--method qem|cluster]`: load a model, make the coarse mesh with QEM (meshoptimizer) or
 * Rossignac–Borrel vertex clustering, write it atomically, print a one-line summary. The target is
 * an upper bound: a model already small enough is written as it is (with a note), and where the
 * simplifier cannot reach the target the best mesh it reached is written with a warning (exit 0).
 * Exit 1 is kept for real errors (unreadable model, bad flag), which write nothing. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "common/folders.h"
#include "common/mesh_io.h"
#include "common/simplify.h"
#include "coordinator/cli/cli_args.h"

#define CMD "simplify"

typedef struct simplify_args {
    const char *input, *output;
    uint32_t target;
    int have_target;
    lm_simplify_method method;
} simplify_args;

static void usage(FILE *f)
{
    fputs("usage: lumesh simplify ORIGINAL -o OUT --target-verts N [--method qem|cluster]\n"
          "Makes a coarse version of ORIGINAL with at most N vertices (the search aims within 5%\n"
          "of N; up to 5% above N counts as reached) and writes it to OUT (.obj with .mtl and PNG\n"
          "textures, .ply or .glb, chosen by the extension). A model that already has N vertices\n"
          "or fewer is written as it is, with a note; where the simplifier cannot get down to N\n"
          "(QEM keeps closed small parts and seams) the best mesh it reached is written, with a\n"
          "warning on stderr. Part names and materials are kept.\n"
          "  -o, --output OUT       the file to write (atomically; missing folders are made)\n"
          "  -n, --target-verts N   the most vertices wanted (below 4: as few as possible)\n"
          "  -m, --method M         qem (default): quadric edge collapses (meshoptimizer), keeps\n"
          "                         UV seams, materials and separate parts;\n"
          "                         cluster: Rossignac-Borrel vertex clustering on a grid, with\n"
          "                         double-sided faces removed (the paper's Figure 7a input)\n"
          "  -h, --help             this text\n",
          f);
}

static int parse_method(const char *val, lm_simplify_method *out)
{
    if (!strcmp(val, "qem"))
        *out = LM_SIMPLIFY_QEM;
    else if (!strcmp(val, "cluster"))
        *out = LM_SIMPLIFY_CLUSTER;
    else
        return co_cli_usage_error(CMD, "--method expects qem or cluster, got '%s'", val);
    return -1;
}

/* Returns -1 to go on, else the exit code. */
static int parse_option(int c, char **argv, simplify_args *a)
{
    switch (c) {
    case 'o':
        a->output = optarg;
        return -1;
    case 'n':
        a->have_target = 1;
        return co_arg_u32(CMD, "--target-verts", optarg, 1, LM_MESH_MAX_VERTS, &a->target) ? 1 : -1;
    case 'm':
        return parse_method(optarg, &a->method);
    case 'h':
        usage(stdout);
        return 0;
    default:
        return co_cli_bad_option(CMD, c, argv);
    }
}

static int parse(int argc, char **argv, simplify_args *a)
{
    static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
                                         {"target-verts", required_argument, NULL, 'n'},
                                         {"method", required_argument, NULL, 'm'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    int c, rc;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:n:m:h", opts, NULL)) != -1)
        if ((rc = parse_option(c, argv, a)) >= 0)
            return rc;
    if (optind >= argc)
        return co_cli_usage_error(CMD, "missing ORIGINAL model (see --help)");
    if (optind + 1 < argc)
        return co_cli_usage_error(CMD, "unexpected argument '%s' (see --help)", argv[optind + 1]);
    a->input = argv[optind];
    if (!a->output)
        return co_cli_usage_error(CMD, "missing -o OUT (see --help)");
    if (!a->have_target)
        return co_cli_usage_error(CMD, "missing --target-verts N (see --help)");
    return -1;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The note or warning when the result is not a simplification to the target. */
static void report_target(const simplify_args *a, const lm_mesh *in, const lm_mesh *out,
                          lm_status s, const char *why)
{
    if (in->live_verts <= a->target)
        fprintf(stderr,
                "lumesh simplify: note: %s has %u vertices, at most the target %u: written as it "
                "is\n",
                a->input, in->live_verts, a->target);
    else if (s == LM_E_RANGE)
        fprintf(stderr,
                "lumesh simplify: warning: target not reached: %s; wrote the best mesh "
                "(%u vertices)\n",
                why, out->live_verts);
}

static lm_status write_result(const simplify_args *a, const lm_mesh *out)
{
    lm_status s = lm_make_parent_folders(a->output);
    return s ? s : lm_mesh_save(a->output, out);
}

int co_cli_simplify(int argc, char **argv)
{
    simplify_args a = {.method = LM_SIMPLIFY_QEM};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    lm_mesh *in = NULL, *out = NULL;
    char why[512] = "";
    double t0 = now_s();
    lm_status s = lm_mesh_load(a.input, NULL, &in), reach = LM_OK;
    double t1 = now_s();
    if (!s)
        s = reach = lm_simplify(in, a.method, a.target, &out);
    if (s == LM_E_RANGE && out) { /* the best mesh reached: written, with a warning */
        snprintf(why, sizeof why, "%s", lm_last_error());
        s = LM_OK;
    }
    double t2 = now_s();
    if (!s)
        s = write_result(&a, out);
    if (!s) {
        report_target(&a, in, out, reach, why);
        printf("lumesh simplify: %s %u vertices / %u triangles -> %u vertices / %u triangles "
               "(%s, load %.2f s, simplify %.2f s) -> %s\n",
               a.input, in->live_verts, in->live_tris, out->live_verts, out->live_tris,
               a.method == LM_SIMPLIFY_QEM ? "qem" : "cluster", t1 - t0, t2 - t1, a.output);
    }
    lm_mesh_destroy(in);
    lm_mesh_destroy(out);
    return s ? co_cli_fail(CMD, s) : 0;
}
