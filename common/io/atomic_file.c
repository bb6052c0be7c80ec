/* common/io/atomic_file.c — atomic file replacement shared by every writer (meshes, images,
 * checkpoints): write "<path>.tmp.XXXXXX" in the same folder, fsync it, rename it over <path>,
 * fsync the folder. A failed or abandoned write leaves nothing behind. */
#include "common/io/atomic_file.h"
#include "common/io/mesh_io.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void atomic_free(lm_atomic_file *f)
{
    free(f->final_path);
    free(f->tmp_path);
    f->final_path = f->tmp_path = NULL;
    f->fp = NULL;
}

lm_status lm_atomic_open(lm_atomic_file *f, const char *path)
{
    memset(f, 0, sizeof *f);
    if (!path || !*path)
        return lm_fail(LM_E_INVALID, "empty output path");
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
        return lm_fail(LM_E_IO, "cannot write %s: it is a directory", path);
    size_t n = strlen(path);
    f->final_path = strdup(path);
    f->tmp_path = malloc(n + sizeof ".tmp.XXXXXX");
    if (!f->final_path || !f->tmp_path) {
        atomic_free(f);
        return lm_fail(LM_E_NOMEM, "out of memory opening %s", path);
    }
    memcpy(f->tmp_path, path, n);
    memcpy(f->tmp_path + n, ".tmp.XXXXXX", sizeof ".tmp.XXXXXX");
    int fd = mkstemp(f->tmp_path);
    if (fd < 0) {
        int e = errno;
        atomic_free(f);
        return lm_fail(LM_E_IO, "cannot write %s: %s", path, strerror(e));
    }
    /* mkstemp makes the file 0600; give it the usual permissions of an output file (umask is
     * not read: changing it to read it would race with other threads). */
    if (fchmod(fd, 0644) != 0 || !(f->fp = fdopen(fd, "wb"))) {
        int e = errno;
        close(fd);
        unlink(f->tmp_path);
        atomic_free(f);
        return lm_fail(LM_E_IO, "cannot write %s: %s", path, strerror(e));
    }
    return LM_OK;
}

/* fsync the folder holding `path` so the rename itself is durable (best effort). */
static void sync_parent(const char *path)
{
    const char *slash = strrchr(path, '/');
    char *dir = slash ? strndup(path, (size_t)(slash - path) + (slash == path)) : strdup(".");
    if (!dir)
        return;
    int fd = open(dir, O_RDONLY | O_DIRECTORY);
    if (fd >= 0) {
        fsync(fd);
        close(fd);
    }
    free(dir);
}

/* Flush, sync and close the temporary file; returns 0 or an errno value. */
static int finish_tmp(lm_atomic_file *f)
{
    FILE *fp = f->fp;
    f->fp = NULL;
    if (fp) {
        int e = 0;
        if (ferror(fp) || fflush(fp) != 0 || fsync(fileno(fp)) != 0)
            e = errno ? errno : EIO;
        if (fclose(fp) != 0 && !e)
            e = errno ? errno : EIO;
        return e;
    }
    int fd = open(f->tmp_path, O_RDONLY);
    if (fd < 0)
        return errno;
    int e = fsync(fd) != 0 ? errno : 0;
    close(fd);
    return e;
}

/* Fault injection for tests: LUMESH_FAULT_RENAME="SUFFIX:N" kills the process (SIGKILL) at the
 * N-th commit of a file whose name ends with SUFFIX, after the temporary file is written and
 * synced and before it is renamed: the moment a crash may leave a temporary file and the old
 * version behind. */
static void maybe_die_before_rename(const char *path)
{
    static int seen;
    const char *spec = getenv("LUMESH_FAULT_RENAME");
    const char *colon = spec ? strrchr(spec, ':') : NULL;
    if (!colon)
        return;
    size_t n = (size_t)(colon - spec), len = strlen(path);
    if (len >= n && !strncmp(path + len - n, spec, n) && ++seen == atoi(colon + 1))
        raise(SIGKILL);
}

lm_status lm_atomic_commit(lm_atomic_file *f)
{
    LM_ASSERT(f->tmp_path != NULL && f->final_path != NULL);
    errno = 0;
    int e = finish_tmp(f);
    if (!e)
        maybe_die_before_rename(f->final_path);
    if (!e && rename(f->tmp_path, f->final_path) != 0)
        e = errno;
    if (e) {
        unlink(f->tmp_path);
        lm_status s = lm_fail(LM_E_IO, "cannot write %s: %s", f->final_path, strerror(e));
        atomic_free(f);
        return s;
    }
    sync_parent(f->final_path);
    atomic_free(f);
    return LM_OK;
}

void lm_atomic_abort(lm_atomic_file *f)
{
    if (f->fp)
        fclose(f->fp);
    f->fp = NULL;
    if (f->tmp_path)
        unlink(f->tmp_path);
    atomic_free(f);
}
