/* common/io/mesh_io_ply_header.c — the header of a PLY file, for lumesh's own PLY reader
 * (mesh_io_ply_read.c): its format, elements, properties and the roles lumesh gives them, the
 * texture a "comment TextureFile" names, and every count checked against the limits and against
 * the bytes present before the body is read. */
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io_ply_header.h"

#define PLY_MAX_HEADER 65536
#define PLY_MAX_LINE 1024

size_t lm_ply_type_size(ply_type t)
{
    static const uint8_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[t];
}

/* The ply_type a type name means; -1 if none. */
static int type_of(const char *t)
{
    static const struct {
        const char *name;
        ply_type type;
    } types[] = {
        {"char", PLY_I8},   {"int8", PLY_I8},     {"uchar", PLY_U8},   {"uint8", PLY_U8},
        {"short", PLY_I16}, {"int16", PLY_I16},   {"ushort", PLY_U16}, {"uint16", PLY_U16},
        {"int", PLY_I32},   {"int32", PLY_I32},   {"uint", PLY_U32},   {"uint32", PLY_U32},
        {"float", PLY_F32}, {"float32", PLY_F32}, {"double", PLY_F64}, {"float64", PLY_F64}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (!strcmp(t, types[i].name))
            return (int)types[i].type;
    return -1;
}

/* The role of a scalar property of a vertex. */
static ply_role vertex_role(const char *n)
{
    static const struct {
        const char *name;
        ply_role role;
    } roles[] = {{"x", PLY_ROLE_X},         {"y", PLY_ROLE_Y},         {"z", PLY_ROLE_Z},
                 {"nx", PLY_ROLE_NX},       {"ny", PLY_ROLE_NY},       {"nz", PLY_ROLE_NZ},
                 {"red", PLY_ROLE_RED},     {"r", PLY_ROLE_RED},       {"green", PLY_ROLE_GREEN},
                 {"g", PLY_ROLE_GREEN},     {"blue", PLY_ROLE_BLUE},   {"b", PLY_ROLE_BLUE},
                 {"alpha", PLY_ROLE_ALPHA}, {"u", PLY_ROLE_U},         {"s", PLY_ROLE_U},
                 {"tx", PLY_ROLE_U},        {"texture_u", PLY_ROLE_U}, {"texture_s", PLY_ROLE_U},
                 {"v", PLY_ROLE_V},         {"t", PLY_ROLE_V},         {"ty", PLY_ROLE_V},
                 {"texture_v", PLY_ROLE_V}, {"texture_t", PLY_ROLE_V}};
    for (size_t i = 0; i < sizeof roles / sizeof roles[0]; i++)
        if (!strcmp(n, roles[i].name))
            return roles[i].role;
    return PLY_ROLE_NONE;
}

/* The role of property `n` (a list when is_list) of element e. */
static ply_role role_of(const ply_elem *e, const char *n, int is_list)
{
    if (e->kind == PLY_ELEM_VERTEX && !is_list)
        return vertex_role(n);
    if (e->kind == PLY_ELEM_FACE && is_list &&
        (!strcmp(n, "vertex_indices") || !strcmp(n, "vertex_index")))
        return PLY_ROLE_INDICES;
    if (e->kind == PLY_ELEM_STRIP && is_list)
        return PLY_ROLE_INDICES;
    return PLY_ROLE_NONE;
}

/* "property TYPE NAME" or "property list CTYPE ITYPE NAME" (w[0] = "property"). */
static lm_status header_property(ply_header *h, char **w, int nw, const char *name)
{
    if (h->n_elems == 0)
        return lm_fail(LM_E_FORMAT, "%s: PLY property before any element", name);
    ply_elem *e = &h->elems[h->n_elems - 1];
    if (e->n_props == PLY_MAX_PROPS)
        return lm_fail(LM_E_FORMAT, "%s: PLY element with more than %d properties", name,
                       PLY_MAX_PROPS);
    ply_prop *p = &e->props[e->n_props];
    int is_list = nw == 5 && !strcmp(w[1], "list");
    int ct = is_list ? type_of(w[2]) : 0, it = type_of(w[is_list ? 3 : 1]);
    if ((!is_list && nw != 3) || ct < 0 || it < 0 || ct >= PLY_F32)
        return lm_fail(LM_E_FORMAT, "%s: bad PLY property line (property %s ...)", name,
                       nw > 1 ? w[1] : "");
    int taken = 0;
    for (uint32_t k = 0; k < e->n_props; k++)
        taken |= e->props[k].role == PLY_ROLE_INDICES;
    p->is_list = (uint8_t)is_list;
    p->count_type = (uint8_t)ct;
    p->type = (uint8_t)it;
    p->role = (uint8_t)role_of(e, w[nw - 1], is_list);
    if (p->role == PLY_ROLE_INDICES && taken) /* the first index list is the one read */
        p->role = PLY_ROLE_NONE;
    e->n_props++;
    return LM_OK;
}

static lm_status header_element(ply_header *h, char **w, const char *name)
{
    if (h->n_elems == PLY_MAX_ELEMS)
        return lm_fail(LM_E_FORMAT, "%s: more than %d PLY elements", name, PLY_MAX_ELEMS);
    ply_elem *e = &h->elems[h->n_elems];
    snprintf(e->name, sizeof e->name, "%s", w[1]);
    e->kind = !strcmp(w[1], "vertex")      ? PLY_ELEM_VERTEX
              : !strcmp(w[1], "face")      ? PLY_ELEM_FACE
              : !strcmp(w[1], "tristrips") ? PLY_ELEM_STRIP
                                           : PLY_ELEM_OTHER;
    for (uint32_t i = 0; e->kind != PLY_ELEM_OTHER && i < h->n_elems; i++)
        if (h->elems[i].kind == e->kind)
            return lm_fail(LM_E_FORMAT, "%s: the PLY header declares element '%s' twice", name,
                           e->name);
    char *endp;
    if (w[2][0] < '0' || w[2][0] > '9' || (e->count = strtoull(w[2], &endp, 10), *endp))
        return lm_fail(LM_E_FORMAT, "%s: bad PLY element count '%.40s'", name, w[2]);
    h->n_elems++;
    return LM_OK;
}

static lm_status header_format(ply_header *h, const char *f, int *seen, const char *name)
{
    if (*seen)
        return lm_fail(LM_E_FORMAT, "%s: the PLY header has two format lines", name);
    *seen = 1;
    if (!strcmp(f, "ascii"))
        h->format = PLY_ASCII;
    else if (!strcmp(f, "binary_little_endian"))
        h->format = PLY_BINARY_LE;
    else if (!strcmp(f, "binary_big_endian"))
        h->format = PLY_BINARY_BE;
    else
        return lm_fail(LM_E_FORMAT, "%s: unknown PLY format '%.40s'", name, f);
    return LM_OK;
}

/* "comment TextureFile NAME": NAME (to the end of the line, spaces trimmed) is the texture. */
static void header_comment(ply_header *h, const char *line)
{
    const char *tag = "comment TextureFile ";
    if (strncmp(line, tag, strlen(tag)) != 0)
        return;
    const char *t = line + strlen(tag);
    while (*t == ' ' || *t == '\t')
        t++;
    size_t n = strnlen(t, sizeof h->texture - 1);
    memcpy(h->texture, t, n);
    h->texture[n] = '\0';
    while (n && (h->texture[n - 1] == ' ' || h->texture[n - 1] == '\t'))
        h->texture[--n] = '\0';
}

/* One header line, split into words in place. Sets *end on "end_header". */
static lm_status header_line(ply_header *h, char *line, int *seen_format, int *end,
                             const char *name)
{
    header_comment(h, line);
    char *w[8], *save = NULL;
    int nw = 0;
    for (char *t = strtok_r(line, " \t", &save); t && nw < 8; t = strtok_r(NULL, " \t", &save))
        w[nw++] = t;
    if (nw == 0 || !strcmp(w[0], "comment") || !strcmp(w[0], "obj_info"))
        return LM_OK;
    if (!strcmp(w[0], "end_header") && nw == 1) {
        *end = 1;
        return LM_OK;
    }
    if (!strcmp(w[0], "format") && nw == 3)
        return header_format(h, w[1], seen_format, name);
    if (!strcmp(w[0], "element") && nw == 3)
        return header_element(h, w, name);
    if (!strcmp(w[0], "property"))
        return header_property(h, w, nw, name);
    return lm_fail(LM_E_FORMAT, "%s: unexpected PLY header line '%.40s'", name, w[0]);
}

/* The header, line by line up to "end_header"; h->body is the offset after it. */
static lm_status parse_lines(const uint8_t *d, size_t size, const char *name, ply_header *h)
{
    size_t limit = size < PLY_MAX_HEADER ? size : PLY_MAX_HEADER;
    if (size < 4 || memcmp(d, "ply", 3) != 0 || (d[3] != '\n' && d[3] != '\r'))
        return lm_fail(LM_E_FORMAT, "%s: not a PLY file (no 'ply' line)", name);
    char line[PLY_MAX_LINE];
    int end = 0, seen_format = 0;
    lm_status s = LM_OK;
    for (size_t at = 0; !s && !end;) {
        const uint8_t *nl = at < limit ? memchr(d + at, '\n', limit - at) : NULL;
        size_t len = nl ? (size_t)(nl - d) - at : 0;
        if (!nl || len >= sizeof line || memchr(d + at, '\0', len))
            return lm_fail(LM_E_FORMAT, "%s: bad or unterminated PLY header", name);
        memcpy(line, d + at, len);
        line[len - (len && line[len - 1] == '\r')] = '\0';
        s = at == 0 ? LM_OK : header_line(h, line, &seen_format, &end, name);
        at += len + 1;
        h->body = at;
    }
    if (!s && !seen_format)
        s = lm_fail(LM_E_FORMAT, "%s: the PLY header has no format line", name);
    return s;
}

/* Claimed counts against limits and against the bytes present. */
static lm_status check_counts(const ply_header *h, size_t size, const char *name, uint32_t max_tris)
{
    uint64_t need = 0, left = size - h->body;
    for (uint32_t i = 0; i < h->n_elems; i++) {
        const ply_elem *e = &h->elems[i];
        uint64_t per = 0;
        for (uint32_t k = 0; k < e->n_props; k++)
            per += h->format == PLY_ASCII
                       ? 2
                       : lm_ply_type_size(e->props[k].is_list ? e->props[k].count_type
                                                              : e->props[k].type);
        uint64_t limit =
            e->kind == PLY_ELEM_FACE || e->kind == PLY_ELEM_STRIP ? max_tris : LM_MESH_MAX_VERTS;
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

lm_status lm_ply_header_parse(const uint8_t *d, size_t size, const char *name, uint32_t max_tris,
                              ply_header *h)
{
    memset(h, 0, sizeof *h);
    lm_status s = parse_lines(d, size, name, h);
    return s ? s : check_counts(h, size, name, max_tris);
}
