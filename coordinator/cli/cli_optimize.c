/* coordinator/cli/cli_optimize.c — `lumesh optimize`: flags → co_job_options → co_job_run, and
 * with --report DIR the quality report of the result (the coarse start saved beside it). */
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/folders.h"
#include "common/io/mesh_io.h"
#include "common/optimizer/optimizer_tuning.h"
#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/geometric/run.h"
#include "coordinator/job/bake.h"
#include "coordinator/job/job.h"
#include "coordinator/job/job_log.h"
#include "coordinator/job/progress.h"
#include "coordinator/pool/pool.h"
#include "coordinator/quality/report.h"

static const char co_optimize_help[] =
    "usage: lumesh optimize ORIGINAL -o OUT [--initial COARSE | [--start image|qem|adaptive]\n"
    "                       [--target-verts N]] [--views 30] [--size 208] [--evals N]\n"
    "                       [--time SECONDS] [--seed S]\n"
    "                       [--checkpoint FILE [--checkpoint-every N|Ns]] [--resume FILE]\n"
    "                       [--attrs pos,normal,uv,color] [--device D] [--json] [--report DIR]\n"
    "                       [--workers N] [--listen tcp://ADDR:PORT] [--renderer ID]\n"
    "                       [--edges-in-flight K [--lanes shared|isolated|remote]] [--keys DIR]\n"
    "                       [--edges-per-iteration P] [--audit-lanes P,R|0]\n"
    "                       [--save-initial FILE]\n"
    "                       [--surface-weight W | --surface-share S] [--regrid-every N]\n"
    "                       [--energy image|geometric|image+geometric] [--c-rep C]\n"
    "                       [--geo-improvements LIST] [--geo-start-multiple K]\n"
    "                       [--validate-every K [--validate-views N] [--validate-patience P]]\n"
    "                       [--quality draft|good|best] [--view-schedule fixed|grow|extend]\n"
    "                       [--bake normal,color [--bake-size N] [--bake-every N]]\n"
    "\n"
    "Improve a coarse mesh so that its rendered images match the original's from many viewpoints\n"
    "(Lindstrom & Turk 2001): vertex positions and attributes by downhill simplex, connectivity "
    "by\n"
    "edge swaps, collapses and vertex teleports. The same inputs and seed give a byte-identical\n"
    "output, also after a --resume.\n"
    "\n"
    "  ORIGINAL                the detailed model (OBJ+MTL, PLY, OFF, STL, glTF 2.0/GLB, FBX, "
    "DAE)\n"
    "  -o, --output OUT        where to write the result (.obj with .mtl and textures, .ply, "
    ".glb);\n"
    "                          written atomically\n"
    "  --initial COARSE        start from this coarse mesh instead of simplifying the original\n"
    "  --start METHOD          how the original is simplified to the start: image (default: QEM\n"
    "                          to 10x the target, then the edge collapses that change the images\n"
    "                          least, with the geometric term below; on the job's workers, for\n"
    "                          about as long as 100,000 evaluations; the better result on every\n"
    "                          model measured), qem (quadric error only: seconds, the paper's\n"
    "                          start) or adaptive (Park, Lee & Lee's shape-adaptive\n"
    "                          simplification, sharp edges kept; lumesh simplify --method\n"
    "                          adaptive). Part of the job, like the seed\n"
    "  --save-initial FILE     also write the coarse mesh the optimisation starts from (after\n"
    "                          its preparation) to FILE\n"
    "  --target-verts N        vertices of the coarse mesh (default: 1%% of the original's\n"
    "                          vertices, at least %u)\n"
    "  --views N               number of viewpoints around the original (default %u);\n"
    "                          upper or upper:N: on the hemisphere above it (+Y up, for assets\n"
    "                          on the ground; --report's held-out views mirrored into it)\n"
    "  --views-from FILE       the cameras of a JSON file instead: [{\"position\": [x,y,z],\n"
    "                          \"target\": [x,y,z], \"up\": [x,y,z], \"fov\": degrees}, ...],\n"
    "                          or the perspective cameras of a .gltf or .glb file\n"
    "  --cull-unseen           remove from the output the triangles no view sees (the\n"
    "                          views rendered 4x larger by the exact CPU rasteriser; for\n"
    "                          --views upper or --views-from: what those cameras never see)\n"
    "  --size PIXELS           side of each square view image (default %d)\n"
    "  --evals N               budget of energy evaluations, counted from the start of the job\n"
    "                          (default %llu)\n"
    "  --time SECONDS          also stop after this much wall-clock time (default: no limit)\n"
    "  --quality Q             a preset of --evals, --views, --size and --view-schedule (flags\n"
    "                          given win over it). Wall time for the CGAL bunny at 1%% (378\n"
    "                          vertices, the image start, --workers 0) on one 2-core machine\n"
    "                          shared with other jobs; on 16 workers tests/bench/bench_scaling\n"
    "                          predicts the optimisation loop x3.6 faster with 30 views of\n"
    "                          208x208, x7.7 with 68 of 260x260 (best's last stage):\n"
    "                            draft  %llu evaluations, %u views of %dx%d, fixed: 63 s\n"
    "                            good   %llu evaluations, %u views of %dx%d, fixed: 126-147 s\n"
    "                                   (the defaults: the same output as no --quality)\n"
    "                            best   %llu evaluations, %u views of %dx%d, grow: 133-322 s\n"
    "                                   (unseen-view energy of the bunny, duck, fandisk, %% of\n"
    "                                   the start, seeds 1 and 2: 89.1, 75.9, 66.3 and 90.5,\n"
    "                                   84.7, 61.1 against good's 93.0, 78.9, 64.8 and 93.9,\n"
    "                                   85.0, 62.1; coordinator/OPTIMIZER.md)\n"
    "  --view-schedule S       fixed (default: the views above all along) or grow: %u stages\n"
    "                          from 0, 1/%u, 2/%u of --evals (with --time alone: of the default\n"
    "                          budget), each new views of the same distribution, 1.5x as many\n"
    "                          and 1.12x as large as the last (30 of 208x208, 45 of 233x233, 68\n"
    "                          of 260x260): more pixels for more compute; the geometric term\n"
    "                          grows with the pixels, keeping its share of the energy. Part of\n"
    "                          the job, like the seed (a --resume must give the same --evals).\n"
    "                          extend: the views above up to %u evaluations, then %u stages\n"
    "                          at %u, %u, %u, %u evaluations whatever --evals\n"
    "                          (45 of 233x233, 68 of 260x260, then 1.5x as many of 260x260\n"
    "                          each stage): a run with a larger --evals passes through the\n"
    "                          states of one with a smaller one, and --resume with a larger\n"
    "                          --evals continues it. Pair it with --validate-every to keep the\n"
    "                          best mesh on views it never fits\n"
    "  --seed S                random seed (default 1)\n"
    "  --checkpoint FILE       write checkpoints (atomically) to FILE at iteration boundaries,\n"
    "                          and when the run stops\n"
    "  --checkpoint-every N|Ns every N evaluations, or every N seconds with an 's' suffix\n"
    "                          (default every %.0f seconds)\n"
    "  --resume FILE           continue from a checkpoint written with the same original and\n"
    "                          options (a larger --evals extends a finished run); checkpoints\n"
    "                          then go on to FILE unless --checkpoint is given\n"
    "  --attrs LIST            attributes to optimise besides positions, from pos,normal,uv,color\n"
    "                          (default: uv if the original has a texture, color if it has vertex\n"
    "                          colours); normals not listed are derived from the geometry\n"
    "  --surface-weight W      weight of a geometric term that keeps the mesh on the original's\n"
    "                          surface where the views cannot place it (default: from\n"
    "                          --surface-share; 0 = none, the paper's energy; see\n"
    "                          coordinator/OPTIMIZER.md). Part of the job, like the seed\n"
    "  --surface-share S       the geometric term with the weight that makes it S times the image\n"
    "                          energy of QEM's mesh at the target, or of the --initial mesh\n"
    "                          (default %g with --start image, whose collapses are weighed with\n"
    "                          it too; %g with --start qem or --initial; 0 = none, the paper's\n"
    "                          energy; ignored with --surface-weight). Part of the job, like the\n"
    "                          seed\n"
    "  --regrid-every N        every N evaluations (default %llu; 0 = never) shift each view's\n"
    "                          picture by its own offset of under a pixel, drawn from the seed,\n"
    "                          and render its targets again: edges are not fitted to one set of\n"
    "                          pixel centres, so the energy shown predicts unseen views. Progress\n"
    "                          stays relative to the start across grids (a chain of ratios).\n"
    "                          Part of the job, like the seed\n"
    "  --energy E              image (default: the above), geometric (Hoppe et al. 1993 mesh\n"
    "                          optimization: E = E_dist + E_rep + E_spring over points sampled\n"
    "                          from ORIGINAL's surface; no rendering, for when fidelity to the\n"
    "                          surface matters more than looks: scans, CAD, collision meshes;\n"
    "                          starts as --geo-start-multiple says; see\n"
    "                          coordinator/geometric/GEOMETRIC.md) or image+geometric\n"
    "                          (the geometric result as the start of the image optimizer, as\n"
    "                          with --initial). With geometric only -o, --target-verts, --seed,\n"
    "                          --json, --save-initial and the three options below apply;\n"
    "                          --checkpoint and --resume are refused with geometric and\n"
    "                          image+geometric (the geometric part is not checkpointed)\n"
    "  --c-rep C               the representation constant c_rep (> 0; default %g; distances in\n"
    "                          bounding-box diagonals, E_dist as if 10,000 points): a vertex is\n"
    "                          kept when it lowers E_dist + E_spring by more than C.\n"
    "                          --target-verts N is a floor no move crosses; while the mesh has\n"
    "                          more than N vertices after the spring schedule, c_rep doubles and\n"
    "                          the moves run again, so C is where that ramp begins (smaller: a\n"
    "                          more careful order of collapses, slower)\n"
    "  --geo-improvements L    Ozdal & Gudukbay's improvements to the moves, a comma list of\n"
    "                          collapse-only (no swaps or splits), stored (later passes try only\n"
    "                          the edges whose last collapse's change of E, re-weighed, says it\n"
    "                          now pays), deferred (edges near a kept collapse wait for the\n"
    "                          next pass); or all (default) or none (Hoppe's original moves)\n"
    "  --geo-start-multiple K  the geometric method starts from ORIGINAL itself (Hoppe's start)\n"
    "                          when it has at most K times the target's vertices, else from QEM\n"
    "                          at K times (default %u; 1: QEM's mesh at the target, refined:\n"
    "                          best measured on the CAD part fandisk, 2 on the scans; with 1 the\n"
    "                          result may have a few vertices fewer than N, as QEM's may)\n"
    "  --validate-every K      every K evaluations (default %llu; 0 = never) render the mesh on\n"
    "                          validation views the optimizer never fits (the job's views turned\n"
    "                          by a rotation drawn from the seed: about the centre for the\n"
    "                          sphere, about +Y for upper, each camera by up to 15 degrees about\n"
    "                          +Y for --views-from), keep the best mesh on them, and write it as\n"
    "                          the output: more evaluations never end worse on them. Progress\n"
    "                          shows their energy and the best. Part of the job, like the seed\n"
    "  --validate-views N      validation views (default: as many as --views)\n"
    "  --validate-patience P   after P checks without a new best, fit new training views of the\n"
    "                          same distribution (turned by another rotation; default %u =\n"
    "                          never: measured worse, see coordinator/OPTIMIZER.md). Part of the\n"
    "                          job, like the seed\n"
    "  --device D              rendering device: auto (GPU if any, else cpu), cpu, host, egl:N\n"
    "                          (default auto; see lumesh devices); local workers use it too\n"
    "  --workers N             render in N lumesh-worker processes on this machine, each owning\n"
    "                          some of the views (default: one per core; 0 = in this process);\n"
    "                          the output is the same for any N\n"
    "  --listen ADDR           also take workers that connect to ADDR (tcp://HOST:PORT), started\n"
    "                          anywhere with `lumesh-worker --connect tcp://HOST:PORT`; with\n"
    "                          --listen alone no local worker is started and the job waits,\n"
    "                          saying so, until one connects\n"
    "  --edges-in-flight K     optimise K edges at once, their evaluations in one batch (more\n"
    "                          work per round trip to the workers; default %u, the paper's\n"
    "                          order; at most %u). Part of the job: it changes the output (a\n"
    "                          --resume must give the same K), the number of workers never does\n"
    "  --lanes MODE            how those K edges see each other: shared (default: each sees the\n"
    "                          others' statistics, clock and collapse queue as they go) or\n"
    "                          isolated (each sees only the group's start and its own moves,\n"
    "                          merged in order afterwards). Part of the job, like K; remote:\n"
    "                          isolated lanes, each run whole on a worker that serves every view\n"
    "                          (needs K >= 2 and workers): the same output as isolated\n"
    "  --edges-per-iteration P edges planned per iteration (default %u, at most %u): the\n"
    "                          groups of K edges in flight are taken from each plan, so a larger\n"
    "                          plan gives --lanes remote more work between plans. Part of the\n"
    "                          job, like K (a --resume must give the same P)\n"
    "  --audit-lanes P,R       --lanes remote: lanes run again by a second worker and the results\n"
    "                          compared: every lane of a worker until P of its results agreed\n"
    "                          with another's, then 1 lane in R (default %u,%u; 0 = off). A\n"
    "                          mismatch goes to a third worker; the odd one is fenced. Two\n"
    "                          workers that disagree with none to arbitrate stop the run. Never\n"
    "                          changes the output\n"
    "  --keys DIR              CURVE keys (lumesh keygen): workers' connections encrypted and\n"
    "                          authenticated, only keys in DIR/workers.allow admitted; needed to\n"
    "                          --listen beyond this machine\n"
    "  --renderer ID           accept only workers of this renderer id (lumesh-worker --self-test\n"
    "                          prints it); default: the first worker's. A job never mixes\n"
    "                          renderers: workers of another one are refused with the reason\n"
    "  --json                  newline-delimited JSON progress records and a final summary on\n"
    "                          stdout instead of the human progress line on stderr\n"
    "  --bake KINDS            then bake maps of ORIGINAL onto the result, KINDS one or both\n"
    "                          of normal, color (comma-separated, e.g. normal,color):\n"
    "                          normal, a tangent-space normal map written as OUT's name\n"
    "                          without its extension + _normal.png (GLB: normalTexture with\n"
    "                          TANGENT; OBJ: an MTL norm line); color, the original's base\n"
    "                          colour (texture x factor x vertex colour) where the same line\n"
    "                          meets it, written as + _color.png and made the materials'\n"
    "                          texture (GLB: baseColorTexture, factor RGB 1; OBJ: map_Kd).\n"
    "                          Through the result's texture coordinates where they lie in\n"
    "                          [0,1] and do not overlap, else an atlas that replaces them:\n"
    "                          charts of near-planar triangles packed with gutters (one\n"
    "                          triangle a cell where they do not pack; without color, the\n"
    "                          result's colour textures resampled into it); see\n"
    "                          coordinator/cli/COMMANDS.md\n"
    "  --bake-size N           side of the baked map in texels (default %u, %u to %u)\n"
    "  --bake-every N          maps in the loop: also bake them onto the current mesh every N\n"
    "                          evaluations (from the first) and render the current mesh with\n"
    "                          them, so that the geometry is optimised with the maps on\n"
    "                          (default: bake once, after optimising). In the loop the maps go\n"
    "                          through a per-triangle atlas keyed by triangle id (a triangle a\n"
    "                          move changes keeps its chart until the next bake), so uv is not\n"
    "                          optimised; the output is baked as --bake says, from the final\n"
    "                          mesh. Any --workers; excludes --checkpoint, --resume,\n"
    "                          --validate-every and --lanes remote. Part of the job, like the\n"
    "                          seed\n"
    "  --report DIR            then write the quality report into DIR (created): index.html,\n"
    "                          a self-contained page comparing the result and its coarse start\n"
    "                          (saved as DIR/initial.obj) with ORIGINAL on 24 held-out views\n"
    "                          (see lumesh report --help); with --bake also the result before\n"
    "                          its maps (saved as DIR/unbaked.glb), baked against unbaked\n"
    "  -h, --help              this help\n"
    "\n"
    "SIGINT or SIGTERM end the run at the next step: the last checkpoint and the output are\n"
    "written, the workers stopped, and the exit status is 130. SIGUSR1 (a batch scheduler's\n"
    "warning before a time limit) ends it the same way but writes only the checkpoint, exit\n"
    "status 75: the same command with --resume CHECKPOINT then finishes the run with the output\n"
    "of an uninterrupted one (without --checkpoint or --resume, SIGUSR1 acts as SIGTERM).\n"
    "Exit status: 0 success, 1 bad input or flag (one line on stderr), 2 internal failure,\n"
    "75 suspended by SIGUSR1, 130 interrupted.\n";

#define CMD "optimize"

/* Exit status of a run suspended by SIGUSR1 (EX_TEMPFAIL: try again, here with --resume). */
#define CO_EXIT_SUSPENDED 75

enum { ENERGY_IMAGE, ENERGY_GEOMETRIC, ENERGY_BOTH };

typedef struct optimize_args {
    co_job_options o;
    int energy;                   /* ENERGY_* */
    double c_rep;                 /* 0: default */
    const char *geo_improvements; /* NULL: all */
    uint32_t geo_start_multiple;  /* 0: CO_GEO_START_MULTIPLE */
    uint32_t geo_bits;
    const char *report_dir;
    unsigned bake;        /* --bake's maps (CO_BAKE_*), 0: not given */
    uint32_t bake_size;   /* 0: not given (CO_BAKE_DEFAULT_SIZE) */
    char initial[4096];   /* DIR/initial.obj */
    char unbaked[4096];   /* with --bake: DIR/unbaked.glb, the result before its maps; "": none */
    char geometric[4200]; /* image+geometric: OUT.geometric.glb, the image job's --initial */
} optimize_args;

/* "5000" = every 5000 evaluations, "30s" = every 30 seconds. */
static lm_status parse_every(const char *val, co_job_options *o)
{
    size_t n = strlen(val);
    if (n > 1 && val[n - 1] == 's') {
        char num[64];
        if (n - 1 >= sizeof num)
            return co_cli_usage_error(CMD, "--checkpoint-every: '%s' is too long", val),
                   LM_E_INVALID;
        memcpy(num, val, n - 1);
        num[n - 1] = '\0';
        return co_arg_double(CMD, "--checkpoint-every", num, 0.001, 1e9, &o->checkpoint_every_s);
    }
    return co_arg_u64(CMD, "--checkpoint-every", val, 1, UINT64_MAX / 2,
                      &o->checkpoint_every_evals);
}

static int parse_start(void *to, const char *val)
{
    co_job_options *o = to;
    if (!strcmp(val, "image"))
        o->start = CO_JOB_START_IMAGE;
    else if (!strcmp(val, "qem"))
        o->start = CO_JOB_START_QEM;
    else if (!strcmp(val, "adaptive"))
        o->start = CO_JOB_START_ADAPTIVE;
    else
        return co_cli_usage_error(CMD, "--start expects image, qem or adaptive, got '%s'", val);
    return -1;
}

static int parse_schedule(void *to, const char *val)
{
    co_job_options *o = to;
    if (co_schedule_parse(val, &o->view_schedule) != LM_OK)
        return co_cli_usage_error(CMD, "--view-schedule expects fixed, grow or extend, got '%s'",
                                  val);
    return -1;
}

static int parse_quality(void *to, const char *val)
{
    co_job_options *o = to;
    if (co_job_quality_parse(val, &o->quality) != LM_OK)
        return co_cli_usage_error(CMD, "--quality expects draft, good or best, got '%s'", val);
    return -1;
}

static int parse_lanes(void *to, const char *val)
{
    co_job_options *o = to;
    o->lanes_remote = 0;
    if (!strcmp(val, "shared"))
        o->lane_isolation = 0;
    else if (!strcmp(val, "isolated"))
        o->lane_isolation = 1;
    else if (!strcmp(val, "remote"))
        o->lane_isolation = o->lanes_remote = 1;
    else
        return co_cli_usage_error(CMD, "--lanes expects shared, isolated or remote, got '%s'", val);
    return -1;
}

static int parse_audit(void *to, const char *val)
{
    co_job_options *o = to;
    if (co_audit_parse(val, &o->audit) != LM_OK)
        return co_cli_usage_error(CMD, "%s", lm_last_error());
    o->audit_set = 1;
    return -1;
}

static int parse_energy(void *to, const char *val)
{
    int *e = to;
    if (!strcmp(val, "image"))
        *e = ENERGY_IMAGE;
    else if (!strcmp(val, "geometric"))
        *e = ENERGY_GEOMETRIC;
    else if (!strcmp(val, "image+geometric"))
        *e = ENERGY_BOTH;
    else
        return co_cli_usage_error(CMD,
                                  "--energy expects image, geometric or image+geometric, "
                                  "got '%s'",
                                  val);
    return -1;
}

static int parse_c_rep(void *to, const char *val)
{
    char *end = NULL;
    double x = strtod(val, &end);
    if (!*val || *end || !(x > 0) || !(x < 1e300))
        return co_cli_usage_error(CMD, "--c-rep expects a number above 0, got '%s'", val);
    *(double *)to = x;
    return -1;
}

static int parse_attrs(void *to, const char *val)
{
    co_job_options *o = to;
    uint32_t attrs;
    o->attrs = val;
    if (co_job_parse_attrs(val, &attrs) == LM_OK)
        return -1;
    co_cli_fail(CMD, LM_E_INVALID);
    return 1;
}

static int parse_bake(void *to, const char *val)
{
    if (co_bake_parse_kind(val, (unsigned *)to) != LM_OK)
        return co_cli_usage_error(CMD, "%s", lm_last_error());
    return -1;
}

static int parse_checkpoint_every(void *o, const char *val)
{
    return parse_every(val, o) == LM_OK ? -1 : 1;
}

static void usage(FILE *f)
{
    const co_job_preset *d = co_job_preset_of(CO_QUALITY_DRAFT),
                        *g = co_job_preset_of(CO_QUALITY_GOOD),
                        *b = co_job_preset_of(CO_QUALITY_BEST);
    fprintf(f, co_optimize_help, CO_JOB_MIN_TARGET_VERTS, CO_JOB_DEFAULT_VIEWS, CO_JOB_DEFAULT_SIZE,
            (unsigned long long)CO_JOB_DEFAULT_EVALS, (unsigned long long)d->evals, d->views,
            d->size, d->size, (unsigned long long)g->evals, g->views, g->size, g->size,
            (unsigned long long)b->evals, b->views, b->size, b->size, CO_SCHEDULE_STAGES,
            CO_SCHEDULE_STAGES, CO_SCHEDULE_STAGES, CO_SCHEDULE_EXTEND_BASE,
            CO_SCHEDULE_EXTEND_STAGES - 1, CO_SCHEDULE_EXTEND_BASE, CO_SCHEDULE_EXTEND_BASE * 2,
            CO_SCHEDULE_EXTEND_BASE * 4, CO_SCHEDULE_EXTEND_BASE * 8, CO_JOB_DEFAULT_CHECKPOINT_S,
            CO_JOB_IMAGE_START_SHARE, LM_SURFACE_SHARE,
            (unsigned long long)CO_JOB_DEFAULT_REGRID_EVERY, CO_GEO_DEFAULT_C_REP,
            CO_GEO_START_MULTIPLE, (unsigned long long)CO_JOB_DEFAULT_VALIDATE_EVERY,
            CO_JOB_DEFAULT_VALIDATE_PATIENCE, CO_JOB_DEFAULT_IN_FLIGHT, LM_MAX_EDGES_IN_FLIGHT,
            LM_DEFAULT_EDGES_PER_ITERATION, LM_MAX_EDGES_PER_ITERATION, CO_AUDIT_DEFAULT_PROBATION,
            CO_AUDIT_DEFAULT_RATE, CO_BAKE_DEFAULT_SIZE, CO_BAKE_MIN_SIZE, CO_BAKE_MAX_SIZE);
}

/* What a 0 given stands for: no geometric term (--surface-weight, --surface-share), one grid all
 * along (--regrid-every). */
static const double no_term = CO_JOB_NONE;
static const uint64_t never = CO_JOB_NONE;
static const uint32_t never_u32 = CO_JOB_NONE;

/* The rows of the optimiser's own options (o: the job's). */
#define OPT_SURFACE(n, p, hi)                                                                      \
    {                                                                                              \
        CO_OPT_ROW(n, 0, CO_OPT_KIND_DOUBLE, double, p), .dlo = 0, .dhi = (hi), .zero = &no_term   \
    }
#define OPT_REGRID(p)                                                                              \
    {                                                                                              \
        CO_OPT_ROW("regrid-every", 0, CO_OPT_KIND_U64, uint64_t, p),                               \
            .lo = 0, .hi = UINT64_MAX - 1, .zero = &never                                          \
    }

static const co_cli_spec spec = {
    CMD, usage, 1, 1, "missing ORIGINAL model (try lumesh optimize --help)", NULL, 0};

/* -1 when the options given go together, else 1 (said). */
static int check_options(optimize_args *a)
{
    const co_job_options *o = &a->o;
    if (o->initial_path && o->target_verts)
        return co_cli_usage_error(CMD, "--initial and --target-verts exclude each other");
    if (o->initial_path && o->start)
        return co_cli_usage_error(CMD, "--initial and --start exclude each other");
    if (a->energy == ENERGY_IMAGE && (a->c_rep > 0 || a->geo_improvements || a->geo_start_multiple))
        return co_cli_usage_error(CMD, "--c-rep, --geo-improvements and --geo-start-multiple need "
                                       "--energy geometric or image+geometric");
    if (a->energy != ENERGY_IMAGE && (o->checkpoint_path || o->resume_path))
        return co_cli_usage_error(CMD, "--checkpoint and --resume are not supported with "
                                       "--energy geometric or image+geometric");
    if (a->energy != ENERGY_IMAGE && (o->initial_path || o->start))
        return co_cli_usage_error(CMD, "--initial and --start exclude --energy geometric and "
                                       "image+geometric (the geometric method makes the start)");
    if (a->energy == ENERGY_GEOMETRIC && (o->validate_every || o->cull_unseen))
        return co_cli_usage_error(CMD, "--validate-every and --cull-unseen need rendering: use "
                                       "--energy image+geometric");
    if (a->energy == ENERGY_GEOMETRIC && a->report_dir)
        return co_cli_usage_error(CMD, "--report needs rendering: use --energy image+geometric "
                                       "or lumesh report on the result");
    if (a->geo_improvements && co_geo_parse_improvements(a->geo_improvements, &a->geo_bits))
        return co_cli_fail(CMD, LM_E_INVALID);
    if (!a->geo_improvements)
        a->geo_bits = CO_GEO_ALL;
    if (o->initial_output_path && a->report_dir)
        return co_cli_usage_error(CMD, "--save-initial and --report exclude each other (the "
                                       "report keeps the start as DIR/initial.obj)");
    if (a->bake_size && !a->bake)
        return co_cli_usage_error(CMD, "--bake-size needs --bake");
    if (!a->bake_size)
        a->bake_size = CO_BAKE_DEFAULT_SIZE;
    if (o->bake_every && !a->bake)
        return co_cli_usage_error(CMD, "--bake-every needs --bake");
    if (o->bake_every && a->energy == ENERGY_GEOMETRIC)
        return co_cli_usage_error(CMD, "--bake-every needs rendering: use --energy image or "
                                       "image+geometric");
    if (o->bake_every && (o->checkpoint_path || o->resume_path))
        return co_cli_usage_error(CMD, "--bake-every excludes --checkpoint and --resume (the "
                                       "maps in the loop are not checkpointed)");
    if (o->bake_every && o->validate_every && !co_job_is_none(o->validate_every))
        return co_cli_usage_error(CMD, "--bake-every excludes --validate-every (the validation "
                                       "views render without the maps)");
    if (o->bake_every && o->lanes_remote)
        return co_cli_usage_error(CMD, "--bake-every excludes --lanes remote");
    a->o.bake_kinds = a->bake;
    a->o.bake_size = a->bake_size;
    return -1;
}

/* Returns -1 to go on, 0 after --help, or the exit code of a flag error. */
static int parse_args(int argc, char **argv, optimize_args *a)
{
    co_job_options *o = &a->o;
    const co_opt opts[] = {
        CO_OPT_OUTPUT_NEEDED(&o->output_path, "missing -o OUT"),
        CO_OPT_STR("initial", 0, &o->initial_path),
        CO_OPT_U32("target-verts", 0, &o->target_verts, 4, LM_MESH_MAX_VERTS),
        CO_OPT_VIEWS(&o->views),
        CO_OPT_SIZE_INT(&o->size),
        CO_OPT_EVALS(&o->max_evals),
        CO_OPT_DOUBLE("time", &o->time_limit_s, 0.001, 1e9),
        CO_OPT_SEED(&o->seed, 1),
        CO_OPT_STR("checkpoint", 0, &o->checkpoint_path),
        CO_OPT_CALL("checkpoint-every", 0, parse_checkpoint_every, o),
        CO_OPT_STR("resume", 0, &o->resume_path),
        CO_OPT_CALL("attrs", 0, parse_attrs, o),
        CO_OPT_DEVICE(&o->device_spec),
        CO_OPT_FLAG("json", 0, &o->json),
        CO_OPT_JOB_WORKERS(&o->workers),
        CO_OPT_STR("listen", 0, &o->listen),
        CO_OPT_STR("renderer", 0, &o->renderer),
        CO_OPT_STR("report", 0, &a->report_dir),
        CO_OPT_CALL("bake", 0, parse_bake, &a->bake),
        CO_OPT_U32("bake-size", 0, &a->bake_size, CO_BAKE_MIN_SIZE, CO_BAKE_MAX_SIZE),
        {CO_OPT_ROW("bake-every", 0, CO_OPT_KIND_U64, uint64_t, &o->bake_every), .lo = 1,
         .hi = UINT64_MAX / 2},
        CO_OPT_U32("edges-in-flight", 0, &o->edges_in_flight, 1, LM_MAX_EDGES_IN_FLIGHT),
        CO_OPT_U32("edges-per-iteration", 0, &o->edges_per_iteration, 1,
                   LM_MAX_EDGES_PER_ITERATION),
        CO_OPT_CALL("lanes", 0, parse_lanes, o),
        CO_OPT_CALL("audit-lanes", 0, parse_audit, o),
        CO_OPT_STR("keys", 0, &o->keys),
        CO_OPT_STR("save-initial", 0, &o->initial_output_path),
        CO_OPT_FLAG("cull-unseen", 0, &o->cull_unseen),
        OPT_SURFACE("surface-weight", &o->surface_weight, 1e9),
        OPT_SURFACE("surface-share", &o->surface_share, 1e6),
        CO_OPT_CALL("start", 0, parse_start, o),
        OPT_REGRID(&o->regrid_every),
        CO_OPT_CALL("view-schedule", 0, parse_schedule, o),
        CO_OPT_CALL("quality", 0, parse_quality, o),
        CO_OPT_CALL("energy", 0, parse_energy, &a->energy),
        CO_OPT_CALL("c-rep", 0, parse_c_rep, &a->c_rep),
        CO_OPT_STR("geo-improvements", 0, &a->geo_improvements),
        CO_OPT_U32("geo-start-multiple", 0, &a->geo_start_multiple, 1, 1000),
        {CO_OPT_ROW("validate-every", 0, CO_OPT_KIND_U64, uint64_t, &o->validate_every), .lo = 0,
         .hi = UINT64_MAX / 2, .zero = &never},
        CO_OPT_U32("validate-views", 0, &o->validate_views, 1, LM_MAX_VIEWS),
        {CO_OPT_ROW("validate-patience", 0, CO_OPT_KIND_U32, uint32_t, &o->validate_patience),
         .lo = 0, .hi = 1000000, .zero = &never_u32},
    };
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    o->original_path = argv[optind];
    return check_options(a);
}

/* The report of the finished job: its coarse start, its output, the log gathered while it ran. */
static lm_status write_report(const optimize_args *a, const co_job_summary *s, co_run_log *log)
{
    co_job_log_finish(log, s);
    co_report_options ro = {.original = a->o.original_path,
                            .initial = a->initial,
                            .optimized = a->o.output_path,
                            .unbaked = a->unbaked[0] ? a->unbaked : NULL,
                            .log = log,
                            .device = a->o.device_spec,
                            .size = a->o.size,
                            .dir = a->report_dir,
                            .views = a->o.views};
    char page[4096];
    lm_status st = co_report_write(&ro, page, sizeof page);
    if (st == LM_OK && a->o.json) {
        fputs("{\"type\":\"report\",\"page\":", stdout);
        co_json_string(stdout, page);
        fputs("}\n", stdout);
    } else if (st == LM_OK) {
        printf("report: %s (open it in a browser)\n", page);
    }
    return st;
}

/* With --report: the folder made before any work, the coarse start saved there, the log kept. */
static lm_status prepare_report(optimize_args *a, co_run_log *log)
{
    int n = snprintf(a->initial, sizeof a->initial, "%s/initial.obj", a->report_dir);
    if (n < 0 || (size_t)n >= sizeof a->initial)
        return lm_fail(LM_E_INVALID, "--report: folder name '%s' is too long", a->report_dir);
    a->o.initial_output_path = a->initial;
    a->o.on_progress = co_job_log_progress;
    a->o.progress_ctx = log;
    return lm_make_folders(a->report_dir);
}

/* With --report and --bake: the result before its maps, kept as DIR/unbaked.glb (a GLB: its
 * textures inside it) for the report to show beside the baked one. */
static lm_status keep_unbaked(optimize_args *a)
{
    int n = snprintf(a->unbaked, sizeof a->unbaked, "%s/unbaked.glb", a->report_dir);
    if (n < 0 || (size_t)n >= sizeof a->unbaked) {
        a->unbaked[0] = 0;
        return lm_fail(LM_E_INVALID, "--report: folder name '%s' is too long", a->report_dir);
    }
    lm_mesh *m = NULL;
    lm_status st = lm_mesh_load(a->o.output_path, NULL, &m);
    if (st == LM_OK)
        st = lm_mesh_save(a->unbaked, m);
    lm_mesh_destroy(m);
    if (st != LM_OK)
        a->unbaked[0] = 0;
    return st;
}

/* With --bake: the written output's maps (job/bake.h); with --report too, the unbaked result
 * kept first. */
static lm_status bake_output(optimize_args *a)
{
    if (!a->bake)
        return LM_OK;
    lm_status st = a->report_dir ? keep_unbaked(a) : LM_OK;
    if (st != LM_OK)
        return st;
    co_bake_result r;
    st = co_bake_file(a->o.original_path, a->o.output_path, a->bake, (int)a->bake_size, &r);
    if (st == LM_OK)
        co_bake_print(&r, a->o.json);
    return st;
}

/* The geometric method (Hoppe et al. 1993) alone, or into `geo_out` as the image job's start. */
static lm_status run_geometric(const optimize_args *a, const char *geo_out)
{
    co_geo_run_options g = {.original_path = a->o.original_path,
                            .output_path = geo_out ? geo_out : a->o.output_path,
                            .initial_output_path = geo_out ? NULL : a->o.initial_output_path,
                            .target_verts = a->o.target_verts,
                            .c_rep = a->c_rep,
                            .start_multiple = a->geo_start_multiple,
                            .improvements = a->geo_bits,
                            .seed = a->o.seed,
                            .json = a->o.json,
                            .then_image = geo_out != NULL};
    co_geo_summary sum;
    return co_geo_run(&g, &sum);
}

/* image+geometric: the geometric result (written beside OUT, removed after) is the --initial. */
static int run_both(optimize_args *a)
{
    char *tmp = a->geometric; /* outlives this function: the job reads it as its --initial */
    int n = snprintf(tmp, sizeof a->geometric, "%s.geometric.glb", a->o.output_path);
    if (n < 0 || (size_t)n >= sizeof a->geometric)
        return co_cli_usage_error(CMD, "-o: '%s' is too long", a->o.output_path);
    lm_status st = run_geometric(a, tmp);
    if (st != LM_OK)
        return co_cli_fail(CMD, st);
    a->o.initial_path = tmp;
    a->o.target_verts = 0;
    return -1;
}

int co_cli_optimize(int argc, char **argv)
{
    optimize_args a = {.o = {0}};
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0)
        return rc;
    if (a.energy == ENERGY_GEOMETRIC) {
        lm_status gst = run_geometric(&a, NULL);
        if (gst == LM_OK)
            gst = bake_output(&a);
        return gst == LM_OK ? 0 : co_cli_fail(CMD, gst);
    }
    const char *both_tmp = NULL;
    if (a.energy == ENERGY_BOTH) {
        rc = run_both(&a);
        if (rc >= 0)
            return rc;
        both_tmp = a.o.initial_path;
    }
    co_run_log log;
    co_run_log_init(&log);
    co_job_summary s;
    lm_status st = a.report_dir ? prepare_report(&a, &log) : LM_OK;
    if (st == LM_OK)
        st = co_job_run(&a.o, &s);
    int suspended = st == LM_OK && strcmp(s.stop_reason, "suspended") == 0;
    if (st == LM_OK && !suspended)
        st = bake_output(&a);
    if (st == LM_OK && a.report_dir && !suspended)
        st = write_report(&a, &s, &log);
    co_run_log_free(&log);
    if (both_tmp)
        remove(both_tmp);
    if (st != LM_OK) { /* a signal before the optimisation began (the start): nothing written */
        int code = co_cli_fail(CMD, st);
        if (!co_pool_interrupted())
            return code;
        int suspend =
            co_pool_interrupt_signal() == SIGUSR1 && (a.o.checkpoint_path || a.o.resume_path);
        return suspend ? CO_EXIT_SUSPENDED : 130; /* as a suspension or interruption would */
    }
    if (suspended)
        return CO_EXIT_SUSPENDED;
    return strcmp(s.stop_reason, "interrupted") ? 0 : 130;
}
