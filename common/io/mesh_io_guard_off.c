/* common/io/mesh_io_guard_off.c — walks an OFF file the way assimp 5.2's OFF reader does (same
 * token and line rules) before assimp reads it, because that reader allocates the header's counts
 * up front, silently clamps out-of-range vertex indices to the last vertex, silently accepts files
 * with fewer lines than the header claims, loops past the face count on faces with 0 or > 9
 * corners, and overflows its 4096-byte line buffer by one byte on longer lines. */
#include <string.h>

#include "common/io/mesh_io_internal.h"

#define OFF_LINE_MAX 4000 /* assimp copies lines into char[4096] */

typedef struct off_cursor {
    const char *p, *end; /* end = first NUL or end of data (assimp stops at NUL too) */
} off_cursor;

static int is_line_end(char c)
{
    return c == '\r' || c == '\n' || c == '\f';
}

/* assimp's NextToken: skip blanks and line ends, and comment lines. */
static void next_token(off_cursor *c)
{
    for (;;) {
        while (c->p < c->end && (*c->p == ' ' || *c->p == '\t' || is_line_end(*c->p)))
            c->p++;
        if (c->p >= c->end || *c->p != '#')
            return;
        while (c->p < c->end && *c->p != '\n' && *c->p != '\r')
            c->p++;
    }
}

/* Decimal digits as a saturating 64-bit number; *ok = 0 when no digit is there. */
static uint64_t read_uint(off_cursor *c, int *ok)
{
    uint64_t v = 0;
    *ok = 0;
    while (c->p < c->end && *c->p >= '0' && *c->p <= '9') {
        v = v > UINT64_MAX / 16 ? UINT64_MAX : v * 10 + (uint64_t)(*c->p - '0');
        c->p++;
        *ok = 1;
    }
    return v;
}

/* assimp's GetNextLine: the text up to the next line end, then skip all consecutive line ends. */
static int next_line(off_cursor *c, const char **line, size_t *len)
{
    if (c->p >= c->end)
        return 0;
    *line = c->p;
    while (c->p < c->end && !is_line_end(*c->p))
        c->p++;
    *len = (size_t)(c->p - *line);
    while (c->p < c->end && is_line_end(*c->p))
        c->p++;
    return 1;
}

/* Header "[ST][C][N][4][n]OFF [dim] nv nf ne"; leaves the cursor at the first vertex line. */
static lm_status off_header(off_cursor *c, const char *name, uint64_t *nv, uint64_t *nf)
{
    next_token(c);
    const char *prefixes[] = {"ST", "C", "N", "4", "n"};
    int has_dim = 0;
    for (int i = 0; i < 5; i++) {
        size_t n = strlen(prefixes[i]);
        if (c->end - c->p > (long)n && !memcmp(c->p, prefixes[i], n)) {
            c->p += n;
            has_dim = i == 4;
        }
    }
    if (c->end - c->p >= 3 && !memcmp(c->p, "OFF", 3))
        c->p += 3;
    int ok;
    if (has_dim) {
        next_token(c);
        read_uint(c, &ok);
    }
    next_token(c);
    *nv = read_uint(c, &ok);
    if (!ok)
        return lm_fail(LM_E_FORMAT, "%s: OFF header has no vertex count", name);
    next_token(c);
    *nf = read_uint(c, &ok);
    if (!ok)
        return lm_fail(LM_E_FORMAT, "%s: OFF header has no face count", name);
    next_token(c);
    read_uint(c, &ok); /* edge count, unused */
    next_token(c);
    return LM_OK;
}

static lm_status off_counts(const off_cursor *c, const char *name, uint64_t nv, uint64_t nf,
                            uint32_t max_tris)
{
    if (nv == 0 || nf == 0)
        return lm_fail(LM_E_FORMAT, "%s: OFF file has %llu vertices and %llu faces", name,
                       (unsigned long long)nv, (unsigned long long)nf);
    if (nv > LM_MESH_MAX_VERTS || nf > max_tris)
        return lm_fail(LM_E_RANGE,
                       "%s: OFF header claims %llu vertices and %llu faces (limits %u, %u)", name,
                       (unsigned long long)nv, (unsigned long long)nf, LM_MESH_MAX_VERTS, max_tris);
    /* Every vertex and face takes a line of at least two bytes. */
    size_t left = (size_t)(c->end - c->p);
    if ((nv + nf) * 2 > (uint64_t)left + 2)
        return lm_fail(LM_E_FORMAT,
                       "%s: truncated OFF file: header claims %llu vertices and %llu faces but "
                       "only %zu bytes follow",
                       name, (unsigned long long)nv, (unsigned long long)nf, left);
    return LM_OK;
}

/* One face line: corner count 1..9, then that many indices below nv. */
static lm_status off_face(const char *line, size_t len, uint64_t face, uint64_t nv,
                          const char *name)
{
    off_cursor c = {line, line + len};
    int ok;
    while (c.p < c.end && (*c.p == ' ' || *c.p == '\t'))
        c.p++;
    uint64_t n = read_uint(&c, &ok);
    if (!ok || n == 0 || n > 9)
        return lm_fail(LM_E_FORMAT, "%s: OFF face %llu has a bad corner count (1..9 allowed)", name,
                       (unsigned long long)face);
    for (uint64_t k = 0; k < n; k++) {
        while (c.p < c.end && (*c.p == ' ' || *c.p == '\t'))
            c.p++;
        uint64_t idx = read_uint(&c, &ok);
        if (!ok)
            return lm_fail(LM_E_FORMAT,
                           "%s: OFF face %llu has %llu corners but a missing or "
                           "non-numeric index",
                           name, (unsigned long long)face, (unsigned long long)n);
        if (idx >= nv)
            return lm_fail(LM_E_RANGE, "%s: OFF face %llu refers to vertex %llu of %llu", name,
                           (unsigned long long)face, (unsigned long long)idx,
                           (unsigned long long)nv);
    }
    return LM_OK;
}

lm_status lm_io_guard_off(const uint8_t *data, size_t size, const char *name, uint32_t max_tris)
{
    const char *text = (const char *)data;
    const char *nul = memchr(text, '\0', size);
    off_cursor c = {text, nul ? nul : text + size};
    uint64_t nv = 0, nf = 0;
    lm_status s = off_header(&c, name, &nv, &nf);
    if (!s)
        s = off_counts(&c, name, nv, nf, max_tris);
    const char *line;
    size_t len;
    for (uint64_t i = 0; !s && i < nv + nf; i++) {
        if (!next_line(&c, &line, &len))
            return lm_fail(LM_E_FORMAT, "%s: truncated OFF file: %s %llu of %llu is missing", name,
                           i < nv ? "vertex" : "face", (unsigned long long)(i < nv ? i : i - nv),
                           (unsigned long long)(i < nv ? nv : nf));
        if (len > OFF_LINE_MAX)
            return lm_fail(LM_E_FORMAT, "%s: OFF line of %zu characters (limit %d)", name, len,
                           OFF_LINE_MAX);
        if (i >= nv)
            s = off_face(line, len, i - nv, nv, name);
    }
    return s;
}
