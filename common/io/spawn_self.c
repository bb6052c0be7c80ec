/* common/io/spawn_self.c — lm_spawn_self: the environment built before the fork; after it, only
 * async-signal-safe calls. /proc/self/exe is the running program's own file, even when a newer
 * build has replaced it on disk. */
#include "common/io/spawn_self.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

extern char **environ;

/* A helper that crashes must die of the signal, so that its caller reports one line: in a
 * sanitizer build, the sanitizer's own handlers would print a report and exit 1 instead. (Read
 * only by sanitizer builds.) */
#define HELPER_ASAN_OPTIONS "handle_segv=0:handle_sigbus=0:handle_sigfpe=0:handle_sigill=0"

/* "ASAN_OPTIONS=" the caller's, then HELPER_ASAN_OPTIONS (malloc'ed). */
static char *asan_options(void)
{
    const char *old = getenv("ASAN_OPTIONS");
    size_t n = strlen("ASAN_OPTIONS=") + (old ? strlen(old) + 1 : 0) + strlen(HELPER_ASAN_OPTIONS);
    char *e = malloc(n + 1);
    if (e)
        snprintf(e, n + 1, "ASAN_OPTIONS=%s%s" HELPER_ASAN_OPTIONS, old ? old : "",
                 old && *old ? ":" : "");
    return e;
}

/* The caller's environment less its LM_SPAWN_ENV_PREFIX variables and ASAN_OPTIONS, then `env`
 * and `asan` (malloc'ed array; the strings stay the caller's). */
static char **environment_with(const char *const *env, char *asan)
{
    size_t n = 0, k = 0, extra = 0;
    const size_t plen = strlen(LM_SPAWN_ENV_PREFIX);
    while (environ && environ[n])
        n++;
    while (env[extra])
        extra++;
    char **out = malloc((n + extra + 2) * sizeof *out);
    if (!out)
        return NULL;
    for (size_t i = 0; i < n; i++)
        if (strncmp(environ[i], LM_SPAWN_ENV_PREFIX, plen) != 0 &&
            strncmp(environ[i], "ASAN_OPTIONS=", 13) != 0)
            out[k++] = environ[i];
    for (size_t i = 0; i < extra; i++)
        out[k++] = (char *)env[i];
    out[k++] = asan;
    out[k] = NULL;
    return out;
}

/* In the child: stdin and stdout on the caller's descriptors, nothing else open, then exec. */
static void child_exec(char **envp, int in_fd, int out_fd)
{
    if (dup2(in_fd, 0) < 0 || dup2(out_fd, 1) < 0)
        _exit(127);
    (void)syscall(SYS_close_range, 3u, ~0u, 0u); /* sockets, pipes: none is the helper's */
    char *argv[] = {(char *)"lumesh-helper", NULL};
    execve("/proc/self/exe", argv, envp);
    _exit(127);
}

static lm_status spawn_on(const char *what, const char *const *env, int in_fd, int out_fd,
                          pid_t *pid)
{
    char *asan = asan_options();
    char **envp = asan ? environment_with(env, asan) : NULL;
    if (!envp) {
        free(asan);
        return lm_fail(LM_E_NOMEM, "out of memory starting %s", what);
    }
    pid_t p = fork();
    if (p == 0)
        child_exec(envp, in_fd, out_fd);
    int err = errno;
    free(envp);
    free(asan);
    if (p < 0)
        return lm_fail(LM_E_IO, "cannot start %s: %s", what, strerror(err));
    *pid = p;
    return LM_OK;
}

lm_status lm_spawn_self(const char *what, const char *const *env, const void *data, size_t size,
                        pid_t *pid, int *answer_fd)
{
    LM_ASSERT(what != NULL && env != NULL && pid != NULL && answer_fd != NULL);
    int in[2], res[2];
    if (pipe(in) != 0)
        return lm_fail(LM_E_IO, "cannot start %s: no pipe: %s", what, strerror(errno));
    if (pipe(res) != 0) {
        close(in[0]), close(in[1]);
        return lm_fail(LM_E_IO, "cannot start %s: no pipe: %s", what, strerror(errno));
    }
    lm_status st = spawn_on(what, env, in[0], res[1], pid);
    close(in[0]), close(res[1]);
    if (st == LM_OK && data) {
        void (*old)(int) = signal(SIGPIPE, SIG_IGN); /* a helper that died must not kill us */
        lm_fd_write_all(in[1], data, size);
        signal(SIGPIPE, old);
    }
    close(in[1]);
    if (st != LM_OK)
        close(res[0]);
    else
        *answer_fd = res[0];
    return st;
}

int lm_spawn_helper_begin(unsigned cpu_seconds)
{
    int answer = dup(1);
    dup2(2, 1);
    struct rlimit cpu = {cpu_seconds, cpu_seconds};
    setrlimit(RLIMIT_CPU, &cpu);
    return answer;
}

int lm_fd_write_all(int fd, const void *p, size_t n)
{
    for (const uint8_t *b = p; n > 0;) {
        ssize_t w = write(fd, b, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return 0;
        b += w, n -= (size_t)w;
    }
    return 1;
}

int lm_fd_read_all(int fd, void *p, size_t n)
{
    for (uint8_t *b = p; n > 0;) {
        ssize_t r = read(fd, b, n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return 0;
        b += r, n -= (size_t)r;
    }
    return 1;
}

uint8_t *lm_spawn_read_stdin(size_t max, size_t *n)
{
    size_t cap = 1 << 16;
    uint8_t *buf = malloc(cap + 1);
    *n = 0;
    for (ssize_t r; buf;) {
        if (*n == cap) {
            uint8_t *b = cap < max ? realloc(buf, cap * 2 + 1) : NULL;
            if (!b) {
                free(buf);
                return NULL;
            }
            buf = b, cap *= 2;
        }
        r = read(0, buf + *n, cap - *n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            break;
        *n += (size_t)r;
    }
    if (buf)
        buf[*n] = 0;
    return buf;
}
