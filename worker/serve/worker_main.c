/* worker/serve/worker_main.c — the lumesh-worker program: device choice, --self-test, and serving
 * views to a coordinator over --connect (worker/serve/serve.h). */
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <unistd.h>

#include "common/error.h"
#include "common/log.h"
#include "worker/render/cpu/cpu_self_test.h"
#include "worker/render/cpu/cpu_views.h"
#include "worker/render/device_choice.h"
#include "worker/render/gl/gl_context.h"
#include "worker/render/gl/self_test.h"
#include "worker/render/probe.h"
#include "worker/serve/serve.h"

typedef struct worker_args {
    const char *connect;
    const char *device;
    int self_test;
    int once;
    long parent;      /* exit with this process (a coordinator that spawned us); 0 = none */
    const char *keys; /* CURVE key folder */
    const char *health_socket; /* answer health queries here */
    const char *health;        /* ask the worker answering here, and exit */
    int link_fd;               /* messages over this descriptor (-1: over --connect) */
    const char *link_id;       /* the routing id the coordinator knows the link by */
    int link_shm;              /* with link_fd: its shared-memory lane (0: none) */
    int ready;                 /* with health: exit 0 only when it is welcomed by a coordinator */
    long spin_us;              /* with link_fd: wait awake this long for the next request */
    int help;
} worker_args;

static void usage(FILE *f)
{
    fputs("usage: lumesh-worker --connect ADDR [--device auto|cpu|egl:N|host] [--once]\n"
          "                     [--keys DIR] [--health-socket ADDR]\n"
          "       lumesh-worker --health ADDR [--ready]\n"
          "       lumesh-worker --self-test [--device auto|cpu|egl:N|host]\n"
          "\n"
          "Renders views for a lumesh coordinator: `lumesh optimize --listen ADDR` waits for\n"
          "workers at ADDR; each worker that connects is given some of the job's views. A worker\n"
          "outlives its job and serves the next one at the same address (assets it has already\n"
          "received are kept); it keeps trying while no coordinator is there.\n"
          "\n"
          "  --connect ADDR   coordinator address, e.g. tcp://host:5555 (or ipc://PATH)\n"
          "  --once           exit when the first job ends\n"
          "  --keys DIR       authenticate and encrypt with the CURVE keys in DIR (worker.key and\n"
          "                   coordinator.pub, from `lumesh keygen`): the coordinator's key is\n"
          "                   checked, and the coordinator checks this worker's\n"
          "  --health-socket ADDR  answer health queries at ADDR (e.g. ipc:///tmp/w.health)\n"
          "  --health ADDR    ask the worker answering at ADDR how it stands: print its JSON\n"
          "                   state and exit 0, or exit 1 when it does not answer within 2 s\n"
          "  --ready          with --health: exit 0 only when a coordinator has welcomed it\n"
          "  --parent PID     exit when process PID (the coordinator that started this worker)\n"
          "                   does\n"
          "  --link-fd N --link-id ID  (given by a coordinator that starts its own workers)\n"
          "                   exchange messages over descriptor N, a socketpair, as ID; only\n"
          "                   heartbeats go to --connect\n"
          "  --link-shm N     with --link-fd: descriptor N is the link's shared memory, through\n"
          "                   which short messages pass without system calls\n"
          "  --spin-us N      with --link-fd: after each reply, look for the next request for up\n"
          "                   to N µs (yielding the processor to anything else that wants it)\n"
          "                   before sleeping; a wake-up can cost more than that (default 0;\n"
          "                   a coordinator gives its workers 150 when they fit on its cores)\n"
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
        {"connect", required_argument, NULL, 'c'},  {"device", required_argument, NULL, 'd'},
        {"self-test", no_argument, NULL, 's'},      {"verbose", no_argument, NULL, 'v'},
        {"once", no_argument, NULL, 'o'},           {"parent", required_argument, NULL, 'p'},
        {"keys", required_argument, NULL, 'k'},     {"health-socket", required_argument, NULL, 'H'},
        {"health", required_argument, NULL, 'q'},   {"ready", no_argument, NULL, 'r'},
        {"link-fd", required_argument, NULL, 'L'},  {"link-id", required_argument, NULL, 'I'},
        {"link-shm", required_argument, NULL, 'M'}, {"spin-us", required_argument, NULL, 'S'},
        {"help", no_argument, NULL, 'h'},           {NULL, 0, NULL, 0}};
    int c;
    opterr = 0;
    optind = 1;
    while ((c = getopt_long(argc, argv, ":c:d:svohp:k:H:q:rL:I:M:S:", opts, NULL)) != -1) {
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
        case 'o':
            a->once = 1;
            break;
        case 'k':
            a->keys = optarg;
            break;
        case 'H':
            a->health_socket = optarg;
            break;
        case 'q':
            a->health = optarg;
            break;
        case 'r':
            a->ready = 1;
            break;
        case 'L': {
            char *end;
            long fd = strtol(optarg, &end, 10);
            if (*end || fd < 0 || fd > 1023)
                return lm_fail(LM_E_INVALID, "--link-fd expects a descriptor, got '%s'", optarg);
            a->link_fd = (int)fd;
            break;
        }
        case 'I':
            a->link_id = optarg;
            break;
        case 'M': {
            char *end;
            long fd = strtol(optarg, &end, 10);
            if (!*optarg || *end || fd < 3 || fd > 1023)
                return lm_fail(LM_E_INVALID, "--link-shm expects a descriptor, got '%s'", optarg);
            a->link_shm = (int)fd;
            break;
        }
        case 'S': {
            char *end;
            a->spin_us = strtol(optarg, &end, 10);
            if (!*optarg || *end || a->spin_us < 0 || a->spin_us > WK_SERVE_MAX_SPIN_US)
                return lm_fail(LM_E_INVALID, "--spin-us expects 0 to %d, got '%s'",
                               WK_SERVE_MAX_SPIN_US, optarg);
            break;
        }
        case 'p': {
            char *end;
            a->parent = strtol(optarg, &end, 10);
            if (*end || a->parent <= 0)
                return lm_fail(LM_E_INVALID, "--parent expects a process id, got '%s'", optarg);
            break;
        }
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
    if ((a->link_fd >= 0) != (a->link_id != NULL))
        return lm_fail(LM_E_INVALID, "--link-fd and --link-id go together");
    if (a->link_shm && a->link_fd < 0)
        return lm_fail(LM_E_INVALID, "--link-shm goes with --link-fd");
    if (a->link_id && (!*a->link_id || strlen(a->link_id) > 200))
        return lm_fail(LM_E_INVALID, "--link-id expects 1 to 200 characters");
    if (!a->help && !a->connect && !a->self_test && !a->health)
        return lm_fail(LM_E_INVALID, "nothing to do: give --connect ADDR, --health ADDR or "
                                     "--self-test");
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
    char id[LM_WIRE_RENDERER_ID_CHARS + 1];
    if (st == LM_OK && (st = wk_probe_renderer(device, id, NULL)) == LM_OK)
        printf("renderer id %s (the fingerprint of a probe render: workers of one job share it)\n",
               id);
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
    worker_args a = {.device = "auto", .link_fd = -1};
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
    if (a.health) {
        char state[1024];
        int ready = 0;
        st = wk_serve_health_query(a.health, 2.0, state, sizeof state, &ready);
        if (st != LM_OK) {
            fprintf(stderr, "lumesh-worker: %s\n", lm_last_error());
            return 1;
        }
        printf("%s\n", state);
        return a.ready && !ready ? 1 : 0;
    }
    if (a.self_test) {
        st = self_test(a.device);
        if (st != LM_OK) {
            fprintf(stderr, "lumesh-worker: %s\n", lm_last_error());
            return lm_exit_code(st);
        }
    }
    if (a.connect) {
        if (a.parent) { /* die with the coordinator, and not at all if it is already gone */
            prctl(PR_SET_PDEATHSIG, SIGTERM);
            if (getppid() != (pid_t)a.parent)
                return 0;
        }
        wk_serve_options o = {.endpoint = a.connect,
                              .device = a.device,
                              .once = a.once,
                              .keys = a.keys,
                              .health = a.health_socket,
                              .link_fd = a.link_fd,
                              .link_id = a.link_id,
                              .link_shm = a.link_shm,
                              .spin_s = 1e-6 * (double)a.spin_us};
        st = wk_serve(&o);
        if (st != LM_OK) {
            fprintf(stderr, "lumesh-worker: %s\n", lm_last_error());
            return lm_exit_code(st);
        }
    }
    return 0;
}
