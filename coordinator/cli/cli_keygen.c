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

static const co_cli_spec spec = {CMD, usage, 0, -1, NULL, NULL, 0};

int co_cli_keygen(int argc, char **argv)
{
    const char *dir = NULL;
    const co_opt opts[] = {CO_OPT_OUTPUT(&dir)};
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
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
