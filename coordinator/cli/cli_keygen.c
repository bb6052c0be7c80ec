/* coordinator/cli/cli_keygen.c — `lumesh keygen -o DIR`: a CURVE key folder (proto/keys.h) for a
 * coordinator and its workers. */
#include <getopt.h>
#include <stdio.h>

#include "common/folders.h"
#include "coordinator/cli/cli_args.h"
#include "proto/keys.h"

#define CMD "keygen"

static void usage(FILE *f)
{
    fputs("usage: lumesh keygen -o DIR\n"
          "Writes CURVE keys into DIR (created; existing keys are never overwritten):\n"
          "  coordinator.key, coordinator.pub   the coordinator's pair and public key\n"
          "  worker.key, worker.pub             a worker's pair and public key\n"
          "  workers.allow                      the worker public keys the coordinator accepts\n"
          "Give the same folder to `lumesh optimize --keys DIR` and `lumesh-worker --keys DIR`\n"
          "(a worker needs worker.key and coordinator.pub only; the coordinator coordinator.key\n"
          "and workers.allow). Connections are then encrypted and authenticated both ways;\n"
          "listening beyond this machine requires them.\n",
          f);
}

int co_cli_keygen(int argc, char **argv)
{
    static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    const char *dir = NULL;
    int c;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:h", opts, NULL)) != -1) {
        if (c == 'h') {
            usage(stdout);
            return 0;
        }
        if (c != 'o')
            return co_cli_bad_option(CMD, c, argv);
        dir = optarg;
    }
    if (!dir)
        return co_cli_usage_error(CMD, "missing -o DIR (see --help)");
    if (optind < argc)
        return co_cli_usage_error(CMD, "unexpected argument '%s'", argv[optind]);
    lm_status st = lm_make_folders(dir);
    if (st == LM_OK)
        st = lm_keys_generate(dir);
    if (st != LM_OK)
        return co_cli_fail(CMD, st);
    printf("keys written to %s (coordinator.key, coordinator.pub, worker.key, worker.pub, "
           "workers.allow)\n",
           dir);
    return 0;
}
