/* coordinator/pool/spawn.c — starting, reaping and stopping local lumesh-worker processes. */
#include "coordinator/pool/spawn.h"

#include <errno.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "common/grow.h"

const char *co_spawn_find_worker(const char *path, char *buf)
{
    if (path && *path)
        return path;
    const char *env = getenv("LUMESH_WORKER");
    if (env && *env)
        return env;
    char exe[3072];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        exe[n] = 0;
        char *slash = strrchr(exe, '/');
        if (slash) {
            *slash = 0;
            snprintf(buf, 4096, "%s/lumesh-worker", exe);
            if (access(buf, X_OK) == 0)
                return buf;
            snprintf(buf, 4096, "%s/../worker/lumesh-worker", exe);
            if (access(buf, X_OK) == 0)
                return buf;
        }
    }
    return "lumesh-worker";
}

static lm_status remember(co_spawned *s, pid_t pid)
{
    if (s->n == s->cap && !LM_GROW32(&s->pids, &s->cap, (size_t)s->n + 1, 8))
        return lm_fail(LM_E_NOMEM, "out of memory for worker processes");
    s->pids[s->n++] = pid;
    return LM_OK;
}

/* The environment of the workers: ours, with LP_NUM_THREADS=0 unless it is set (one core each). */
static char **worker_env(void)
{
    extern char **environ;
    size_t n = 0;
    while (environ[n])
        n++;
    char **env = calloc(n + 2, sizeof *env);
    if (!env)
        return NULL;
    memcpy(env, environ, n * sizeof *env);
    if (!getenv("LP_NUM_THREADS"))
        env[n++] = "LP_NUM_THREADS=0";
    return env;
}

#define WORKER_LINK_FD 3 /* the descriptor a worker finds its link on */
#define WORKER_SHM_FD 4  /* ... and its link's shared-memory lane */

/* The link's end as descriptor WORKER_LINK_FD in the child, its lane as WORKER_SHM_FD (every
 * other descriptor of ours is close-on-exec or not the child's business). */
static lm_status link_actions(posix_spawn_file_actions_t *fa, int fd, int shm_fd)
{
    int rc = posix_spawn_file_actions_init(fa);
    if (rc == 0 && fd >= 0 && fd != WORKER_LINK_FD)
        rc = posix_spawn_file_actions_adddup2(fa, fd, WORKER_LINK_FD);
    if (rc == 0 && fd >= 0 && shm_fd >= 0)
        rc = posix_spawn_file_actions_adddup2(fa, shm_fd, WORKER_SHM_FD);
    return rc == 0 ? LM_OK : lm_fail(LM_E_NOMEM, "preparing a worker's start: %s", strerror(rc));
}

lm_status co_spawn_worker(co_spawned *s, const char *program, const co_spawn_args *a, pid_t *pid)
{
    char parent[32], link_fd[16], shm_fd[16], spin[16];
    snprintf(parent, sizeof parent, "%d", (int)getpid());
    snprintf(link_fd, sizeof link_fd, "%d", WORKER_LINK_FD);
    snprintf(shm_fd, sizeof shm_fd, "%d", WORKER_SHM_FD);
    /* dup2 onto itself would keep close-on-exec; the first dup2 must not overwrite the second's */
    LM_ASSERT(a->link_fd != WORKER_LINK_FD && a->link_fd != WORKER_SHM_FD);
    LM_ASSERT(a->shm_fd < 0 || (a->shm_fd != WORKER_LINK_FD && a->shm_fd != WORKER_SHM_FD));
    char *argv[20] = {(char *)program,
                      "--connect",
                      (char *)a->endpoint,
                      "--device",
                      (char *)(a->device ? a->device : "auto"),
                      "--once",
                      "--parent",
                      parent};
    int k = 8;
    if (a->link_fd >= 0) {
        argv[k++] = "--link-fd", argv[k++] = link_fd;
        argv[k++] = "--link-id", argv[k++] = (char *)a->link_id;
        if (a->shm_fd >= 0)
            argv[k++] = "--link-shm", argv[k++] = shm_fd;
        if (a->spin_us > 0) {
            snprintf(spin, sizeof spin, "%d", a->spin_us);
            argv[k++] = "--spin-us", argv[k++] = spin;
        }
    }
    if (a->keys)
        argv[k++] = "--keys", argv[k++] = (char *)a->keys;
    argv[k] = NULL;
    char **env = worker_env();
    if (!env)
        return lm_fail(LM_E_NOMEM, "out of memory starting workers");
    posix_spawn_file_actions_t fa;
    lm_status st = link_actions(&fa, a->link_fd, a->shm_fd);
    if (st == LM_OK) {
        fflush(NULL);
        int rc = posix_spawnp(pid, program, &fa, NULL, argv, env);
        st = rc == 0 ? remember(s, *pid)
                     : lm_fail(LM_E_INVALID, "cannot start the worker program '%s': %s", program,
                               strerror(rc));
        posix_spawn_file_actions_destroy(&fa);
    }
    free(env);
    return st;
}

uint32_t co_spawn_reap(co_spawned *s, pid_t *exited, uint32_t cap)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->n;) {
        int status;
        pid_t r = waitpid(s->pids[i], &status, WNOHANG);
        if (r == s->pids[i] || (r < 0 && errno == ECHILD)) {
            if (k < cap)
                exited[k] = s->pids[i];
            k++;
            s->pids[i] = s->pids[--s->n];
        } else {
            i++;
        }
    }
    return k;
}

static void sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

void co_spawn_stop_all(co_spawned *s)
{
    for (uint32_t i = 0; i < s->n; i++)
        kill(s->pids[i], SIGTERM);
    for (int t = 0; t < 200 && s->n; t++) {
        co_spawn_reap(s, NULL, 0);
        if (s->n)
            sleep_ms(10);
    }
    for (uint32_t i = 0; i < s->n; i++)
        kill(s->pids[i], SIGKILL);
    for (uint32_t i = 0; i < s->n; i++)
        waitpid(s->pids[i], NULL, 0);
    free(s->pids);
    memset(s, 0, sizeof *s);
}
