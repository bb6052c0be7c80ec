/* common/mesh_io_guard_ply.c — walks a PLY file (header, then every element of the body, ASCII or
 * binary) before assimp 5.2 reads it, because that reader allocates the header's element counts
 * and each list's stored length up front: a 200-byte file claiming 10^9 vertices or a face list
 * of 2*10^9 indices makes it allocate gigabytes. Counts must fit in what the file holds. */
#include <stdlib.h>
#include <string.h>

#include "common/mesh_io_internal.h"

#define PLY_MAX_ELEMS 16
#define PLY_MAX_PROPS 64
#define PLY_MAX_HEADER 65536

typedef struct ply_prop {
    uint8_t is_list;
    uint8_t count_size, item_size; /* bytes in binary files */
    uint8_t count_signed;
} ply_prop;

typedef struct ply_elem {
    char name[32];
    uint64_t count;
    uint32_t n_props;
    ply_prop props[PLY_MAX_PROPS];
} ply_elem;

typedef struct ply_header {
    int format; /* 0 ascii, 1 binary little endian, 2 binary big endian */
    uint32_t n_elems;
    ply_elem elems[PLY_MAX_ELEMS];
    size_t body; /* offset of the first body byte */
} ply_header;

/* Size of a PLY scalar type name; 0 if unknown. Sets *is_signed. */
static uint8_t type_size(const char *t, uint8_t *is_signed)
{
    static const struct {
        const char *name;
        uint8_t size, is_signed;
    } types[] = {{"char", 1, 1},  {"int8", 1, 1},    {"uchar", 1, 0},  {"uint8", 1, 0},
                 {"short", 2, 1}, {"int16", 2, 1},   {"ushort", 2, 0}, {"uint16", 2, 0},
                 {"int", 4, 1},   {"int32", 4, 1},   {"uint", 4, 0},   {"uint32", 4, 0},
                 {"float", 4, 1}, {"float32", 4, 1}, {"double", 8, 1}, {"float64", 8, 1}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (!strcmp(t, types[i].name)) {
            *is_signed = types[i].is_signed;
            return types[i].size;
        }
    return 0;
}

/* "property TYPE NAME" or "property list CTYPE ITYPE NAME" (words[0] = "property"). */
static lm_status header_property(ply_header *h, char **w, int nw, const char *name)
{
    if (h->n_elems == 0)
        return lm_fail(LM_E_FORMAT, "%s: PLY property before any element", name);
    ply_elem *e = &h->elems[h->n_elems - 1];
    if (e->n_props == PLY_MAX_PROPS)
        return lm_fail(LM_E_FORMAT, "%s: PLY element with more than %d properties", name,
                       PLY_MAX_PROPS);
    ply_prop *p = &e->props[e->n_props++];
    uint8_t sgn;
    if (nw >= 5 && !strcmp(w[1], "list")) {
        p->is_list = 1;
        p->count_size = type_size(w[2], &p->count_signed);
        p->item_size = type_size(w[3], &sgn);
        if (p->count_size && p->item_size && !strstr(w[2], "float") && strcmp(w[2], "double"))
            return LM_OK;
    } else if (nw >= 3) {
        p->item_size = type_size(w[1], &sgn);
        if (p->item_size)
            return LM_OK;
    }
    return lm_fail(LM_E_FORMAT, "%s: bad PLY property line", name);
}

/* One header line split into words (modified in place). Sets *end on "end_header". */
static lm_status header_line(ply_header *h, char *line, const char *name, int *end)
{
    char *w[8], *save = NULL;
    int nw = 0;
    for (char *t = strtok_r(line, " \t\r", &save); t && nw < 8; t = strtok_r(NULL, " \t\r", &save))
        w[nw++] = t;
    if (nw == 0 || !strcmp(w[0], "comment") || !strcmp(w[0], "obj_info"))
        return LM_OK;
    if (!strcmp(w[0], "end_header") && nw == 1) {
        *end = 1;
        return LM_OK;
    }
    if (!strcmp(w[0], "format") && nw == 3) {
        h->format = !strcmp(w[1], "ascii")                  ? 0
                    : !strcmp(w[1], "binary_little_endian") ? 1
                    : !strcmp(w[1], "binary_big_endian")    ? 2
                                                            : -1;
        return h->format < 0 ? lm_fail(LM_E_FORMAT, "%s: unknown PLY format '%s'", name, w[1])
                             : LM_OK;
    }
    if (!strcmp(w[0], "element") && nw == 3) {
        if (h->n_elems == PLY_MAX_ELEMS)
            return lm_fail(LM_E_FORMAT, "%s: more than %d PLY elements", name, PLY_MAX_ELEMS);
        ply_elem *e = &h->elems[h->n_elems++];
        snprintf(e->name, sizeof e->name, "%s", w[1]);
        char *endp;
        if (w[2][0] < '0' || w[2][0] > '9' || (e->count = strtoull(w[2], &endp, 10), *endp))
            return lm_fail(LM_E_FORMAT, "%s: bad PLY element count '%s'", name, w[2]);
        return LM_OK;
    }
    if (!strcmp(w[0], "property"))
        return header_property(h, w, nw, name);
    return lm_fail(LM_E_FORMAT, "%s: unexpected PLY header line '%.40s'", name, w[0]);
}

/* The header, line by line up to a line "end_header"; h->body is the offset after it. */
static lm_status parse_header(const uint8_t *d, size_t size, const char *name, ply_header *h)
{
    memset(h, 0, sizeof *h);
    h->format = -1;
    size_t limit = size < PLY_MAX_HEADER ? size : PLY_MAX_HEADER;
    if (size < 4 || memcmp(d, "ply", 3) != 0 || (d[3] != '\n' && d[3] != '\r'))
        return lm_fail(LM_E_FORMAT, "%s: not a PLY file (no 'ply' line)", name);
    char line[512];
    int end = 0;
    lm_status s = LM_OK;
    for (size_t at = 0; !s && !end;) {
        const uint8_t *nl = at < limit ? memchr(d + at, '\n', limit - at) : NULL;
        size_t len = nl ? (size_t)(nl - d) - at : 0;
        if (!nl || len >= sizeof line || memchr(d + at, '\0', len))
            return lm_fail(LM_E_FORMAT, "%s: bad or unterminated PLY header", name);
        memcpy(line, d + at, len);
        line[len] = '\0';
        s = at == 0 ? LM_OK : header_line(h, line, name, &end);
        at += len + 1;
        h->body = at;
    }
    if (!s && h->format < 0)
        s = lm_fail(LM_E_FORMAT, "%s: PLY header has no format line", name);
    return s;
}

/* Claimed counts against limits and against the bytes present (each element takes at least one
 * byte, each property at least its binary size or two ASCII characters). */
static lm_status check_counts(const ply_header *h, size_t size, const char *name, uint32_t max_tris)
{
    uint64_t need = 0, left = size - h->body;
    for (uint32_t i = 0; i < h->n_elems; i++) {
        const ply_elem *e = &h->elems[i];
        uint64_t per = 0;
        for (uint32_t k = 0; k < e->n_props; k++)
            per += h->format == 0        ? 2
                   : e->props[k].is_list ? e->props[k].count_size
                                         : e->props[k].item_size;
        uint64_t limit = !strcmp(e->name, "face") ? max_tris : LM_MESH_MAX_VERTS;
        if (e->count > limit)
            return lm_fail(LM_E_RANGE, "%s: PLY header claims %llu %s elements (limit %llu)", name,
                           (unsigned long long)e->count, e->name, (unsigned long long)limit);
        need += e->count * (per ? per : 1);
        if (need > left)
            return lm_fail(LM_E_FORMAT,
                           "%s: truncated PLY file: header claims %llu %s elements but only %llu "
                           "bytes follow",
                           name, (unsigned long long)e->count, e->name, (unsigned long long)left);
    }
    return LM_OK;
}

/* ---- body walkers --------------------------------------------------------------------------- */

static uint64_t read_count(const uint8_t *p, const ply_prop *pr, int big, int *negative)
{
    uint64_t v = 0;
    for (int i = 0; i < pr->count_size; i++)
        v |= (uint64_t)p[big ? pr->count_size - 1 - i : i] << (8 * i);
    *negative = pr->count_signed && (v >> (8 * pr->count_size - 1)) & 1;
    return v;
}

static lm_status walk_binary(const uint8_t *d, size_t size, const ply_header *h, const char *name)
{
    uint64_t at = h->body;
    for (uint32_t i = 0; i < h->n_elems; i++) {
        const ply_elem *e = &h->elems[i];
        for (uint64_t j = 0; j < e->count; j++) {
            for (uint32_t k = 0; k < e->n_props; k++) {
                const ply_prop *p = &e->props[k];
                uint64_t n = 1;
                int negative = 0;
                if (p->is_list) {
                    if (at + p->count_size > size)
                        goto truncated;
                    n = read_count(d + at, p, h->format == 2, &negative);
                    at += p->count_size;
                }
                if (negative)
                    return lm_fail(LM_E_FORMAT, "%s: negative PLY list length in %s %llu", name,
                                   e->name, (unsigned long long)j);
                if (n > size || at + n * p->item_size > size)
                    goto truncated;
                at += n * p->item_size;
            }
        }
    }
    return LM_OK;
truncated:
    return lm_fail(LM_E_FORMAT, "%s: truncated binary PLY file (%zu bytes)", name, size);
}

/* The next non-blank line of the ASCII body: [*ls, *le). 0 at the end. */
static int next_line(const uint8_t *d, size_t size, uint64_t *at, uint64_t *ls, uint64_t *le)
{
    for (;;) {
        if (*at >= size)
            return 0;
        *ls = *at;
        while (*at < size && d[*at] != '\n')
            (*at)++;
        *le = *at;
        if (*at < size)
            (*at)++;
        for (uint64_t i = *ls; i < *le; i++)
            if (d[i] > ' ')
                return 1;
    }
}

/* Next token within [*at, le): its length (0 when the line has no more). */
static size_t next_word(const uint8_t *d, uint64_t le, uint64_t *at, const uint8_t **w)
{
    while (*at < le && d[*at] <= ' ')
        (*at)++;
    *w = d + *at;
    size_t n = 0;
    for (; *at < le && d[*at] > ' '; (*at)++)
        n++;
    return n;
}

/* One element instance on one line, as assimp reads ASCII PLY (missing trailing values are
 * tolerated; list lengths are bounded by the file since assimp allocates them first). */
static lm_status ascii_instance(const uint8_t *d, size_t size, uint64_t ls, uint64_t le,
                                const ply_elem *e, const char *name)
{
    const uint8_t *w;
    for (uint32_t k = 0; k < e->n_props; k++) {
        size_t len = next_word(d, le, &ls, &w);
        if (!len || !e->props[k].is_list)
            continue;
        uint64_t n = 0;
        for (size_t c = 0; c < len; c++) {
            if (w[c] < '0' || w[c] > '9')
                return lm_fail(LM_E_FORMAT, "%s: bad PLY list length in a %s element", name,
                               e->name);
            n = n > UINT64_MAX / 16 ? UINT64_MAX : n * 10 + (uint64_t)(w[c] - '0');
        }
        if (n > size / 2 + 1)
            return lm_fail(LM_E_RANGE,
                           "%s: PLY list of %llu values in a %s element exceeds the "
                           "file",
                           name, (unsigned long long)n, e->name);
        for (uint64_t v = 0; v < n && next_word(d, le, &ls, &w); v++)
            ;
    }
    return LM_OK;
}

static lm_status walk_ascii(const uint8_t *d, size_t size, const ply_header *h, const char *name)
{
    uint64_t at = h->body, ls, le;
    for (uint32_t i = 0; i < h->n_elems; i++) {
        const ply_elem *e = &h->elems[i];
        for (uint64_t j = 0; j < e->count; j++) {
            if (!next_line(d, size, &at, &ls, &le))
                return lm_fail(LM_E_FORMAT, "%s: truncated PLY file: %s %llu of %llu is missing",
                               name, e->name, (unsigned long long)j, (unsigned long long)e->count);
            lm_status s = ascii_instance(d, size, ls, le, e, name);
            if (s)
                return s;
        }
    }
    return LM_OK;
}

lm_status lm_io_guard_ply(const uint8_t *data, size_t size, const char *name, uint32_t max_tris)
{
    ply_header *h = malloc(sizeof *h);
    if (!h)
        return lm_fail(LM_E_NOMEM, "out of memory reading %s", name);
    lm_status s = parse_header(data, size, name, h);
    if (!s)
        s = check_counts(h, size, name, max_tris);
    if (!s)
        s = h->format == 0 ? walk_ascii(data, size, h, name) : walk_binary(data, size, h, name);
    free(h);
    return s;
}
