/* coordinator/cli/cli_optimize.c — `lumesh optimize`: flags → co_job_options → co_job_run, and
 * with --report DIR the quality report of the result (the coarse start saved beside it). */
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "common/folders.h"
#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/job/job.h"
#include "coordinator/job/job_log.h"
#include "coordinator/job/progress.h"
#include "coordinator/optimizer/optimizer_tuning.h"
#include "coordinator/pool/pool.h"
#include "coordinator/quality/report.h"

static const char co_optimize_help[] =
    "usage: lumesh optimize ORIGINAL -o OUT [--initial COARSE | [--start image|qem]\n"
    "                       [--target-verts N]] [--views 30] [--size 208] [--evals N]\n"
    "                       [--time SECONDS] [--seed S]\n"
    "                       [--checkpoint FILE [--checkpoint-every N|Ns]] [--resume FILE]\n"
    "                       [--attrs pos,normal,uv,color] [--device D] [--json] [--report DIR]\n"
    "                       [--workers N] [--listen tcp://ADDR:PORT] [--renderer ID]\n"
    "                       [--edges-in-flight K] [--keys DIR] [--save-initial FILE]\n"
    "                       [--surface-weight W | --surface-share S] [--regrid-every N]\n"
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
    "                          model measured) or qem (quadric error only: seconds, the paper's\n"
    "                          start). Part of the job, like the seed\n"
    "  --save-initial FILE     also write the coarse mesh the optimisation starts from (after\n"
    "                          its preparation) to FILE\n"
    "  --target-verts N        vertices of the coarse mesh (default: 1%% of the original's\n"
    "                          vertices, at least %u)\n"
    "  --views N               number of viewpoints around the original (default %u)\n"
    "  --size PIXELS           side of each square view image (default %d)\n"
    "  --evals N               budget of energy evaluations, counted from the start of the job\n"
    "                          (default %llu)\n"
    "  --time SECONDS          also stop after this much wall-clock time (default: no limit)\n"
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
    "                          order). Part of the job: it changes the output (a --resume must\n"
    "                          give the same K), the number of workers never does\n"
    "  --keys DIR              CURVE keys (lumesh keygen): workers' connections encrypted and\n"
    "                          authenticated, only keys in DIR/workers.allow admitted; needed to\n"
    "                          --listen beyond this machine\n"
    "  --renderer ID           accept only workers of this renderer id (lumesh-worker --self-test\n"
    "                          prints it); default: the first worker's. A job never mixes\n"
    "                          renderers: workers of another one are refused with the reason\n"
    "  --json                  newline-delimited JSON progress records and a final summary on\n"
    "                          stdout instead of the human progress line on stderr\n"
    "  --report DIR            then write the quality report into DIR (created): index.html,\n"
    "                          a self-contained page comparing the result and its coarse start\n"
    "                          (saved as DIR/initial.obj) with ORIGINAL on 24 held-out views\n"
    "                          (see lumesh report --help)\n"
    "  -h, --help              this help\n"
    "\n"
    "SIGINT or SIGTERM end the run at the next step: the last checkpoint and the output are\n"
    "written, the workers stopped, and the exit status is 130. SIGUSR1 (a batch scheduler's\n"
    "warning before a time limit) ends it the same way but writes only the checkpoint, exit\n"
    "status 75: the same command with --resume CHECKPOINT then finishes the run with the output\n"
    "of an uninterrupted one (without --checkpoint or --resume, SIGUSR1 acts as SIGTERM).\n"
    "Exit status: 0 success, 1 bad input or flag (one line on stderr), 2 internal failure,\n"
    "75 suspended by SIGUSR1, 130 interrupted.\n";

enum {
    OPT_INITIAL = 256,
    OPT_TARGET,
    OPT_VIEWS,
    OPT_SIZE,
    OPT_EVALS,
    OPT_TIME,
    OPT_SEED,
    OPT_CHECKPOINT,
    OPT_CHECKPOINT_EVERY,
    OPT_RESUME,
    OPT_ATTRS,
    OPT_DEVICE,
    OPT_JSON,
    OPT_WORKERS,
    OPT_LISTEN,
    OPT_RENDERER,
    OPT_REPORT,
    OPT_IN_FLIGHT,
    OPT_KEYS,
    OPT_SAVE_INITIAL,
    OPT_SURFACE_WEIGHT,
    OPT_SURFACE_SHARE,
    OPT_START,
    OPT_REGRID,
};

static const struct option co_optimize_opts[] = {
    {"output", required_argument, NULL, 'o'},
    {"initial", required_argument, NULL, OPT_INITIAL},
    {"target-verts", required_argument, NULL, OPT_TARGET},
    {"views", required_argument, NULL, OPT_VIEWS},
    {"size", required_argument, NULL, OPT_SIZE},
    {"evals", required_argument, NULL, OPT_EVALS},
    {"time", required_argument, NULL, OPT_TIME},
    {"seed", required_argument, NULL, OPT_SEED},
    {"checkpoint", required_argument, NULL, OPT_CHECKPOINT},
    {"checkpoint-every", required_argument, NULL, OPT_CHECKPOINT_EVERY},
    {"resume", required_argument, NULL, OPT_RESUME},
    {"attrs", required_argument, NULL, OPT_ATTRS},
    {"device", required_argument, NULL, OPT_DEVICE},
    {"json", no_argument, NULL, OPT_JSON},
    {"workers", required_argument, NULL, OPT_WORKERS},
    {"listen", required_argument, NULL, OPT_LISTEN},
    {"renderer", required_argument, NULL, OPT_RENDERER},
    {"report", required_argument, NULL, OPT_REPORT},
    {"edges-in-flight", required_argument, NULL, OPT_IN_FLIGHT},
    {"keys", required_argument, NULL, OPT_KEYS},
    {"save-initial", required_argument, NULL, OPT_SAVE_INITIAL},
    {"surface-weight", required_argument, NULL, OPT_SURFACE_WEIGHT},
    {"surface-share", required_argument, NULL, OPT_SURFACE_SHARE},
    {"start", required_argument, NULL, OPT_START},
    {"regrid-every", required_argument, NULL, OPT_REGRID},
    {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
};

static const char *co_cmd = "optimize";

/* Exit status of a run suspended by SIGUSR1 (EX_TEMPFAIL: try again, here with --resume). */
#define CO_EXIT_SUSPENDED 75

typedef struct optimize_args {
    co_job_options o;
    const char *report_dir;
    char initial[4096]; /* DIR/initial.obj */
} optimize_args;

/* "5000" = every 5000 evaluations, "30s" = every 30 seconds. */
static lm_status parse_every(const char *val, co_job_options *o)
{
    size_t n = strlen(val);
    if (n > 1 && val[n - 1] == 's') {
        char num[64];
        if (n - 1 >= sizeof num)
            return co_cli_usage_error(co_cmd, "--checkpoint-every: '%s' is too long", val),
                   LM_E_INVALID;
        memcpy(num, val, n - 1);
        num[n - 1] = '\0';
        return co_arg_double(co_cmd, "--checkpoint-every", num, 0.001, 1e9, &o->checkpoint_every_s);
    }
    return co_arg_u64(co_cmd, "--checkpoint-every", val, 1, UINT64_MAX / 2,
                      &o->checkpoint_every_evals);
}

static lm_status parse_value(int c, const char *val, co_job_options *o)
{
    uint32_t views, size;
    lm_status st = LM_OK;
    switch (c) {
    case 'o':
        o->output_path = val;
        break;
    case OPT_INITIAL:
        o->initial_path = val;
        break;
    case OPT_START:
        if (!strcmp(val, "image"))
            o->start = CO_JOB_START_IMAGE;
        else if (!strcmp(val, "qem"))
            o->start = CO_JOB_START_QEM;
        else
            return co_cli_usage_error(co_cmd, "--start expects image or qem, got '%s'", val),
                   LM_E_INVALID;
        break;
    case OPT_TARGET:
        return co_arg_u32(co_cmd, "--target-verts", val, 4, LM_MESH_MAX_VERTS, &o->target_verts);
    case OPT_VIEWS:
        st = co_arg_views(co_cmd, val, &views);
        o->views = views;
        break;
    case OPT_SIZE:
        st = co_arg_size(co_cmd, val, &size);
        o->size = (int)size;
        break;
    case OPT_EVALS:
        return co_arg_u64(co_cmd, "--evals", val, 1, UINT64_MAX / 2, &o->max_evals);
    case OPT_TIME:
        return co_arg_double(co_cmd, "--time", val, 0.001, 1e9, &o->time_limit_s);
    case OPT_SEED:
        return co_arg_u64(co_cmd, "--seed", val, 1, UINT64_MAX, &o->seed);
    case OPT_CHECKPOINT:
        o->checkpoint_path = val;
        break;
    case OPT_CHECKPOINT_EVERY:
        return parse_every(val, o);
    case OPT_RESUME:
        o->resume_path = val;
        break;
    case OPT_ATTRS: {
        uint32_t attrs;
        o->attrs = val;
        if (co_job_parse_attrs(val, &attrs) != LM_OK)
            return co_cli_fail(co_cmd, LM_E_INVALID), LM_E_INVALID;
        break;
    }
    case OPT_DEVICE:
        o->device_spec = val;
        break;
    case OPT_WORKERS:
        st = co_arg_u32(co_cmd, "--workers", val, 0, 4096, &o->workers);
        if (st == LM_OK && o->workers == 0)
            o->workers = CO_JOB_IN_PROCESS;
        break;
    case OPT_LISTEN:
        o->listen = val;
        break;
    case OPT_RENDERER:
        o->renderer = val;
        break;
    case OPT_KEYS:
        o->keys = val;
        break;
    case OPT_SAVE_INITIAL:
        o->initial_output_path = val;
        break;
    case OPT_SURFACE_WEIGHT:
        st = co_arg_double(co_cmd, "--surface-weight", val, 0, 1e9, &o->surface_weight);
        if (st == LM_OK && o->surface_weight == 0)
            o->surface_weight = -1; /* 0 on the command line: no geometric term */
        break;
    case OPT_SURFACE_SHARE:
        st = co_arg_double(co_cmd, "--surface-share", val, 0, 1e6, &o->surface_share);
        if (st == LM_OK && o->surface_share == 0)
            o->surface_share = -1; /* 0 on the command line: no relative term */
        break;
    case OPT_REGRID:
        st = co_arg_u64(co_cmd, "--regrid-every", val, 0, UINT64_MAX - 1, &o->regrid_every);
        if (st == LM_OK && o->regrid_every == 0)
            o->regrid_every = CO_JOB_NEVER; /* 0 on the command line: one grid all along */
        break;
    case OPT_IN_FLIGHT:
        return co_arg_u32(co_cmd, "--edges-in-flight", val, 1, CO_MAX_EDGES_IN_FLIGHT,
                          &o->edges_in_flight);
    }
    return st;
}

/* Returns 0 to go on, -1 after --help, or the exit code of a flag error. */
static int parse_args(int argc, char **argv, optimize_args *a)
{
    co_job_options *o = &a->o;
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, ":o:h", co_optimize_opts, NULL)) != -1) {
        if (c == 'h') {
            printf(co_optimize_help, CO_JOB_MIN_TARGET_VERTS, CO_JOB_DEFAULT_VIEWS,
                   CO_JOB_DEFAULT_SIZE, (unsigned long long)CO_JOB_DEFAULT_EVALS,
                   CO_JOB_DEFAULT_CHECKPOINT_S, CO_JOB_IMAGE_START_SHARE, CO_SURFACE_SHARE,
                   (unsigned long long)CO_JOB_DEFAULT_REGRID_EVERY, CO_JOB_DEFAULT_IN_FLIGHT);
            return -1;
        }
        if (c == '?' || c == ':')
            return co_cli_bad_option(co_cmd, c, argv);
        if (c == OPT_JSON)
            o->json = 1;
        else if (c == OPT_REPORT)
            a->report_dir = optarg;
        else if (parse_value(c, optarg, o) != LM_OK)
            return 1;
    }
    if (optind >= argc)
        return co_cli_usage_error(co_cmd, "missing ORIGINAL model (try lumesh optimize --help)");
    if (argc - optind > 1)
        return co_cli_usage_error(co_cmd, "unexpected argument '%s'", argv[optind + 1]);
    o->original_path = argv[optind];
    if (!o->output_path)
        return co_cli_usage_error(co_cmd, "missing -o OUT");
    if (o->initial_path && o->target_verts)
        return co_cli_usage_error(co_cmd, "--initial and --target-verts exclude each other");
    if (o->initial_path && o->start)
        return co_cli_usage_error(co_cmd, "--initial and --start exclude each other");
    if (o->initial_output_path && a->report_dir)
        return co_cli_usage_error(co_cmd, "--save-initial and --report exclude each other (the "
                                          "report keeps the start as DIR/initial.obj)");
    return 0;
}

/* The report of the finished job: its coarse start, its output, the log gathered while it ran. */
static lm_status write_report(const optimize_args *a, const co_job_summary *s, co_run_log *log)
{
    co_job_log_finish(log, s);
    co_report_options ro = {.original = a->o.original_path,
                            .initial = a->initial,
                            .optimized = a->o.output_path,
                            .log = log,
                            .device = a->o.device_spec,
                            .size = a->o.size,
                            .dir = a->report_dir};
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

int co_cli_optimize(int argc, char **argv)
{
    optimize_args a = {.o = {0}};
    int rc = parse_args(argc, argv, &a);
    if (rc)
        return rc < 0 ? 0 : rc;
    co_run_log log;
    co_run_log_init(&log);
    co_job_summary s;
    lm_status st = a.report_dir ? prepare_report(&a, &log) : LM_OK;
    if (st == LM_OK)
        st = co_job_run(&a.o, &s);
    int suspended = st == LM_OK && strcmp(s.stop_reason, "suspended") == 0;
    if (st == LM_OK && a.report_dir && !suspended)
        st = write_report(&a, &s, &log);
    co_run_log_free(&log);
    if (st != LM_OK) { /* a signal before the optimisation began (the start): nothing written */
        int code = co_cli_fail(co_cmd, st);
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
