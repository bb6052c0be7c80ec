/* common/optimizer/binio.c — sticky-error little-endian binary I/O. */
#include "common/optimizer/binio.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

void lm_bin_init(lm_bin *b, FILE *fp, const char *what)
{
    memset(b, 0, sizeof *b);
    b->fp = fp;
    b->status = LM_OK;
    b->what = what;
}

void lm_bin_init_writer(lm_bin *b, const char *what)
{
    lm_bin_init(b, NULL, what);
}

void lm_bin_init_reader(lm_bin *b, const uint8_t *buf, size_t len, const char *what)
{
    lm_bin_init(b, NULL, what);
    b->in = buf;
    b->cap = len;
}

lm_status lm_bin_take(lm_bin *b, uint8_t **buf, size_t *len)
{
    if (b->status == LM_OK && !b->out && !(b->out = malloc(1)))
        b->status = lm_fail(LM_E_NOMEM, "out of memory for %s", b->what);
    *buf = b->status == LM_OK ? b->out : NULL;
    *len = b->status == LM_OK ? b->pos : 0;
    if (b->status != LM_OK)
        free(b->out);
    b->out = NULL;
    b->pos = b->cap = 0;
    return b->status;
}

uint64_t lm_bin_left(lm_bin *b)
{
    if (!b->fp)
        return b->cap - b->pos;
    long here = ftell(b->fp);
    if (here < 0 || fseek(b->fp, 0, SEEK_END) != 0)
        return UINT64_MAX;
    long end = ftell(b->fp);
    if (fseek(b->fp, here, SEEK_SET) != 0 || end < here)
        return UINT64_MAX;
    return (uint64_t)(end - here);
}

/* Room for n more bytes in a writer's memory (doubling); 0 and the status set when none. */
static int grow(lm_bin *b, size_t n)
{
    if (b->in) { /* a reader is not written to */
        b->status = lm_fail(LM_E_INTERNAL, "%s: writing to a reader", b->what);
        return 0;
    }
    if (b->cap - b->pos >= n)
        return 1;
    size_t cap = b->cap ? b->cap : 4096;
    while (cap - b->pos < n)
        cap *= 2;
    uint8_t *out = realloc(b->out, cap);
    if (!out) {
        b->status = lm_fail(LM_E_NOMEM, "out of memory for %s", b->what);
        return 0;
    }
    b->out = out;
    b->cap = cap;
    return 1;
}

void lm_put_bytes(lm_bin *b, const void *p, size_t n)
{
    if (b->status || n == 0)
        return;
    if (!b->fp) {
        if (grow(b, n)) {
            memcpy(b->out + b->pos, p, n);
            b->pos += n;
        }
        return;
    }
    if (fwrite(p, 1, n, b->fp) != n)
        b->status = lm_fail(LM_E_IO, "writing %s failed", b->what);
}

static void put_le(lm_bin *b, uint64_t v, int bytes)
{
    if (!b->fp && b->status == LM_OK && grow(b, 8)) { /* memory: stored in place */
        uint8_t *p = b->out + b->pos;
        for (int i = 0; i < bytes; i++)
            p[i] = (uint8_t)(v >> (8 * i));
        b->pos += (size_t)bytes;
        return;
    }
    uint8_t buf[8];
    for (int i = 0; i < bytes; i++)
        buf[i] = (uint8_t)(v >> (8 * i));
    lm_put_bytes(b, buf, (size_t)bytes);
}

void lm_put_u32(lm_bin *b, uint32_t v)
{
    put_le(b, v, 4);
}

void lm_put_u64(lm_bin *b, uint64_t v)
{
    put_le(b, v, 8);
}

void lm_put_i64(lm_bin *b, int64_t v)
{
    put_le(b, (uint64_t)v, 8);
}

void lm_put_f32(lm_bin *b, float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    put_le(b, u, 4);
}

void lm_put_f64(lm_bin *b, double v)
{
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    put_le(b, u, 8);
}

void lm_get_bytes(lm_bin *b, void *p, size_t n)
{
    if (b->status) {
        memset(p, 0, n);
        return;
    }
    if (!b->fp) { /* memory (a writer has nothing to read: truncated) */
        if (n && (!b->in || b->cap - b->pos < n)) {
            memset(p, 0, n);
            b->pos = b->cap;
            b->status = lm_fail(LM_E_FORMAT, "%s is truncated", b->what);
        } else if (n) {
            memcpy(p, b->in + b->pos, n);
            b->pos += n;
        }
        return;
    }
    if (n && fread(p, 1, n, b->fp) != n) {
        memset(p, 0, n);
        b->status = lm_fail(LM_E_FORMAT, "%s is truncated", b->what);
    }
}

static uint64_t get_le(lm_bin *b, int bytes)
{
    if (!b->fp && b->in && b->status == LM_OK && b->cap - b->pos >= (size_t)bytes) { /* memory */
        const uint8_t *p = b->in + b->pos;
        uint64_t v = 0;
        for (int i = 0; i < bytes; i++)
            v |= (uint64_t)p[i] << (8 * i);
        b->pos += (size_t)bytes;
        return v;
    }
    uint8_t buf[8];
    lm_get_bytes(b, buf, (size_t)bytes);
    uint64_t v = 0;
    for (int i = 0; i < bytes; i++)
        v |= (uint64_t)buf[i] << (8 * i);
    return v;
}

uint32_t lm_get_u32(lm_bin *b)
{
    return (uint32_t)get_le(b, 4);
}

uint64_t lm_get_u64(lm_bin *b)
{
    return get_le(b, 8);
}

int64_t lm_get_i64(lm_bin *b)
{
    return (int64_t)get_le(b, 8);
}

float lm_get_f32(lm_bin *b)
{
    uint32_t u = (uint32_t)get_le(b, 4);
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

double lm_get_f64(lm_bin *b)
{
    uint64_t u = get_le(b, 8);
    double v;
    memcpy(&v, &u, sizeof v);
    return v;
}

lm_status lm_bin_bad(lm_bin *b, const char *fmt, ...)
{
    if (b->status)
        return b->status;
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    b->status = lm_fail(LM_E_FORMAT, "%s: %s", b->what, msg);
    return b->status;
}
