/* common/io/image_read.c — which decoder may see an image from outside (a model's texture, a
 * texture embedded in a model or a progressive-mesh file), and where. The bytes decide, never the
 * name: PNG and JPEG (by their signatures) are decoded in this process, through OpenImageIO's
 * readers that the test gate fuzzes (tests/fuzz/fuzz_image.c); anything else OpenImageIO may know
 * (TGA, BMP, TIFF, DDS, PSD, EXR, ...: dozens of readers nobody here fuzzes) is decoded in a
 * process of its own (this program run afresh: common/io/spawn_self.h) that hands the pixels back
 * through a pipe, so that a decoder crashing on a hostile file is a one-line error and the caller's
 * heap, GL contexts and work are untouched. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common/image.h"
#include "common/io/image_io.h"
#include "common/io/spawn_self.h"

/* CPU seconds a decoder process may use (a 16k x 16k texture decodes in a few). */
#define IMAGE_DECODER_CPU_SECONDS 300
/* Largest image file read into memory to be decoded here. */
#define IMAGE_MAX_FILE_BYTES ((size_t)1 << 30)

/* "png" or "jpg" when the bytes start with that format's signature; NULL otherwise. */
static const char *vetted_format(const uint8_t *p, size_t n)
{
    if (n >= 8 && !memcmp(p, "\x89PNG\r\n\x1a\n", 8))
        return "png";
    if (n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF)
        return "jpg";
    return NULL;
}

/* What to decode: a file (path) or bytes in memory. */
typedef struct decode_job {
    const char *path;
    const void *data;
    size_t size;
    const char *hint;
} decode_job;

/* ---- the decoder process ----------------------------------------------------------------------
 * A fork alone is not enough: the child would inherit locks and thread pools of threads it does
 * not have (OpenImageIO's TIFF reader spun forever in such a child, waiting on its parent's pool).
 * So the decoder is this same program afresh, with DECODER_ENV set; before main runs, the
 * constructor below sees it, decodes (the file DECODER_ENV names, or the bytes on stdin), answers
 * on stdout with {status, width, height} and the pixels (or the message), and exits. */
#define DECODER_ENV LM_SPAWN_ENV_PREFIX "IMAGE"
#define DECODER_HINT_ENV LM_SPAWN_ENV_PREFIX "IMAGE_HINT"

static void decoder_answer(int fd, lm_status st, const lm_image *img)
{
    int32_t head[3] = {(int32_t)st, img ? img->width : 0, img ? img->height : 0};
    if (fd >= 0 && lm_fd_write_all(fd, head, sizeof head)) {
        if (st == LM_OK)
            lm_fd_write_all(fd, img->pixels, (size_t)img->width * (size_t)img->height * 4);
        else
            lm_fd_write_all(fd, lm_last_error(), strlen(lm_last_error()));
    }
}

__attribute__((constructor)) static void decoder_main(void)
{
    const char *what = getenv(DECODER_ENV);
    if (!what)
        return;
    int answer = lm_spawn_helper_begin(IMAGE_DECODER_CPU_SECONDS);
    lm_image *img = NULL;
    lm_status st;
    if (what[0]) {
        st = lm_image_decode_file(what, &img);
    } else {
        size_t n = 0;
        uint8_t *data = lm_spawn_read_stdin(IMAGE_MAX_FILE_BYTES, &n);
        const char *hint = getenv(DECODER_HINT_ENV);
        st = data ? lm_image_decode_memory(data, n, hint && *hint ? hint : NULL, &img)
                  : lm_fail(LM_E_NOMEM, "out of memory reading an image");
        free(data);
    }
    decoder_answer(answer, st, img);
    _exit(0);
}

/* In the parent: the decoder's answer, read whole before it is reaped. */
static lm_status parent_read(int fd, const char *name, lm_image **out)
{
    int32_t head[3];
    if (!lm_fd_read_all(fd, head, sizeof head))
        return lm_fail(LM_E_FORMAT, "image %s: the image decoder failed on this file", name);
    if (head[0] != LM_OK) {
        char msg[400] = "";
        ssize_t n = read(fd, msg, sizeof msg - 1);
        msg[n > 0 ? n : 0] = '\0';
        lm_status st = head[0] > 0 && head[0] < LM_E_COUNT_ ? (lm_status)head[0] : LM_E_INTERNAL;
        return lm_fail(st, "%s", msg[0] ? msg : "image decoder failed");
    }
    if (head[1] < 1 || head[2] < 1 || head[1] > LM_IMAGE_MAX_SIDE || head[2] > LM_IMAGE_MAX_SIDE)
        return lm_fail(LM_E_INTERNAL, "image %s: the decoder process sent a %dx%d image", name,
                       head[1], head[2]);
    lm_image *img;
    lm_status st = lm_image_create(head[1], head[2], &img);
    if (st)
        return st;
    if (!lm_fd_read_all(fd, img->pixels, (size_t)head[1] * (size_t)head[2] * 4)) {
        lm_image_destroy(img);
        return lm_fail(LM_E_FORMAT, "image %s: the image decoder failed on this file", name);
    }
    *out = img;
    return LM_OK;
}

/* The decoder's exit: a crash, or an exec that failed, is an error naming `name`. */
static lm_status reap(pid_t pid, lm_status st, const char *name)
{
    int ws = 0;
    while (waitpid(pid, &ws, 0) < 0 && errno == EINTR)
        ;
    if (st == LM_OK) /* a whole image came back: it stands, whatever happened after */
        return LM_OK;
    if (WIFSIGNALED(ws))
        return lm_fail(LM_E_FORMAT,
                       "image %s: the image decoder crashed on it (%s): it is malformed", name,
                       strsignal(WTERMSIG(ws)));
    if (WIFEXITED(ws) && WEXITSTATUS(ws) == 127)
        return lm_fail(LM_E_INTERNAL, "image %s: cannot start an image decoder process", name);
    return st;
}

/* Decode in a fresh process (fork, then exec of this program); a crash there is LM_E_FORMAT
 * naming `name`. Bytes in memory go to it on a pipe. */
static lm_status decode_isolated(const decode_job *j, const char *name, lm_image **out)
{
    char what[4200], hint[64];
    snprintf(what, sizeof what, DECODER_ENV "=%s", j->path ? j->path : "");
    snprintf(hint, sizeof hint, DECODER_HINT_ENV "=%s", j->hint ? j->hint : "");
    const char *env[] = {what, hint, NULL};
    pid_t pid = 0;
    int answer = -1;
    lm_status st = lm_spawn_self("an image decoder process", env, j->path ? NULL : j->data, j->size,
                                 &pid, &answer);
    if (st)
        return st;
    lm_image *img = NULL;
    st = parent_read(answer, name, &img);
    close(answer);
    st = reap(pid, st, name);
    if (st) {
        lm_image_destroy(img);
        return st;
    }
    *out = img;
    return LM_OK;
}

/* The whole file, when it is small enough to decode from memory here. */
static lm_status read_bytes(const char *path, size_t size, uint8_t **out)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return lm_fail(LM_E_IO, "cannot read image %s: %s", path, strerror(errno));
    uint8_t *buf = malloc(size ? size : 1);
    size_t got = buf ? fread(buf, 1, size, fp) : 0;
    fclose(fp);
    if (!buf || got != size) {
        free(buf);
        return buf ? lm_fail(LM_E_IO, "cannot read image %s: it changed while read", path)
                   : lm_fail(LM_E_NOMEM, "out of memory reading image %s", path);
    }
    *out = buf;
    return LM_OK;
}

lm_status lm_image_read(const char *path, lm_image **out)
{
    LM_ASSERT(path != NULL && out != NULL);
    struct stat st;
    if (stat(path, &st) != 0)
        return lm_fail(LM_E_IO, "cannot read image %s: %s", path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return lm_fail(LM_E_IO, "cannot read image %s: not a regular file", path);
    uint8_t head[8] = {0};
    FILE *fp = fopen(path, "rb");
    size_t n = fp ? fread(head, 1, sizeof head, fp) : 0;
    if (fp)
        fclose(fp);
    if (!fp)
        return lm_fail(LM_E_IO, "cannot read image %s: %s", path, strerror(errno));
    const char *fmt = vetted_format(head, n);
    if (!fmt || (uint64_t)st.st_size > IMAGE_MAX_FILE_BYTES) {
        decode_job j = {.path = path};
        return decode_isolated(&j, path, out);
    }
    uint8_t *bytes = NULL;
    lm_status s = read_bytes(path, (size_t)st.st_size, &bytes);
    if (s)
        return s;
    s = lm_image_decode_memory(bytes, (size_t)st.st_size, fmt, out);
    free(bytes);
    if (s) { /* the message names the file, not "embedded.png" */
        char msg[300];
        snprintf(msg, sizeof msg, "%s", lm_last_error());
        s = lm_fail(s, "image %s: %s", path, msg);
    }
    return s;
}

lm_status lm_image_read_memory(const void *data, size_t size, const char *hint_ext, lm_image **out)
{
    LM_ASSERT(out != NULL);
    if (!data || size == 0)
        return lm_fail(LM_E_FORMAT, "embedded image is empty");
    const char *fmt = vetted_format(data, size);
    if (fmt)
        return lm_image_decode_memory(data, size, fmt, out);
    decode_job j = {.data = data, .size = size, .hint = hint_ext};
    char name[64];
    snprintf(name, sizeof name, "embedded %s (%zu bytes)", hint_ext && *hint_ext ? hint_ext : "",
             size);
    return decode_isolated(&j, name, out);
}
