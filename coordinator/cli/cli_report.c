/* coordinator/cli/cli_report.c — `lumesh report ORIGINAL OPTIMIZED [--initial COARSE] [--log
 * RUN.jsonl] -o DIR [--size S] [--device D]`: the quality report of an optimised model (see
 * coordinator/quality/report.h), written into DIR; prints the page's path. */
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
          "                     [--size S] [--device D]\n"
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
          "  -o, --output DIR   the report's folder, created with its parents\n"
          "  --size S           side of the view images (default 256, as lumesh energy)\n"
          "  --device D         auto (default), cpu, egl:N or host\n"
          "  -h, --help         this text\n",
          f);
}

static int parse_option(int c, char **argv, report_args *a)
{
    switch (c) {
    case 'o':
        a->o.dir = optarg;
        return -1;
    case 'i':
        a->o.initial = optarg;
        return -1;
    case 'l':
        a->log = optarg;
        return -1;
    case 's':
        return co_arg_size(CMD, optarg, &a->size) ? 1 : -1;
    case 'd':
        a->o.device = optarg;
        return -1;
    case 'h':
        usage(stdout);
        return 0;
    default:
        return co_cli_bad_option(CMD, c, argv);
    }
}

static int parse(int argc, char **argv, report_args *a)
{
    static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
                                         {"initial", required_argument, NULL, 'i'},
                                         {"log", required_argument, NULL, 'l'},
                                         {"size", required_argument, NULL, 's'},
                                         {"device", required_argument, NULL, 'd'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    int c, rc;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:h", opts, NULL)) != -1)
        if ((rc = parse_option(c, argv, a)) >= 0)
            return rc;
    if (optind + 2 > argc)
        return co_cli_usage_error(CMD, "expects ORIGINAL and OPTIMIZED (see --help)");
    if (optind + 2 < argc)
        return co_cli_usage_error(CMD, "unexpected argument '%s' (see --help)", argv[optind + 2]);
    if (!a->o.dir)
        return co_cli_usage_error(CMD, "needs -o DIR (see --help)");
    a->o.original = argv[optind];
    a->o.optimized = argv[optind + 1];
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
