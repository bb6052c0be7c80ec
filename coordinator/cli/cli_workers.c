/* coordinator/cli/cli_workers.c — `lumesh workers --connect ADDR [--keys DIR] [--json]`: how a
 * running coordinator's pool stands (coordinator/pool/status.h). */
#include <stdio.h>

#include "common/view.h"
#include "coordinator/cli/cli_args.h"
#include "coordinator/job/progress.h"
#include "coordinator/pool/status.h"

#define CMD "workers"

static void usage(FILE *f)
{
    fputs("usage: lumesh workers --connect ADDR [--keys DIR] [--json]\n"
          "Asks the coordinator listening at ADDR (lumesh optimize --listen ADDR) how its pool\n"
          "stands: each worker's id, host, pid, device, views, evaluations, busy share, when it\n"
          "was last heard, and whether it is lost. With --keys, connects like a worker of that\n"
          "key folder.\n",
          f);
}

static void print_json(const Lumesh__StatusResult *r)
{
    printf("{\"endpoint\": ");
    co_json_string(stdout, r->endpoint);
    printf(", \"renderer_id\": ");
    co_json_string(stdout, r->renderer_id);
    printf(", \"job_evals\": %llu, \"workers\": [", (unsigned long long)r->job_evals);
    for (size_t i = 0; i < r->n_workers; i++) {
        const Lumesh__WorkerStatus *w = r->workers[i];
        printf("%s{\"id\": %u, \"host\": ", i ? ", " : "", w->id);
        co_json_string(stdout, w->host);
        printf(", \"pid\": %u, \"device\": ", w->pid);
        co_json_string(stdout, w->device);
        printf(", \"views\": [%u, %u], \"views_stride\": %u, \"evals\": %llu, \"busy_s\": %.3f, "
               "\"joined_s\": %.1f, \"last_heard_s\": %.2f, \"lost\": %s, \"in_job\": %s}",
               w->first, w->count, w->stride ? w->stride : 1, (unsigned long long)w->evals,
               w->busy_s, w->joined_s, w->last_heard_s, w->lost ? "true" : "false",
               w->in_job ? "true" : "false");
    }
    printf("]}\n");
}

static void print_table(const Lumesh__StatusResult *r)
{
    printf("pool at %s, renderer %s, %llu evaluations so far\n", r->endpoint, r->renderer_id,
           (unsigned long long)r->job_evals);
    printf("  %3s  %-20s %7s  %-8s %-9s %9s %6s %7s  %s\n", "ID", "HOST", "PID", "DEVICE", "VIEWS",
           "EVALS", "BUSY", "HEARD", "STATE");
    for (size_t i = 0; i < r->n_workers; i++) {
        const Lumesh__WorkerStatus *w = r->workers[i];
        char views[48];
        lm_view_deal_text((lm_view_deal){w->first, w->count, w->stride}, views, sizeof views);
        double busy = w->joined_s > 0 ? 100.0 * w->busy_s / w->joined_s : 0.0;
        printf("  %3u  %-20.20s %7u  %-8.8s %-9s %9llu %5.0f%% %6.1fs  %s\n", w->id, w->host,
               w->pid, w->device, views, (unsigned long long)w->evals, busy, w->last_heard_s,
               w->lost     ? "lost"
               : w->in_job ? "serving"
                           : "idle");
    }
}

static const co_cli_spec spec = {CMD, usage, 0, -1, NULL, NULL, 0};

int co_cli_workers(int argc, char **argv)
{
    const char *addr = NULL, *keys = NULL;
    int json = 0;
    const co_opt opts[] = {{CO_OPT_ROW("connect", 0, CO_OPT_KIND_STR, const char *, &addr),
                            .needed = "missing --connect ADDR (see --help)"},
                           CO_OPT_STR("keys", 0, &keys),
                           CO_OPT_FLAG("json", 0, &json)};
    int rc = co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
    if (rc >= 0)
        return rc;
    lm_wire_in in;
    lm_status st = co_pool_status_query(addr, keys, 3.0, &in);
    if (st != LM_OK)
        return co_cli_fail(CMD, st);
    if (json)
        print_json(in.msg->status_result);
    else
        print_table(in.msg->status_result);
    lm_wire_in_free(&in);
    return 0;
}
