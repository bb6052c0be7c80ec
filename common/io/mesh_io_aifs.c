/* common/io/mesh_io_aifs.c — the file system assimp reads through (its C aiFileIO interface). The
 * model itself is served from memory (already checked by mesh_io_guard*.c); files it refers to
 * (MTL libraries, glTF buffers) are read whole from regular files only, so a hostile model cannot
 * make assimp read /dev/zero, a FIFO or a directory; in memory mode they do not exist at all. */
#include <assimp/cfileio.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "common/io/mesh_io_internal.h"

struct lm_aifs {
    struct aiFileIO io;
    char *main_name;
    const uint8_t *data;
    size_t size;
    int allow_disk;
};

typedef struct aifs_file {
    struct aiFile file;
    const uint8_t *data;
    size_t size, pos;
    uint8_t *owned; /* data read from disk, or NULL */
} aifs_file;

lm_status lm_io_read_file(const char *path, uint8_t **out, size_t *size)
{
    FILE *fp = fopen(path, "rb");
    struct stat st;
    if (!fp)
        return lm_fail(LM_E_IO, "cannot read %s: %s", path, strerror(errno));
    lm_status s = LM_OK;
    uint8_t *buf = NULL;
    if (fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode))
        s = lm_fail(LM_E_IO, "cannot read %s: not a regular file", path);
    else if ((uint64_t)st.st_size > LM_IO_MAX_FILE_BYTES)
        s = lm_fail(LM_E_RANGE, "%s: file of %lld bytes exceeds the limit of %zu", path,
                    (long long)st.st_size, LM_IO_MAX_FILE_BYTES);
    else if (!(buf = malloc((size_t)st.st_size + 1)))
        s = lm_fail(LM_E_NOMEM, "out of memory reading %s", path);
    else if (fread(buf, 1, (size_t)st.st_size, fp) != (size_t)st.st_size || ferror(fp))
        s = lm_fail(LM_E_IO, "cannot read %s: %s", path,
                    ferror(fp) ? strerror(errno) : "short read");
    fclose(fp);
    if (s) {
        free(buf);
        return s;
    }
    buf[st.st_size] = 0;
    *out = buf;
    *size = (size_t)st.st_size;
    return LM_OK;
}

static size_t f_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    aifs_file *af = (aifs_file *)f->UserData;
    if (size == 0 || count == 0)
        return 0;
    size_t avail = (af->size - af->pos) / size;
    size_t n = count < avail ? count : avail;
    memcpy(buf, af->data + af->pos, n * size);
    af->pos += n * size;
    return n;
}

static size_t f_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0;
}

static size_t f_tell(struct aiFile *f)
{
    return ((aifs_file *)f->UserData)->pos;
}

static size_t f_size(struct aiFile *f)
{
    return ((aifs_file *)f->UserData)->size;
}

static void f_flush(struct aiFile *f)
{
    (void)f;
}

/* Offsets are size_t: negative relative seeks arrive wrapped around, so add modulo 2^N. */
static enum aiReturn f_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    aifs_file *af = (aifs_file *)f->UserData;
    size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? af->pos : af->size;
    size_t to = base + offset;
    if (to > af->size)
        return aiReturn_FAILURE;
    af->pos = to;
    return aiReturn_SUCCESS;
}

static struct aiFile *fs_open(struct aiFileIO *io, const char *name, const char *mode)
{
    lm_aifs *fs = (lm_aifs *)io->UserData;
    if (!name || !mode || strchr(mode, 'w') || strchr(mode, 'a') || strchr(mode, '+'))
        return NULL;
    aifs_file *af = calloc(1, sizeof *af);
    if (!af)
        return NULL;
    if (!strcmp(name, fs->main_name)) {
        af->data = fs->data;
        af->size = fs->size;
    } else if (!fs->allow_disk || lm_io_read_file(name, &af->owned, &af->size) != LM_OK) {
        free(af);
        return NULL;
    } else {
        af->data = af->owned;
    }
    af->file = (struct aiFile){.ReadProc = f_read,
                               .WriteProc = f_write,
                               .TellProc = f_tell,
                               .FileSizeProc = f_size,
                               .SeekProc = f_seek,
                               .FlushProc = f_flush,
                               .UserData = (aiUserData)af};
    return &af->file;
}

static void fs_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (!f)
        return;
    aifs_file *af = (aifs_file *)f->UserData;
    free(af->owned);
    free(af);
}

lm_status lm_aifs_create(const char *main_name, const void *data, size_t size, int allow_disk,
                         lm_aifs **out)
{
    lm_aifs *fs = calloc(1, sizeof *fs);
    if (!fs || !(fs->main_name = strdup(main_name))) {
        free(fs);
        return lm_fail(LM_E_NOMEM, "out of memory opening %s", main_name);
    }
    fs->data = data;
    fs->size = size;
    fs->allow_disk = allow_disk;
    fs->io.OpenProc = fs_open;
    fs->io.CloseProc = fs_close;
    fs->io.UserData = (aiUserData)fs;
    *out = fs;
    return LM_OK;
}

struct aiFileIO *lm_aifs_io(lm_aifs *fs)
{
    return &fs->io;
}

void lm_aifs_destroy(lm_aifs *fs)
{
    if (!fs)
        return;
    free(fs->main_name);
    free(fs);
}
