/* common/io/mesh_io_guard_stl.c — checks an STL file before assimp 5.2 reads it. Binary: assimp
 * computes 84 + 50 * count in 32 bits, so a count that wraps around passes its size check and
 * makes it read far beyond the buffer. ASCII: a malformed number after "vertex" or "facet normal"
 * makes assimp throw from the middle of its parser and leak the mesh it was building; this walk
 * follows assimp's token rules and its number grammar (fast_atoreal_move) to refuse those first. */
#include <string.h>
#include <strings.h>

#include "common/bytes.h"
#include "common/io/mesh_io_internal.h"

typedef struct stl_cursor {
    const char *p, *end; /* end = first NUL or end of data, like assimp's C string */
} stl_cursor;

static char at(const stl_cursor *c, size_t k)
{
    return c->p + k < c->end ? c->p[k] : '\0';
}

static int is_digit(char ch)
{
    return ch >= '0' && ch <= '9';
}

static int is_space_or_newline(char ch)
{
    return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n' || ch == '\f' || ch == '\0';
}

static void skip_blanks(stl_cursor *c)
{
    while (c->p < c->end && (*c->p == ' ' || *c->p == '\t'))
        c->p++;
}

static int starts(const stl_cursor *c, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(c->end - c->p) >= n && !memcmp(c->p, word, n);
}

static void skip_digits(stl_cursor *c)
{
    while (is_digit(at(c, 0)))
        c->p++;
}

/* One number as assimp's fast_atoreal_move reads it; 0 where assimp would throw. */
static int number(stl_cursor *c)
{
    if (at(c, 0) == '-' || at(c, 0) == '+')
        c->p++;
    if ((size_t)(c->end - c->p) >= 3 && !strncasecmp(c->p, "nan", 3)) {
        c->p += 3;
        return 1;
    }
    if ((size_t)(c->end - c->p) >= 3 && !strncasecmp(c->p, "inf", 3)) {
        c->p += 3;
        if ((size_t)(c->end - c->p) >= 5 && !strncasecmp(c->p, "inity", 5))
            c->p += 5;
        return 1;
    }
    int lead_point = (at(c, 0) == '.' || at(c, 0) == ',') && is_digit(at(c, 1));
    if (!is_digit(at(c, 0)) && !lead_point)
        return 0;
    skip_digits(c);
    if ((at(c, 0) == '.' || at(c, 0) == ',') && is_digit(at(c, 1))) {
        c->p++;
        skip_digits(c);
    } else if (at(c, 0) == '.') {
        c->p++;
    }
    if (at(c, 0) == 'e' || at(c, 0) == 'E') {
        c->p++;
        if (at(c, 0) == '-' || at(c, 0) == '+')
            c->p++;
        if (!is_digit(at(c, 0)))
            return 0;
        skip_digits(c);
    }
    return 1;
}

/* After "vertex" or "normal" and the one character assimp skips with it: three numbers. */
static int three_numbers(stl_cursor *c)
{
    c->p += 7;
    for (int k = 0; k < 3; k++) {
        skip_blanks(c);
        if (c->p >= c->end || !number(c))
            return 0;
    }
    return 1;
}

static lm_status guard_ascii(const uint8_t *d, size_t size, const char *name)
{
    const char *nul = memchr(d, '\0', size);
    stl_cursor c = {(const char *)d, nul ? nul : (const char *)d + size};
    for (;;) {
        while (c.p < c.end && is_space_or_newline(*c.p))
            c.p++;
        if (c.p >= c.end)
            return LM_OK;
        int ok = 1;
        if (starts(&c, "vertex") && is_space_or_newline(at(&c, 6))) {
            ok = three_numbers(&c);
        } else if (starts(&c, "facet") && is_space_or_newline(at(&c, 5)) && at(&c, 5)) {
            c.p += 6;
            skip_blanks(&c);
            if (starts(&c, "normal"))
                ok = at(&c, 6) != '\0' && three_numbers(&c);
        } else if (starts(&c, "endsolid")) {
            while (c.p < c.end && *c.p != '\n' && *c.p != '\r' && *c.p != '\f')
                c.p++;
        } else {
            do
                c.p++;
            while (!is_space_or_newline(at(&c, 0)));
        }
        if (!ok)
            return lm_fail(LM_E_FORMAT, "%s: malformed number in ASCII STL at byte %zu", name,
                           (size_t)(c.p - (const char *)d));
    }
}

lm_status lm_io_guard_stl(const uint8_t *d, size_t size, const char *name, uint32_t max_tris)
{
    if (size < 84 || (uint32_t)(lm_le32(d + 80) * 50u + 84u) != (uint32_t)size)
        return guard_ascii(d, size, name); /* assimp's test for binary: exact size, 32 bits */
    uint32_t n = lm_le32(d + 80);
    if (n > max_tris)
        return lm_fail(LM_E_RANGE, "%s: binary STL header claims %u triangles (limit %u)", name, n,
                       max_tris);
    if ((uint64_t)n * 50u + 84u != size)
        return lm_fail(LM_E_FORMAT, "%s: binary STL header claims %u triangles, the file holds %zu",
                       name, n, (size - 84) / 50);
    return LM_OK;
}
