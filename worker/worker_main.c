/* worker/worker_main.c — the lumesh-worker program: device choice, --self-test, and (later)
 * serving views to a coordinator over --connect. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "common/log.h"
#include "worker/cpu_self_test.h"
#include "worker/device_choice.h"
#include "worker/gl_context.h"
#include "worker/self_test.h"

typedef struct worker_args {
    const char *connect;
    const char *device;
    int self_test;
    int help;
} worker_args;

static void usage(FILE *f)
{
    fputs("usage: lumesh-worker --connect ADDR [--device auto|cpu|egl:N|host] [--self-test]\n"
          "\n"
          "Renders views for a lumesh coordinator.\n"
          "\n"
          "  --connect ADDR   coordinator address, e.g. tcp://host:5555\n"
          "                   (not available in this version: distribution lands later)\n"
          "  --device SPEC    rendering device: auto (first working GPU, else cpu), cpu\n"
          "                   (lumesh's exact CPU rasteriser), host (Mesa llvmpipe), egl:N\n"
          "                   (device N as listed by `lumesh devices`); default auto\n"
          "  --self-test      create a context on the device, render and check a test image,\n"
          "                   print the device and \"self-test ok\"\n"
          "  -v, --verbose    log device choice details to stderr\n"
          "  -h, --help       this text\n"
          "Environment: LUMESH_LOG=error|warn|info|debug (default warn).\n",
          f);
}

static lm_status parse_args(int argc, char **argv, worker_args *a)
{
    static const struct option opts[] = {
        {"connect", required_argument, NULL, 'c'}, {"device", required_argument, NULL, 'd'},
        {"self-test", no_argument, NULL, 's'},     {"verbose", no_argument, NULL, 'v'},
        {"help", no_argument, NULL, 'h'},          {NULL, 0, NULL, 0}};
    int c;
    opterr = 0;
    optind = 1;
    while ((c = getopt_long(argc, argv, ":c:d:svh", opts, NULL)) != -1) {
        switch (c) {
        case 'c':
            a->connect = optarg;
            break;
        case 'd':
            a->device = optarg;
            break;
        case 's':
            a->self_test = 1;
            break;
        case 'v':
            lm_log_set_level(LM_LOG_DEBUG);
            break;
        case 'h':
            a->help = 1;
            break;
        case ':':
            return lm_fail(LM_E_INVALID, "option %s needs a value", argv[optind - 1]);
        default:
            return lm_fail(LM_E_INVALID, "unknown option '%s' (see --help)", argv[optind - 1]);
        }
    }
    if (optind < argc)
        return lm_fail(LM_E_INVALID, "unexpected argument '%s' (see --help)", argv[optind]);
    if (!a->help && !a->connect && !a->self_test)
        return lm_fail(LM_E_INVALID, "nothing to do: give --connect ADDR or --self-test");
    return LM_OK;
}

static lm_status self_test(const char *device)
{
    wk_gl_context *ctx = NULL;
    int red = 0;
    lm_status st = wk_device_open(device, &ctx);
    if (st != LM_OK)
        return st;
    st = ctx ? wk_self_test_run(ctx, &red) : wk_cpu_self_test_run(&red);
    if (st == LM_OK) {
        printf("%s\n", ctx ? wk_gl_context_description(ctx) : "cpu: " WK_CPU_RASTERISER);
        printf("self-test ok (32x32 clear + triangle, %d/1024 pixels covered)\n", red);
    }
    wk_gl_context_destroy(ctx);
    return st;
}

/* LUMESH_LOG=error|warn|info|debug, as for `lumesh`. */
static void log_level_from_env(void)
{
    static const char *const names[] = {"error", "warn", "info", "debug"};
    const char *lvl = getenv("LUMESH_LOG");
    for (int i = 0; lvl && i < 4; i++) {
        if (strcmp(lvl, names[i]) == 0)
            lm_log_set_level((lm_log_level)i);
    }
}

int main(int argc, char **argv)
{
    worker_args a = {NULL, "auto", 0, 0};
    log_level_from_env();
    lm_status st = parse_args(argc, argv, &a);
    if (st != LM_OK) {
        fprintf(stderr, "lumesh-worker: %s\n", lm_last_error());
        return lm_exit_code(st);
    }
    if (a.help) {
        usage(stdout);
        return 0;
    }
    if (a.self_test) {
        st = self_test(a.device);
        if (st != LM_OK) {
            fprintf(stderr, "lumesh-worker: %s\n", lm_last_error());
            return lm_exit_code(st);
        }
    }
    if (a.connect) {
        fprintf(stderr, "lumesh-worker: --connect is not available in this version "
                        "(distribution lands with the distribution issue)\n");
        return 1;
    }
    return 0;
}
