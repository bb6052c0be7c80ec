/* common/mesh_io_isolate.c — runs a model reader in a child process, for the formats whose assimp
 * reader is not fully guarded (FBX, COLLADA): assimp 5.2 aborts on some malformed FBX files
 * (ai_assert) and can crash or exhaust memory on others; one that loops forever is stopped after
 * LM_IO_ISOLATED_CPU_SECONDS of CPU. The child (fork) loads the model and
 * writes it as GLB to a private temporary folder; the parent reads that back through the guarded
 * glTF path. A crash, an abort or the OOM killer in the child becomes a
 * one-line error, and the caller's process, its GL contexts and its work are untouched. The child
 * touches no GL state and leaves with _exit (no atexit handlers, no stdio flush of the parent's
 * buffers). */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common/mesh_io_internal.h"

/* CPU seconds a reader process may use: far beyond any real model (a 2M-triangle OBJ loads in
 * 6 s here), short of a stuck job. */
#define LM_IO_ISOLATED_CPU_SECONDS 900

int lm_io_isolated_format(const char *ext)
{
    return !strcmp(ext, "fbx") || !strcmp(ext, "dae");
}

/* In the child: load, save as GLB, report status and message on fd; never returns. A fault
 * kills the child by default action, whatever handlers the parent installed (test harnesses,
 * sanitizers would otherwise catch it and run on as a copy of the parent). */
static void child_run(lm_io_loader load, void *ctx, const char *glb, int fd)
{
    const int faults[] = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGXCPU};
    for (size_t i = 0; i < sizeof faults / sizeof faults[0]; i++)
        signal(faults[i], SIG_DFL);
    /* a reader that loops forever is killed (SIGXCPU) and reported like a crash */
    struct rlimit cpu = {LM_IO_ISOLATED_CPU_SECONDS, LM_IO_ISOLATED_CPU_SECONDS};
    setrlimit(RLIMIT_CPU, &cpu);
    lm_mesh *m = NULL;
    lm_status st = load(ctx, &m);
    if (st == LM_OK)
        st = lm_mesh_save(glb, m);
    char msg[512];
    snprintf(msg, sizeof msg, "%s", st == LM_OK ? "" : lm_last_error());
    int32_t code = (int32_t)st;
    ssize_t w = write(fd, &code, sizeof code);
    if (w == (ssize_t)sizeof code)
        w = write(fd, msg, strlen(msg));
    (void)w;
    _exit(0);
}

/* In the parent: the child's status and message, then its exit. */
static lm_status parent_wait(pid_t pid, int fd, const char *name)
{
    int32_t code = -1;
    char msg[512] = "";
    ssize_t got = read(fd, &code, sizeof code);
    size_t n = 0;
    for (ssize_t r; got == (ssize_t)sizeof code && n + 1 < sizeof msg &&
                    (r = read(fd, msg + n, sizeof msg - 1 - n)) > 0;)
        n += (size_t)r;
    msg[n] = '\0';
    int ws = 0;
    while (waitpid(pid, &ws, 0) < 0 && errno == EINTR)
        ;
    if (WIFSIGNALED(ws))
        return lm_fail(LM_E_FORMAT,
                       "%s: the model reader crashed on this file (%s): it is malformed", name,
                       strsignal(WTERMSIG(ws)));
    if (got != (ssize_t)sizeof code)
        return lm_fail(LM_E_FORMAT, "%s: the model reader failed on this file (exit status %d)",
                       name, WIFEXITED(ws) ? WEXITSTATUS(ws) : -1);
    if (code < 0 || code >= LM_E_COUNT_)
        return lm_fail(LM_E_INTERNAL, "%s: the model reader process sent status %d", name, code);
    if (code != LM_OK)
        return lm_fail((lm_status)code, "%s", msg);
    return LM_OK;
}

lm_status lm_io_load_isolated(lm_io_loader load, void *ctx, const char *name,
                              const lm_load_options *opts, lm_mesh **out)
{
    const char *tmp = getenv("TMPDIR");
    char dir[512], glb[600];
    snprintf(dir, sizeof dir, "%s/lumesh-load-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(dir))
        return lm_fail(LM_E_IO, "cannot create a temporary folder in %s: %s",
                       tmp && *tmp ? tmp : "/tmp", strerror(errno));
    snprintf(glb, sizeof glb, "%s/model.glb", dir);
    int fds[2];
    lm_status st = LM_OK;
    if (pipe(fds) != 0)
        st = lm_fail(LM_E_IO, "cannot create a pipe: %s", strerror(errno));
    pid_t pid = st == LM_OK ? fork() : -1;
    if (st == LM_OK && pid < 0) {
        st = lm_fail(LM_E_IO, "cannot start a model reader process: %s", strerror(errno));
        close(fds[0]);
        close(fds[1]);
    }
    if (pid == 0) {
        close(fds[0]);
        child_run(load, ctx, glb, fds[1]);
    }
    if (st == LM_OK) {
        close(fds[1]);
        st = parent_wait(pid, fds[0], name);
        close(fds[0]);
    }
    if (st == LM_OK && (st = lm_mesh_load(glb, opts, out)) != LM_OK) {
        char msg[400];
        snprintf(msg, sizeof msg, "%s", lm_last_error());
        st = lm_fail(st, "%s: reading back the converted model: %s", name, msg);
    }
    unlink(glb);
    rmdir(dir);
    return st;
}
