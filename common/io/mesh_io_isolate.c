/* common/io/mesh_io_isolate.c — reads a model in a process of its own, for the formats whose assimp
 * reader is not proven safe under fuzzing: glTF and GLB (a 4 kB GLB makes assimp 5.2 read through
 * a null pointer: tests/data/hostile/glb-assimp-null-read.glb), FBX (assimp aborts on some files,
 * ai_assert) and COLLADA. Which format is read where, and why: common/io/INPUT_SAFETY.md.
 *
 * The reader is this program run afresh (common/io/spawn_self.h). Before main runs, the constructor
 * below sees READER_ENV, reads the model's bytes on stdin, loads them as lm_mesh_load does in
 * process (lm_io_load_bytes_here, with the caller's name, folder and options), writes the mesh as
 * GLB to the private temporary file READER_ENV names, answers {status, message} on stdout and
 * exits. The caller reads that GLB back in process: lumesh's own writer made it. A crash, an
 * abort, the OOM killer or the CPU limit in the reader is a one-line error, and the caller's heap,
 * GL contexts and work are untouched. (A fork without the exec is not enough: under ASan a forked
 * reader hung in a child that had inherited the parent's locks; see spawn_self.h.) */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common/io/mesh_io_internal.h"
#include "common/io/spawn_self.h"

/* CPU seconds a reader process may use: far beyond any real model (a 2M-triangle OBJ loads in
 * 6 s here), short of a stuck job. */
#define LM_IO_ISOLATED_CPU_SECONDS 900

#define READER_ENV LM_SPAWN_ENV_PREFIX "MODEL"           /* the GLB to write */
#define READER_NAME_ENV LM_SPAWN_ENV_PREFIX "MODEL_NAME" /* the model's name (and format) */
#define READER_DIR_ENV LM_SPAWN_ENV_PREFIX "MODEL_DIR"   /* its folder; absent for memory */
#define READER_OPTS_ENV LM_SPAWN_ENV_PREFIX "MODEL_OPTS" /* "max_tris keep_degenerate" */

int lm_io_isolated_format(const char *ext)
{
    return !strcmp(ext, "gltf") || !strcmp(ext, "glb") || !strcmp(ext, "fbx") ||
           !strcmp(ext, "dae");
}

/* ---- the reader process ---------------------------------------------------------------------- */

/* Load the bytes on stdin as the environment says and write them as GLB. */
static lm_status reader_run(const char *glb)
{
    const char *name = getenv(READER_NAME_ENV), *dir = getenv(READER_DIR_ENV),
               *o = getenv(READER_OPTS_ENV);
    lm_load_options opts = {0};
    unsigned long max_tris = 0;
    int keep = 0;
    if (!name || !o || sscanf(o, "%lu %d", &max_tris, &keep) != 2)
        return lm_fail(LM_E_INTERNAL, "model reader process started without its settings");
    opts.max_tris = (uint32_t)max_tris, opts.keep_degenerate = keep;
    size_t n = 0;
    uint8_t *data = lm_spawn_read_stdin(LM_IO_MAX_FILE_BYTES, &n);
    if (!data)
        return lm_fail(LM_E_NOMEM, "%s: out of memory reading the model", name);
    lm_mesh *m = NULL;
    lm_status st = lm_io_load_bytes_here(data, n, name, dir, &opts, &m);
    free(data);
    if (st == LM_OK)
        st = lm_mesh_save(glb, m);
    lm_mesh_destroy(m);
    return st;
}

__attribute__((constructor)) static void reader_main(void)
{
    const char *glb = getenv(READER_ENV);
    if (!glb)
        return;
    int answer = lm_spawn_helper_begin(LM_IO_ISOLATED_CPU_SECONDS);
    lm_status st = reader_run(glb);
    int32_t code = (int32_t)st;
    const char *msg = st == LM_OK ? "" : lm_last_error();
    if (answer >= 0 && lm_fd_write_all(answer, &code, sizeof code))
        lm_fd_write_all(answer, msg, strlen(msg));
    _exit(0);
}

/* ---- the caller's side ----------------------------------------------------------------------- */

/* The reader's status and message (read whole before it is reaped), then its exit. */
static lm_status reader_wait(pid_t pid, int fd, const char *name)
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
    if (WIFEXITED(ws) && WEXITSTATUS(ws) == 127)
        return lm_fail(LM_E_INTERNAL, "%s: cannot start a model reader process", name);
    if (got != (ssize_t)sizeof code)
        return lm_fail(LM_E_FORMAT, "%s: the model reader failed on this file (exit status %d)",
                       name, WIFEXITED(ws) ? WEXITSTATUS(ws) : -1);
    if (code < 0 || code >= LM_E_COUNT_)
        return lm_fail(LM_E_INTERNAL, "%s: the model reader process sent status %d", name, code);
    if (code != LM_OK)
        return lm_fail((lm_status)code, "%s", msg);
    return LM_OK;
}

/* Start the reader on `glb`, hand it the bytes, wait for its answer. */
static lm_status run_reader(const uint8_t *data, size_t size, const char *name, const char *dir,
                            const lm_load_options *opts, const char *glb)
{
    char e_glb[700], e_name[4200], e_dir[4200], e_opts[64];
    snprintf(e_glb, sizeof e_glb, READER_ENV "=%s", glb);
    snprintf(e_name, sizeof e_name, READER_NAME_ENV "=%s", name);
    snprintf(e_dir, sizeof e_dir, READER_DIR_ENV "=%s", dir ? dir : "");
    snprintf(e_opts, sizeof e_opts, READER_OPTS_ENV "=%lu %d",
             (unsigned long)(opts ? opts->max_tris : 0), opts ? opts->keep_degenerate : 0);
    const char *env[] = {e_glb, e_name, e_opts, dir ? e_dir : NULL, NULL};
    pid_t pid = 0;
    int answer = -1;
    lm_status st = lm_spawn_self("a model reader process", env, data, size, &pid, &answer);
    if (st == LM_OK) {
        st = reader_wait(pid, answer, name);
        close(answer);
    }
    return st;
}

/* The reader's GLB, read here: lumesh's own writer made it. */
static lm_status read_back(const char *glb, const char *name, const lm_load_options *opts,
                           lm_mesh **out)
{
    uint8_t *data = NULL;
    size_t size = 0;
    lm_status st = lm_io_read_file(glb, &data, &size);
    if (st == LM_OK)
        st = lm_io_load_bytes_here(data, size, "model.glb", NULL, opts, out);
    free(data);
    if (st != LM_OK) {
        char msg[400];
        snprintf(msg, sizeof msg, "%s", lm_last_error());
        st = lm_fail(st, "%s: reading back the converted model: %s", name, msg);
    }
    return st;
}

lm_status lm_io_load_isolated(const uint8_t *data, size_t size, const char *name, const char *dir,
                              const lm_load_options *opts, lm_mesh **out)
{
    const char *tmp = getenv("TMPDIR");
    char folder[512], glb[600];
    snprintf(folder, sizeof folder, "%s/lumesh-load-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(folder))
        return lm_fail(LM_E_IO, "cannot create a temporary folder in %s: %s",
                       tmp && *tmp ? tmp : "/tmp", strerror(errno));
    snprintf(glb, sizeof glb, "%s/model.glb", folder);
    lm_status st = run_reader(data, size, name, dir, opts, glb);
    if (st == LM_OK)
        st = read_back(glb, name, opts, out);
    unlink(glb);
    rmdir(folder);
    return st;
}
