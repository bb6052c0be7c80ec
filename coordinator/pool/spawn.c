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
    if (s->n == s->cap) {
        uint32_t cap = s->cap ? s->cap * 2 : 8;
        pid_t *p = realloc(s->pids, cap * sizeof *p);
        if (!p)
            return lm_fail(LM_E_NOMEM, "out of memory for worker processes");
        s->pids = p;
        s->cap = cap;
    }
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

lm_status co_spawn_workers(co_spawned *s, const char *program, const char *endpoint,
                           const char *device, const char *keys, uint32_t n)
{
    char parent[32];
    snprintf(parent, sizeof parent, "%d", (int)getpid());
    char *argv[] = {(char *)program,
                    "--connect",
                    (char *)endpoint,
                    "--device",
                    (char *)(device ? device : "auto"),
                    "--once",
                    "--parent",
                    parent,
                    keys ? "--keys" : NULL,
                    (char *)keys,
                    NULL};
    char **env = worker_env();
    if (!env)
        return lm_fail(LM_E_NOMEM, "out of memory starting workers");
    lm_status st = LM_OK;
    fflush(NULL);
    for (uint32_t i = 0; i < n && st == LM_OK; i++) {
        pid_t pid;
        int rc = posix_spawnp(&pid, program, NULL, NULL, argv, env);
        if (rc != 0)
            st = lm_fail(LM_E_INVALID, "cannot start the worker program '%s': %s", program,
                         strerror(rc));
        else
            st = remember(s, pid);
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
