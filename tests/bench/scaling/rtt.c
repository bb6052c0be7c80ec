/* tests/bench/scaling/rtt.c — this machine's round trips: one worker process answers small
 * requests over its link (the socketpair local mode uses) and again over the pool's ZeroMQ ipc
 * socket (as workers that connect by address talk), and two processes bounce 8 bytes over a plain
 * Unix socket with blocking calls: the least a transport that sleeps between messages pays here
 * (the floor; the link goes under it by spinning and through its shared-memory lane). The link is
 * timed a second time with coordinator and worker on one core: the difference is what waking a
 * sleeping processor costs (on a VM, most of a round trip). */
#define _GNU_SOURCE
#include <sched.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "coordinator/pool/pool.h"
#include "scaling.h"

/* Round trip of a small request to one local worker process, in µs: over its link (a socketpair,
 * proto/stream.h) as local mode runs, or with socket_only over the pool's ZeroMQ ipc socket, as
 * a worker that connects by address talks. */
lm_status sc_measure_rtt(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                         const lm_view_set *vs, int socket_only, double *us)
{
    co_pool *pool = NULL;
    lm_views *v = NULL;
    co_pool_options po = {
        .local_workers = 1, .device = o->device, .quiet = 1, .socket_only = socket_only};
    lm_status st = co_pool_create(&po, &pool);
    if (st == LM_OK)
        st = co_pool_wait(pool, 1, 60);
    co_views_desc d = {.kind = CO_VIEWS_REMOTE,
                       .original = orig,
                       .views = vs,
                       .mesh = coarse,
                       .materials = coarse->materials,
                       .n_materials = coarse->n_materials,
                       .pool = pool};
    if (st == LM_OK)
        st = co_views_create(&d, &v);
    lm_patch none; /* an empty patch: a whole Evaluate round trip, next to no rendering */
    lm_patch_init(&none);
    int64_t delta;
    if (st == LM_OK) /* warm */
        st = v->ops->evaluate(v, &none, 1, &delta);
    double t0 = sc_wall();
    const int reps = 1000;
    for (int i = 0; i < reps && st == LM_OK; i++)
        st = v->ops->evaluate(v, &none, 1, &delta);
    *us = 1e6 * (sc_wall() - t0) / reps;
    lm_patch_free(&none);
    lm_views_destroy(v);
    co_pool_destroy(pool);
    return st;
}

/* The link's round trip with this process, and so the worker it starts, on the first core it
 * may use (then given back all of them); 0 where affinity cannot be set. */
lm_status sc_measure_rtt_one_core(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                                  const lm_view_set *vs, double *us)
{
    cpu_set_t all, one;
    *us = 0;
    if (sched_getaffinity(0, sizeof all, &all) != 0)
        return LM_OK;
    CPU_ZERO(&one);
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, &all)) {
            CPU_SET(c, &one);
            break;
        }
    if (sched_setaffinity(0, sizeof one, &one) != 0)
        return LM_OK;
    lm_status st = sc_measure_rtt(o, orig, coarse, vs, 0, us);
    sched_setaffinity(0, sizeof all, &all);
    return st;
}

/* Round trip of 8 bytes between this process and a child over a Unix socket pair, in µs: no
 * library, no I/O thread, two wake-ups per trip. */
lm_status sc_measure_floor_rtt(double *us)
{
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM, 0, sv) != 0)
        return lm_fail(LM_E_IO, "cannot make a socket pair");
    const int reps = 2000;
    char b[8] = {0};
    pid_t pid = fork();
    if (pid == 0) {
        close(sv[0]);
        for (int i = 0; i < reps; i++)
            if (read(sv[1], b, sizeof b) != (ssize_t)sizeof b ||
                write(sv[1], b, sizeof b) != (ssize_t)sizeof b)
                _exit(1);
        _exit(0);
    }
    close(sv[1]);
    int ok = pid > 0;
    double t0 = sc_wall();
    for (int i = 0; i < reps && ok; i++)
        ok = write(sv[0], b, sizeof b) == (ssize_t)sizeof b &&
             read(sv[0], b, sizeof b) == (ssize_t)sizeof b;
    *us = 1e6 * (sc_wall() - t0) / reps;
    close(sv[0]);
    int status = 0;
    if (pid > 0)
        waitpid(pid, &status, 0);
    return ok && WIFEXITED(status) && WEXITSTATUS(status) == 0
               ? LM_OK
               : lm_fail(LM_E_IO, "the socket-pair round trip failed");
}
