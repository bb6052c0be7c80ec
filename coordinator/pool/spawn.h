/* coordinator/pool/spawn.h — lumesh-worker processes started by the coordinator (local mode):
 * found beside the lumesh program (or by LUMESH_WORKER, or on PATH), connected to the pool's
 * endpoint (their messages over a socketpair of their own, proto/stream.h), told to exit when
 * their job ends (--once) and to die with the coordinator
 * (--parent PID: the worker sets PR_SET_PDEATHSIG and checks its parent), rendering single-threaded
 * (LP_NUM_THREADS=0 unless the user set it). Ownership: co_spawn_stop_all signals, waits for and
 * forgets every process it started. */
#ifndef LM_COORDINATOR_POOL_SPAWN_H
#define LM_COORDINATOR_POOL_SPAWN_H

#include <stdint.h>
#include <sys/types.h>

#include "common/error.h"

typedef struct co_spawned {
    pid_t *pids;
    uint32_t n, cap;
} co_spawned;

/* The worker program: `path` if given, else $LUMESH_WORKER, else lumesh-worker beside this
 * program (or in ../worker/ of a build tree), else "lumesh-worker" from PATH. buf >= 4096. */
const char *co_spawn_find_worker(const char *path, char *buf);

/* What a worker is started with: the pool's endpoint (its heartbeats go there), --device
 * (NULL: auto), --keys (NULL: none) and, when link_fd >= 0, the socketpair end that carries its
 * messages (proto/stream.h), given to it as descriptor 3 with the routing id link_id, and with it
 * shm_fd >= 0, the link's shared-memory lane (proto/ring.h), given as descriptor 4. */
typedef struct co_spawn_args {
    const char *endpoint, *device, *keys;
    int link_fd;
    const char *link_id;
    int spin_us; /* with link_fd: its --spin-us (0 = none given) */
    int shm_fd;  /* with link_fd: its --link-shm (-1 = none), never descriptor 3 or 4 */
} co_spawn_args;

/* Start one worker; its pid in *pid. The caller keeps (and closes) link_fd and shm_fd. */
lm_status co_spawn_worker(co_spawned *s, const char *program, const co_spawn_args *a, pid_t *pid);

/* Reap the ones that exited: returns how many, their pids in exited[] (up to cap). */
uint32_t co_spawn_reap(co_spawned *s, pid_t *exited, uint32_t cap);

/* SIGTERM, up to 2 s of waiting, then SIGKILL for what is left; all reaped. */
void co_spawn_stop_all(co_spawned *s);

#endif
