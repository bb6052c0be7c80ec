/* coordinator/cli/cli_simplify.c — `lumesh simplify ORIGINAL -o OUT --target-verts N
 * [--method qem|cluster|adaptive|image|shard]` (adaptive also with --tolerance E instead of
 * the target): load a model, make the coarse mesh with QEM (meshoptimizer), Rossignac–Borrel
 * vertex clustering, Park, Lee & Lee's shape-adaptive simplification, or image-driven edge
 * collapses (priced by the exact image energy, or by shards: coordinator/simplify/), write it
 * atomically, print a one-line summary. The target is
 * an upper bound: a model already small enough is written as it is (with a note), and where the
 * simplifier cannot reach the target the best mesh it reached is written with a warning (exit 0).
 * Exit 1 is kept for real errors (unreadable model, bad flag), which write nothing. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "common/folders.h"
#include "common/io/mesh_io.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/quality/cull_unseen.h"
#include "coordinator/simplify/adaptive.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/simplify/simplify_job.h"

#define CMD "simplify"

typedef struct simplify_args {
    const char *input, *output;
    uint32_t target;
    co_simplify_method method;
    double tolerance; /* --tolerance (adaptive); -1: not given */
    int image;        /* --method image or shard: coordinator/simplify */
    co_simplify_options image_opts;
} simplify_args;

static void usage(FILE *f)
{
    fputs(
        "usage: lumesh simplify ORIGINAL -o OUT --target-verts N [--method qem|cluster|image|"
        "shard]\n"
        "       lumesh simplify ORIGINAL -o OUT --method adaptive (--tolerance E | --target-verts "
        "N)\n"
        "                       [--views N] [--size S] [--device D] [--workers N]\n"
        "                       [--listen tcp://ADDR:PORT] [--keys DIR] [--renderer ID]\n"
        "                       [--presimplify M] [--reference MODEL] [--pm FILE]\n"
        "                       [--surface-share S | --surface-weight W] [--cull-unseen]\n"
        "Makes a coarse version of ORIGINAL with at most N vertices (the search aims within 5%\n"
        "of N; up to 5% above N counts as reached) and writes it to OUT (.obj with .mtl and PNG\n"
        "textures, .ply or .glb, chosen by the extension). A model that already has N vertices\n"
        "or fewer is written as it is, with a note; where the simplifier cannot get down to N\n"
        "(QEM keeps closed small parts and seams) the best mesh it reached is written, with a\n"
        "warning on stderr. Part names and materials are kept, and every part: one the\n"
        "simplifier would remove (a small open part) is kept at its smallest, and one still\n"
        "lost is named in a warning.\n"
        "  -o, --output OUT       the file to write (atomically; missing folders are made)\n"
        "  -n, --target-verts N   the most vertices wanted (below 4: as few as possible)\n"
        "  -m, --method M         qem (default): quadric edge collapses (meshoptimizer), keeps\n"
        "                         UV seams, materials and separate parts;\n"
        "                         cluster: Rossignac-Borrel vertex clustering on a grid, with\n"
        "                         double-sided faces removed (the paper's Figure 7a input);\n"
        "                         adaptive: Park, Lee & Lee's shape-adaptive simplification:\n"
        "                         edges collapsed toward the optimal length that the curvature\n"
        "                         along them allows for a tolerance; sharp edges (above 30\n"
        "                         degrees), seams, borders and corners kept; for scans and CAD\n"
        "                         parts, where the surface matters more than looks; with\n"
        "                         --target-verts it searches the tolerance and ends at exactly N\n"
        "                         (where the features allow);\n"
        "                         image: greedy edge collapses, each priced by the exact change\n"
        "                         of the image energy against the model's own images over the\n"
        "                         views (Lindstrom & Turk); crosses seams and part borders when\n"
        "                         the images allow; goes down to 4 vertices per closed part;\n"
        "                         shard: the same collapses priced by Pfeiffer's shards (the\n"
        "                         triangles a collapse changes, rendered alone, before against\n"
        "                         after: no images of the model are kept; in process only)\n"
        "  --cull-unseen          remove from OUT the triangles no view sees (--views, --size\n"
        "                         or --views-from as below, also with qem and cluster; the\n"
        "                         views rendered 4x larger by the exact CPU rasteriser)\n"
        "adaptive:\n"
        "  --tolerance E          instead of --target-verts: simplify as far as the surface stays\n"
        "                         within E x the bounding-box diagonal (0 < E <= 1; checked from\n"
        "                         the removed vertices to the result and from sampled points of\n"
        "                         the result to ORIGINAL)\n"
        "image and shard:\n"
        "  --views N, --size S    the views (default 20 of 256 pixels); --views upper[:N]: on\n"
        "                         the hemisphere above the model (+Y up)\n"
        "  --views-from FILE      the cameras of a JSON file instead (as lumesh optimize)\n"
        "  --device D             auto (default), host or egl:N\n"
        "  --workers N            image: price in N lumesh-worker processes (default 0: in\n"
        "                         this process); the result is the same for any N\n"
        "  --listen ADDR          image: also take workers that connect to ADDR\n"
        "                         (tcp://HOST:PORT, `lumesh-worker --connect ADDR`); alone, it\n"
        "                         starts no local worker and waits, saying so, for one\n"
        "  --keys DIR             CURVE keys (lumesh keygen), as for lumesh optimize: needed to\n"
        "                         --listen beyond this machine\n"
        "  --renderer ID          accept only workers of this renderer id (default: the first\n"
        "                         worker's)\n"
        "  --presimplify M        QEM brings a larger model to M vertices first (default: 10 x N,\n"
        "                         when the model has more)\n"
        "  --reference MODEL      match MODEL's images instead of ORIGINAL's (simplifying a\n"
        "                         coarse mesh of MODEL further)\n"
        "  --pm FILE              also write the collapses as a progressive mesh (vertex splits\n"
        "                         from the result up to the start); lumesh pm-extract rebuilds\n"
        "                         any vertex count in that range, byte for byte as simplify\n"
        "                         stopped there would write it\n"
        "  --surface-share S      image: add to every collapse's price the geometric term of\n"
        "                         lumesh optimize (squared distance to ORIGINAL's surface, see\n"
        "                         coordinator/OPTIMIZER.md), weighted so that it is S times the\n"
        "                         image energy of QEM's mesh of N vertices (default 0: none, the\n"
        "                         paper's price); 0.1, what optimize --start image uses, keeps\n"
        "                         CAD-like models on their surface\n"
        "  --surface-weight W     the same term with this weight instead\n"
        "  -h, --help             this text\n",
        f);
}

static int parse_method(void *to, const char *val)
{
    simplify_args *a = to;
    a->image = !strcmp(val, "image") || !strcmp(val, "shard");
    a->image_opts.method = !strcmp(val, "shard") ? CO_PRICE_SHARD : CO_PRICE_IMAGE;
    if (!strcmp(val, "qem"))
        a->method = CO_SIMPLIFY_QEM;
    else if (!strcmp(val, "cluster"))
        a->method = CO_SIMPLIFY_CLUSTER;
    else if (!strcmp(val, "adaptive"))
        a->method = CO_SIMPLIFY_ADAPTIVE;
    else if (!a->image)
        return co_cli_usage_error(
            CMD, "--method expects qem, cluster, adaptive, image or shard, got '%s'", val);
    return -1;
}

/* -1 when the options given go with the method, else 1 (said). */
static int check_method(const simplify_args *a)
{
    const co_simplify_options *o = &a->image_opts;
    int workers = co_simplify_workers_given(&o->workers);
    int views = o->views.count || o->views.dist || o->size;
    if (!a->image && ((views && !o->cull_unseen) || o->device || workers || o->presimplify ||
                      o->reference_path || o->pm_path))
        return co_cli_usage_error(CMD, "--views, --size, --device, --workers, --listen, --keys, "
                                       "--renderer, --presimplify, --reference and --pm go with "
                                       "--method image or shard (--views and --size also with "
                                       "--cull-unseen)");
    if ((o->surface_share > 0 || o->surface_weight > 0) &&
        (!a->image || o->method != CO_PRICE_IMAGE))
        return co_cli_usage_error(CMD, "--surface-share and --surface-weight go with --method "
                                       "image");
    if (o->method == CO_PRICE_SHARD && workers)
        return co_cli_usage_error(CMD, "--method shard renders in this process: no --workers, "
                                       "--listen, --keys or --renderer");
    return co_cli_check_simplify_workers(CMD, &o->workers);
}

/* -1 when --target-verts and --tolerance go together as given, else 1 (said). */
static int check_target(const simplify_args *a)
{
    if (a->tolerance >= 0 && (a->image || a->method != CO_SIMPLIFY_ADAPTIVE))
        return co_cli_usage_error(CMD, "--tolerance goes with --method adaptive");
    if (a->tolerance == 0)
        return co_cli_usage_error(CMD, "--tolerance must be above 0 (a fraction of the "
                                       "bounding-box diagonal)");
    if (a->tolerance > 0 && a->target)
        return co_cli_usage_error(CMD, "give --tolerance E or --target-verts N, not both");
    if (a->tolerance < 0 && !a->target)
        return co_cli_usage_error(CMD, "missing --target-verts N (see --help)");
    return -1;
}

static const co_cli_spec spec = {CMD, usage, 1, 1, "missing ORIGINAL model (see --help)", NULL, 1};

static int parse(int argc, char **argv, simplify_args *a)
{
    co_simplify_options *o = &a->image_opts;
    const co_opt opts[] = {
        CO_OPT_OUTPUT_NEEDED(&a->output, "missing -o OUT (see --help)"),
        {CO_OPT_ROW("target-verts", 'n', CO_OPT_KIND_U32, uint32_t, &a->target), .lo = 1,
         .hi = LM_MESH_MAX_VERTS},
        CO_OPT_DOUBLE("tolerance", &a->tolerance, 0, 1),
        CO_OPT_CALL("method", 'm', parse_method, a),
        CO_OPT_VIEWS(&o->views),
        CO_OPT_SIZE_INT(&o->size),
        CO_OPT_DEVICE(&o->device),
        CO_OPT_SIMPLIFY_WORKERS(&o->workers),
        CO_OPT_U32("presimplify", 0, &o->presimplify, 4, LM_MESH_MAX_VERTS),
        CO_OPT_STR("reference", 0, &o->reference_path),
        CO_OPT_STR("pm", 0, &o->pm_path),
        CO_OPT_DOUBLE("surface-weight", &o->surface_weight, 0, 1e9),
        CO_OPT_DOUBLE("surface-share", &o->surface_share, 0, 1e9),
        CO_OPT_FLAG("cull-unseen", 0, &o->cull_unseen),
    };
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    a->input = argv[optind];
    rc = check_target(a);
    return rc >= 0 ? rc : check_method(a);
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

/* ", N unseen triangles removed" with --cull-unseen (a static buffer), else "". */
static const char *culled_note(const co_simplify_options *o, uint32_t culled)
{
    static char buf[64];
    if (!o->cull_unseen)
        return "";
    snprintf(buf, sizeof buf, ", %u unseen triangles removed", culled);
    return buf;
}

/* --method image or shard. */
static int run_image(simplify_args *a)
{
    co_simplify_options *o = &a->image_opts;
    o->input_path = a->input;
    o->output_path = a->output;
    o->target_verts = a->target;
    o->progress = isatty(2) ? CO_METER_TTY : CO_METER_NONE;
    co_simplify_summary s;
    lm_status st = co_simplify_job_run(o, &s);
    if (st)
        return co_cli_fail(CMD, st);
    const char *method = o->method == CO_PRICE_SHARD ? "shard" : "image";
    if (s.in_verts <= a->target)
        fprintf(stderr,
                "lumesh simplify: note: %s has %u vertices, at most the target %u: written as it "
                "is\n",
                a->input, s.in_verts, a->target);
    else if (s.out_verts > a->target)
        fprintf(stderr,
                "lumesh simplify: warning: target not reached: no legal collapse is left at %u "
                "vertices (closed parts stop at 4 vertices); wrote that mesh\n",
                s.out_verts);
    char qem[64] = "";
    if (s.start_verts < s.in_verts)
        snprintf(qem, sizeof qem, "QEM to %u first, ", s.start_verts);
    char geo[64] = "";
    if (s.surface_weight > 0)
        snprintf(geo, sizeof geo, ", geometric term weight %.4g", s.surface_weight);
    printf("lumesh simplify: %s %u vertices / %u triangles -> %u vertices / %u triangles, %u "
           "part%s (%s: %s%u collapses, %llu evaluations%s; load %.2f s, views %.2f s, simplify "
           "%.2f s%s) -> %s%s%s\n",
           a->input, s.in_verts, s.in_tris, s.out_verts, s.out_tris, s.out_parts,
           s.out_parts == 1 ? "" : "s", method, qem, s.stats.collapses,
           (unsigned long long)s.stats.evaluations, geo, s.load_s, s.prepare_s, s.simplify_s,
           culled_note(o, s.culled_tris), a->output, o->pm_path ? ", " : "",
           o->pm_path ? o->pm_path : "");
    return 0;
}

/* --method adaptive: by tolerance, or by target (above the model's size: an error). */
static lm_status run_adaptive(const simplify_args *a, const lm_mesh *in, co_adapt_stats *st,
                              lm_mesh **out)
{
    if (a->target > in->live_verts)
        return lm_fail(LM_E_INVALID, "--target-verts %u is above the %u vertices of %s", a->target,
                       in->live_verts, a->input);
    if (a->target && a->target == in->live_verts)
        return co_simplify(in, CO_SIMPLIFY_ADAPTIVE, a->target, out);
    lm_status s = co_simplify_adaptive(in, a->tolerance > 0 ? a->tolerance : 0,
                                       a->target && a->target < 4 ? 4 : a->target, st, out);
    if (!s && a->target && a->target < 4)
        s = lm_fail(LM_E_RANGE, "a target of %u vertices is below the minimum of 4 (best: %u)",
                    a->target, (*out)->live_verts);
    return s;
}

static void print_summary(const simplify_args *a, const lm_mesh *in, const lm_mesh *out,
                          const co_adapt_stats *st, double load_s, double simplify_s,
                          const char *culled)
{
    char how[128] = "cluster";
    if (a->method == CO_SIMPLIFY_QEM)
        snprintf(how, sizeof how, "qem");
    else if (a->method == CO_SIMPLIFY_ADAPTIVE)
        snprintf(how, sizeof how, "adaptive, tolerance %.4g of the diagonal, %u pass%s%s",
                 st->tolerance, st->runs, st->runs == 1 ? "" : "es",
                 st->soft_features ? ", features held by the tolerance alone" : "");
    printf("lumesh simplify: %s %u vertices / %u triangles -> %u vertices / %u triangles "
           "(%s, load %.2f s, simplify %.2f s%s) -> %s\n",
           a->input, in->live_verts, in->live_tris, out->live_verts, out->live_tris, how, load_s,
           simplify_s, culled, a->output);
}

int co_cli_simplify(int argc, char **argv)
{
    simplify_args a = {.method = CO_SIMPLIFY_QEM, .tolerance = -1};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    if (a.image)
        return run_image(&a);
    lm_mesh *in = NULL, *out = NULL;
    char why[512] = "";
    double t0 = now_s();
    lm_status s = lm_mesh_load(a.input, NULL, &in), reach = LM_OK;
    double t1 = now_s();
    co_adapt_stats ast = {0};
    if (!s)
        s = reach = a.method == CO_SIMPLIFY_ADAPTIVE ? run_adaptive(&a, in, &ast, &out)
                                                     : co_simplify(in, a.method, a.target, &out);
    if (s == LM_E_RANGE && out) { /* the best mesh reached: written, with a warning */
        snprintf(why, sizeof why, "%s", lm_last_error());
        s = LM_OK;
    }
    double t2 = now_s();
    uint32_t culled = 0;
    const co_simplify_options *o = &a.image_opts;
    if (!s && o->cull_unseen)
        s = co_cull_unseen(out, in, &o->views, o->size ? o->size : LM_DEFAULT_VIEW_SIZE, &culled);
    if (!s)
        s = write_result(&a, out);
    if (!s) {
        report_target(&a, in, out, reach, why);
        co_simplify_warn_lost_parts(CMD, in, out);
        print_summary(&a, in, out, &ast, t1 - t0, t2 - t1, culled_note(o, culled));
    }
    lm_mesh_destroy(in);
    lm_mesh_destroy(out);
    return s ? co_cli_fail(CMD, s) : 0;
}
