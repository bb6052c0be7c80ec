/* coordinator/cli/cli_lod.c — `lumesh lod ORIGINAL -o OUT --levels 50%,25%,10%`: a chain of
 * levels of detail, each simplified from the level before it and then optimised against the
 * original's images (coordinator/simplify/lod.h), written one file per level (or, with --msft-lod,
 * as one GLB with MSFT_lod), with the manifest lods.json: every level's size, its distance and
 * held-out image error against the original, and its switch distance
 * (coordinator/simplify/lod_manifest.h). Prints one line per level. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/job/bake.h"
#include "coordinator/simplify/lod.h"
#include "coordinator/simplify/lod_manifest.h"

#define CMD "lod"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: lumesh lod ORIGINAL -o OUT --levels 50%%,25%%,10%%[,...] [--method "
            "image|shard|qem|adaptive]\n"
            "                  [--evals N] [--no-optimize] [--msft-lod] [--manifest PATH]\n"
            "                  [--screen-height PX] [--fov DEG] [--pixel-error P]\n"
            "                  [--views N] [--size S] [--device D] [--workers N]\n"
            "                  [--listen tcp://ADDR:PORT] [--keys DIR] [--renderer ID] [--seed S]\n"
            "                  [--cull-unseen] [--bake normal,color [--bake-size N]]\n"
            "Makes a chain of levels of detail of ORIGINAL: each level is simplified from the\n"
            "level before it (the first from ORIGINAL) and then optimised so that its images\n"
            "match ORIGINAL's (the levels nest: each is a simplification of the one before).\n"
            "Part names and materials are kept in every level.\n"
            "  -o, --output OUT     one file per level, OUT's name with .lod0, .lod1, ... before\n"
            "                       the extension (.obj/.ply/.glb), or with --msft-lod a .glb\n"
            "                       holding every level (LOD0 in the scene, the others named by\n"
            "                       its MSFT_lod extension; viewers without it show LOD0)\n"
            "  --per-level          one file per level (the default; kept for old scripts)\n"
            "  --manifest PATH      where the manifest goes (default: %s beside OUT): per\n"
            "                       level its file, vertices, triangles, parts, its symmetric\n"
            "                       surface distance to ORIGINAL (mean and max, absolute and\n"
            "                       as a fraction of ORIGINAL's bounding-box diagonal; as\n"
            "                       `lumesh energy --distance` measures the level's file), its\n"
            "                       image energy on the 24 held-out views of --views's kind\n"
            "                       (as `energy --heldout --size S`) and where it may be shown\n"
            "                       from\n"
            "  --screen-height PX, --fov DEG, --pixel-error P\n"
            "                       the screen of the switch distances: PX pixels high (default\n"
            "                       %u), DEG degrees of vertical field of view (default %g), P\n"
            "                       pixels of error allowed (default %g). An error e seen from\n"
            "                       distance d covers e * PX / (2 d tan(DEG/2)) pixels, so a\n"
            "                       level is shown from d = e * PX / (2 tan(DEG/2) P) on; e is\n"
            "                       the level's max distance to ORIGINAL, a running maximum\n"
            "                       down the chain (switch distances never decrease)\n"
            "  --levels LIST        vertex counts, as percentages of ORIGINAL's (100%% is\n"
            "                       ORIGINAL as it is) or as numbers, strictly decreasing\n"
            "  --method M           image (default): image-driven collapses; shard: Pfeiffer's\n"
            "                       shards; qem: meshoptimizer's QEM; adaptive: Park, Lee &\n"
            "                       Lee's shape-adaptive simplification (sharp edges kept)\n"
            "  --evals N            optimisation budget per level in evaluations (default %llu)\n"
            "  --no-optimize        levels as simplified\n"
            "  --views N, --size S  the views (default %u of %d pixels); --views upper[:N]: on\n"
            "                       the hemisphere above the model (+Y up)\n"
            "  --views-from FILE    the cameras of a JSON file instead (as lumesh optimize)\n"
            "  --device D           auto (default), host or egl:N\n"
            "  --workers N          render in N lumesh-worker processes (default 0: in process);\n"
            "                       the result is the same for any N\n"
            "  --listen ADDR        also take workers that connect to ADDR (tcp://HOST:PORT,\n"
            "                       `lumesh-worker --connect ADDR`); alone, it starts no local\n"
            "                       worker and waits, saying so, for one\n"
            "  --keys DIR           CURVE keys (lumesh keygen), as for lumesh optimize: needed to\n"
            "                       --listen beyond this machine\n"
            "  --renderer ID        accept only workers of this renderer id (default: the first\n"
            "                       worker's)\n"
            "  --seed S             the optimizer's seed (default %llu)\n"
            "  --cull-unseen        remove from each level's file the triangles no view sees\n"
            "                       (the chain is made whole; the manifest measures the files)\n"
            "  --bake KINDS         then bake maps of ORIGINAL onto each level's file (KINDS:\n"
            "                       normal, color or normal,color), as lumesh optimize --bake\n"
            "                       does (not with --msft-lod; the manifest measures the levels\n"
            "                       before the bake)\n"
            "  --bake-size N        side of each baked map in texels (default %u, %u to %u)\n"
            "  -h, --help           this text\n",
            CO_LOD_MANIFEST_NAME, CO_LOD_DEFAULT_SCREEN_HEIGHT, CO_LOD_DEFAULT_FOV,
            CO_LOD_DEFAULT_PIXEL_ERROR, (unsigned long long)CO_LOD_DEFAULT_EVALS, LM_DEFAULT_VIEWS,
            LM_DEFAULT_VIEW_SIZE, (unsigned long long)CO_LOD_DEFAULT_SEED, CO_BAKE_DEFAULT_SIZE,
            CO_BAKE_MIN_SIZE, CO_BAKE_MAX_SIZE);
}

static int parse_method(void *to, const char *v)
{
    co_lod_options *o = to;
    o->qem = !strcmp(v, "qem");
    o->adaptive = !strcmp(v, "adaptive");
    o->method = !strcmp(v, "shard") ? CO_PRICE_SHARD : CO_PRICE_IMAGE;
    if (!o->qem && !o->adaptive && strcmp(v, "image") && strcmp(v, "shard"))
        return co_cli_usage_error(CMD, "--method expects image, shard, qem or adaptive, got '%s'",
                                  v);
    return -1;
}

static int parse_levels(void *o, const char *v)
{
    if (co_lod_parse_levels(v, o) == LM_OK)
        return -1;
    return co_cli_usage_error(CMD, "%s", lm_last_error());
}

/* -1 when OUT's name suits one file per level (or --msft-lod), else 1 (said). */
static int check_output(const co_lod_options *o)
{
    const char *dot = strrchr(o->output_path, '.'), *slash = strrchr(o->output_path, '/');
    dot = dot && (!slash || dot > slash) ? dot : "";
    if (!o->msft_lod && strcmp(dot, ".glb") && strcmp(dot, ".obj") && strcmp(dot, ".ply"))
        return co_cli_usage_error(CMD, "-o %s: use a .obj, .ply or .glb name", o->output_path);
    if (o->msft_lod && strcmp(dot, ".glb"))
        return co_cli_usage_error(CMD, "one file of levels (--msft-lod) is a .glb: use OUT.glb, "
                                       "or one file per level (without --msft-lod)");
    return -1;
}

/* --bake KINDS [--bake-size N] (0: not given) */
typedef struct lod_bake {
    unsigned on; /* CO_BAKE_* */
    uint32_t size;
} lod_bake;

static int parse_bake(void *to, const char *val)
{
    if (co_bake_parse_kind(val, (unsigned *)to) != LM_OK)
        return co_cli_usage_error(CMD, "%s", lm_last_error());
    return -1;
}

/* -1 when --bake and --bake-size go with the rest, else 1 (said); the size's default resolved. */
static int check_bake(const co_lod_options *o, lod_bake *b)
{
    if (b->size && !b->on)
        return co_cli_usage_error(CMD, "--bake-size needs --bake");
    if (b->on && o->msft_lod)
        return co_cli_usage_error(CMD, "--bake bakes each level's own file: not with --msft-lod");
    b->size = b->size ? b->size : CO_BAKE_DEFAULT_SIZE;
    return -1;
}

static const co_cli_spec spec = {CMD, usage, 1, 1, "missing ORIGINAL model (see --help)", NULL, 1};

static int parse(int argc, char **argv, co_lod_options *o, int *per_level, lod_bake *bake)
{
    const co_opt opts[] = {
        CO_OPT_OUTPUT_NEEDED(&o->output_path, "missing -o OUT (see --help)"),
        {CO_OPT_ROW("levels", 0, CO_OPT_KIND_CALL, void, o), .call = parse_levels,
         .needed = "missing --levels LIST (see --help)"},
        CO_OPT_CALL("method", 0, parse_method, o),
        CO_OPT_EVALS(&o->evals),
        CO_OPT_FLAG("no-optimize", 0, &o->no_optimize),
        CO_OPT_FLAG("per-level", 0, per_level),
        CO_OPT_FLAG("msft-lod", 0, &o->msft_lod),
        CO_OPT_FLAG("cull-unseen", 0, &o->cull_unseen),
        CO_OPT_STR("manifest", 0, &o->manifest_path),
        CO_OPT_U32("screen-height", 0, &o->screen_height, 1, 1u << 20),
        CO_OPT_DOUBLE("fov", &o->fov_deg, 0.001, 179.999),
        CO_OPT_DOUBLE("pixel-error", &o->pixel_error, 1e-6, 1e9),
        CO_OPT_VIEWS(&o->views),
        CO_OPT_SIZE_INT(&o->size),
        CO_OPT_DEVICE(&o->device),
        CO_OPT_SIMPLIFY_WORKERS(&o->workers),
        CO_OPT_SEED(&o->seed, 1),
        CO_OPT_CALL("bake", 0, parse_bake, &bake->on),
        CO_OPT_U32("bake-size", 0, &bake->size, CO_BAKE_MIN_SIZE, CO_BAKE_MAX_SIZE),
    };
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    o->input_path = argv[optind];
    if ((rc = check_output(o)) >= 0)
        return rc;
    if (*per_level && o->msft_lod)
        return co_cli_usage_error(CMD, "--per-level and --msft-lod exclude each other");
    if ((rc = check_bake(o, bake)) >= 0)
        return rc;
    if (o->method == CO_PRICE_SHARD && co_simplify_workers_given(&o->workers))
        return co_cli_usage_error(CMD, "--method shard renders in this process: no --workers, "
                                       "--listen, --keys or --renderer");
    return co_cli_check_simplify_workers(CMD, &o->workers);
}

int co_cli_lod(int argc, char **argv)
{
    co_lod_options o = {0};
    int per_level = 0;
    lod_bake bake = {0, 0};
    int rc = parse(argc, argv, &o, &per_level, &bake);
    if (rc >= 0)
        return rc;
    o.progress = isatty(2);
    co_lod_summary s;
    lm_status st = co_lod_run(&o, &s);
    if (st)
        return co_cli_fail(CMD, st);
    printf("lumesh lod: %s %u vertices / %u triangles -> %u levels in %.1f s -> %s%s\n",
           o.input_path, s.in_verts, s.in_tris, s.n_levels, s.seconds, o.output_path,
           o.msft_lod ? " (one GLB, MSFT_lod)" : " (one file per level)");
    for (uint32_t k = 0; k < s.n_levels; k++) {
        const co_lod_level_result *r = &s.level[k];
        char energy[128];
        if (o.no_optimize)
            snprintf(energy, sizeof energy, "energy %lld (--no-optimize)",
                     (long long)r->energy_simplified);
        else
            snprintf(energy, sizeof energy, "energy %lld simplified, %lld %s",
                     (long long)r->energy_simplified, (long long)r->energy_optimized,
                     r->kept_simplified ? "kept (optimising did not lower it)" : "optimised");
        printf("  LOD%u: %u vertices / %u triangles, %u parts; %s (%llu + %llu evaluations, "
               "%.1f s)%s%s\n",
               k, r->verts, r->tris, r->parts, energy, (unsigned long long)r->simplify_evals,
               (unsigned long long)r->optimize_evals, r->seconds, r->path[0] ? " -> " : "",
               r->path);
        printf("        max distance %.4g (%.3g%% of the diagonal), held-out mse %.2f; shown from "
               "%.4g on\n",
               r->m.distance.max,
               r->m.distance.diagonal > 0 ? 100.0 * r->m.distance.max / r->m.distance.diagonal : 0,
               r->m.heldout_mse, r->m.switch_distance);
    }
    printf("  manifest -> %s\n", s.manifest);
    for (uint32_t k = 0; bake.on && k < s.n_levels; k++) {
        co_bake_result r;
        st = co_bake_file(o.input_path, s.level[k].path, bake.on, (int)bake.size, &r);
        if (st)
            return co_cli_fail(CMD, st);
        co_bake_print(&r, 0);
    }
    return 0;
}
