/* coordinator/cli/cli_report.c — `lumesh report ORIGINAL OPTIMIZED [--initial COARSE] [--log
 * RUN.jsonl] -o DIR [--size S] [--device D] [--views upper | --views-from FILE]`: the quality
 * report of an optimised model (see coordinator/quality/report.h), written into DIR; prints the
 * page's path. `lumesh report ORIGINAL --lods lods.json -o DIR`: the same page for the levels
 * of a `lumesh lod` set, side by side. */
#include <getopt.h>
#include <stdio.h>

#include "coordinator/cli/cli_args.h"
#include "coordinator/quality/report.h"

#define CMD "report"

typedef struct report_args {
    co_report_options o;
    const char *log;
    uint32_t size;
} report_args;

static void usage(FILE *f)
{
    fputs("usage: lumesh report ORIGINAL OPTIMIZED [--initial COARSE] [--log RUN.jsonl] -o DIR\n"
          "                     [--size S] [--device D] [--views upper | --views-from FILE]\n"
          "       lumesh report ORIGINAL --lods lods.json -o DIR [--size S] [--device D]\n"
          "                     [--views upper | --views-from FILE]\n"
          "Writes DIR/index.html, a self-contained page (images embedded, plots inline, no\n"
          "scripts or network) comparing OPTIMIZED (and the COARSE mesh it started from) with\n"
          "ORIGINAL on the 24 held-out views no optimisation uses: a contact sheet (original |\n"
          "initial | optimized | difference), a close-up of the worst cracks where there are\n"
          "any, a table (held-out energy and per-pixel error, silhouette and crack pixels,\n"
          "symmetric surface distance as fractions of the bounding-box diagonal, vertex,\n"
          "triangle and part counts; from the log: evaluations, wall time, renderer) and plots\n"
          "(energy against evaluations with accepted moves by kind; per-view error). The PNGs\n"
          "and SVGs are written beside it too.\n"
          "  --initial COARSE   the coarse mesh the optimisation started from\n"
          "  --log RUN.jsonl    what lumesh optimize --json printed (progress and summary)\n"
          "  --lods lods.json   the levels of `lumesh lod` instead of OPTIMIZED, side by side:\n"
          "                     sheet columns original | LOD0 | LOD1 | ... | difference of\n"
          "                     the last; the table measures every level and adds the\n"
          "                     manifest's switch distance (one file per level: not with\n"
          "                     --msft-lod)\n"
          "  -o, --output DIR   the report's folder, created with its parents\n"
          "  --size S           side of the view images (default 256, as lumesh energy)\n"
          "  --device D         auto (default), cpu, egl:N or host\n"
          "  --views upper      the held-out views of an asset optimised with --views upper: the\n"
          "                     24 mirrored into the upper hemisphere (+Y up)\n"
          "  --views-from FILE  accepted as optimize takes it; the held-out views stay the\n"
          "                     sphere's\n"
          "  -h, --help         this text\n",
          f);
}

static const co_cli_spec spec = {
    CMD,  usage, 1, 2, "expects ORIGINAL and OPTIMIZED, or ORIGINAL and --lods (see --help)",
    NULL, 1};

static int parse(int argc, char **argv, report_args *a)
{
    const co_opt opts[] = {CO_OPT_OUTPUT_NEEDED(&a->o.dir, "needs -o DIR (see --help)"),
                           CO_OPT_STR("initial", 0, &a->o.initial),
                           CO_OPT_STR("log", 0, &a->log),
                           CO_OPT_STR("lods", 0, &a->o.lods),
                           CO_OPT_SIZE(&a->size),
                           CO_OPT_DEVICE(&a->o.device),
                           CO_OPT_VIEWS(&a->o.views)};
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    if (a->o.views.dist == LM_VIEW_DIST_SPHERE && a->o.views.count)
        return co_cli_usage_error(CMD, "--views N has no use here: the report measures on the 24 "
                                       "held-out views (--views upper: the upper hemisphere's)");
    int operands = argc - optind;
    if (a->o.lods && operands == 2)
        return co_cli_usage_error(CMD, "--lods replaces OPTIMIZED: give ORIGINAL and --lods");
    if (!a->o.lods && operands == 1)
        return co_cli_usage_error(CMD, "expects ORIGINAL and OPTIMIZED, or ORIGINAL and --lods "
                                       "(see --help)");
    if (a->o.lods && (a->o.initial || a->log))
        return co_cli_usage_error(CMD, "--initial and --log describe one optimisation, not "
                                       "--lods");
    a->o.original = argv[optind];
    a->o.optimized = a->o.lods ? NULL : argv[optind + 1];
    return -1;
}

int co_cli_report(int argc, char **argv)
{
    report_args a = {.size = 256};
    int rc = parse(argc, argv, &a);
    if (rc >= 0)
        return rc;
    co_run_log log;
    co_run_log_init(&log);
    lm_status st = a.log ? co_run_log_read(a.log, &log) : LM_OK;
    char page[4096];
    a.o.size = (int)a.size;
    a.o.log = a.log ? &log : NULL;
    if (!st)
        st = co_report_write(&a.o, page, sizeof page);
    co_run_log_free(&log);
    if (st)
        return co_cli_fail(CMD, st);
    printf("lumesh report: wrote %s (open it in a browser)\n", page);
    return 0;
}
