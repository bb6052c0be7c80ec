/* coordinator/cli/main.c — the `lumesh` program: dispatches to one subcommand per file (cli_*.c).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "coordinator/cli/cli_args.h"

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = {
    {"optimize", co_cli_optimize, "improve a coarse mesh so its images match the original's"},
    {"simplify", co_cli_simplify,
     "make a coarse mesh (QEM, vertex clustering, image-driven or shard collapses)"},
    {"lod", co_cli_lod, "a chain of levels of detail, each simplified and optimised"},
    {"pm-extract", co_cli_pm_extract, "the mesh of any vertex count from a progressive mesh"},
    {"energy", co_cli_energy, "image energy of a model against the original (JSON)"},
    {"compare", co_cli_compare, "judge models against the original; picture grid, close-up"},
    {"report", co_cli_report, "a quality report as a self-contained HTML page"},
    {"render", co_cli_render, "write view images (and difference images) as PNG"},
    {"devices", co_cli_devices, "list rendering devices (EGL, USB accelerators)"},
    {"gen-frog", co_cli_gen_frog, "generate the procedural frog-style demo model"},
    {"demo", co_cli_demo,
     "the frog generated, simplified, optimised; images and the quality report"},
    {"bench", co_cli_bench, "benchmarks (bench eval: ΔE evaluations per second)"},
    {"workers", co_cli_workers, "how a running coordinator's workers stand"},
    {"keygen", co_cli_keygen, "CURVE keys for a coordinator and its workers"},
};

static void usage(FILE *fp)
{
    fprintf(fp, "usage: lumesh COMMAND [ARGS...]   (lumesh COMMAND --help for details)\n\n"
                "Image-driven mesh optimization (Lindstrom & Turk 2001).\n\ncommands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(fp, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(fp,
            "\nEnvironment: LUMESH_LOG=error|warn|info|debug sets the log level (default warn).\n");
}

static void set_log_level_from_env(void)
{
    const char *lvl = getenv("LUMESH_LOG");
    if (!lvl)
        return;
    static const char *const names[] = {"error", "warn", "info", "debug"};
    for (int i = 0; i < 4; i++)
        if (strcmp(lvl, names[i]) == 0)
            lm_log_set_level((lm_log_level)i);
}

int main(int argc, char **argv)
{
    set_log_level_from_env();
    if (argc < 2) {
        usage(stderr);
        return 1;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("lumesh 0.1.0\n");
        return 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(argv[1], commands[i].name) == 0) {
            co_cli_reset_getopt();
            return commands[i].run(argc - 1, argv + 1);
        }
    }
    fprintf(stderr, "lumesh: unknown command '%s' (try lumesh --help)\n", argv[1]);
    return 1;
}
