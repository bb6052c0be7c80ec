/* common/io/mesh_io_guard_dae.c — checks a COLLADA (.dae) file before assimp 5.2 reads it. assimp
 * trusts the file's numbers: it reserves `count` elements up front (an absurd count is an
 * out-of-memory), resizes skin weights to the sum of <vcount>, and reads accessor data at
 * offset + index * stride + param without checking the source array's size (a large stride is a
 * read far outside the heap). This walk reads the XML tags without building a tree and refuses:
 * any count/stride/offset/set attribute larger than the file, a value array that claims more
 * values than its text can hold, a <vcount> summing beyond the file, an accessor whose last
 * element lies outside its source array, and index lists holding anything but integers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/io/mesh_io_internal.h"

typedef struct dae_array {
    char id[64];
    uint64_t count;
    int strings; /* Name_array, IDREF_array...: assimp keeps no numbers for it */
} dae_array;

typedef struct dae_accessor {
    char source[64], owner[64]; /* the array it reads; the <source> it belongs to */
    uint64_t count, stride, offset, params;
} dae_accessor;

typedef struct dae_ref {
    char id[64];
} dae_ref;

typedef struct dae_scan {
    const char *p, *end, *name;
    uint64_t size;
    dae_array *arrays;
    size_t n_arrays, cap_arrays;
    dae_accessor *accessors;
    size_t n_accessors, cap_accessors;
    dae_accessor *open_accessor; /* set between <accessor> and </accessor>: counts <param>s */
    char open_source[64];        /* id of the <source> being read, "" outside one */
    dae_ref *geometry_inputs;    /* sources read as geometry (POSITION, NORMAL, TEXCOORD...) */
    size_t n_inputs, cap_inputs;
} dae_scan;

/* Decimal value saturated at UINT64_MAX; leading blanks and sign skipped like strtoul10. */
static uint64_t parse_u64(const char *s, const char *end)
{
    while (s < end &&
           (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r' || *s == '+' || *s == '-'))
        s++;
    uint64_t v = 0;
    for (; s < end && *s >= '0' && *s <= '9'; s++)
        v = v > (UINT64_MAX - 9) / 10 ? UINT64_MAX : v * 10 + (uint64_t)(*s - '0');
    return v;
}

static int is_name_char(char c)
{
    return c != '\0' && !strchr(" \t\r\n/>=<\"'", c);
}

/* Advance past `text`; the scan ends (p = end) when it is missing. */
static void skip_past(dae_scan *s, const char *text)
{
    size_t n = strlen(text);
    for (; s->p + n <= s->end; s->p++)
        if (!memcmp(s->p, text, n)) {
            s->p += n;
            return;
        }
    s->p = s->end;
}

static int tag_is(const char *name, size_t len, const char *want)
{
    return strlen(want) == len && !memcmp(name, want, len);
}

static int name_ends_with(const char *name, size_t len, const char *suffix)
{
    size_t n = strlen(suffix);
    return len >= n && !memcmp(name + len - n, suffix, n);
}

static void copy_id(char dst[64], const char *v, size_t len)
{
    if (len > 0 && v[0] == '#') {
        v++;
        len--;
    }
    if (len > 63)
        len = 63;
    memcpy(dst, v, len);
    dst[len] = '\0';
}

/* Text between the current position and the next '<': how many values it can hold at most. */
static uint64_t text_capacity(const dae_scan *s)
{
    const char *q = s->p;
    while (q < s->end && *q != '<')
        q++;
    return ((uint64_t)(q - s->p) + 1) / 2;
}

/* Sum of the integers in the text up to the next '<' (saturating). */
static uint64_t text_sum(const dae_scan *s)
{
    uint64_t sum = 0;
    const char *q = s->p;
    while (q < s->end && *q != '<') {
        while (q < s->end && (*q < '0' || *q > '9') && *q != '<')
            q++;
        uint64_t v = parse_u64(q, s->end);
        sum = sum > UINT64_MAX - v ? UINT64_MAX : sum + v;
        while (q < s->end && *q >= '0' && *q <= '9')
            q++;
    }
    return sum;
}

typedef struct dae_tag {
    const char *name;
    size_t len;
    uint64_t count, stride, offset;
    int has_count, has_stride;
    char id[64], source[64], semantic[32];
} dae_tag;

static lm_status read_attribute(dae_scan *s, dae_tag *t)
{
    const char *an = s->p;
    while (s->p < s->end && is_name_char(*s->p))
        s->p++;
    size_t alen = (size_t)(s->p - an);
    while (s->p < s->end && (*s->p == ' ' || *s->p == '\t' || *s->p == '\r' || *s->p == '\n'))
        s->p++;
    if (alen == 0 || s->p >= s->end || *s->p != '=') {
        s->p = s->end; /* not well-formed XML: assimp's parser refuses it */
        return LM_OK;
    }
    s->p++;
    while (s->p < s->end && (*s->p == ' ' || *s->p == '\t' || *s->p == '\r' || *s->p == '\n'))
        s->p++;
    if (s->p >= s->end || (*s->p != '"' && *s->p != '\'')) {
        s->p = s->end;
        return LM_OK;
    }
    char quote = *s->p++;
    const char *v = s->p;
    while (s->p < s->end && *s->p != quote)
        s->p++;
    size_t vlen = (size_t)(s->p - v);
    if (s->p < s->end)
        s->p++;
    uint64_t num = parse_u64(v, v + vlen);
    int numeric = tag_is(an, alen, "count") || tag_is(an, alen, "stride") ||
                  tag_is(an, alen, "offset") || tag_is(an, alen, "set");
    if (numeric && num > s->size)
        return lm_fail(LM_E_FORMAT, "%s: <%.*s %.*s=\"%.*s\"> is larger than the file allows",
                       s->name, (int)(t->len > 40 ? 40 : t->len), t->name, (int)alen, an,
                       (int)(vlen > 20 ? 20 : vlen), v);
    if (tag_is(an, alen, "count"))
        t->count = num, t->has_count = 1;
    else if (tag_is(an, alen, "stride"))
        t->stride = num, t->has_stride = 1;
    else if (tag_is(an, alen, "offset"))
        t->offset = num;
    else if (tag_is(an, alen, "id"))
        copy_id(t->id, v, vlen);
    else if (tag_is(an, alen, "source"))
        copy_id(t->source, v, vlen);
    else if (tag_is(an, alen, "semantic"))
        snprintf(t->semantic, sizeof t->semantic, "%.*s", (int)(vlen > 31 ? 31 : vlen), v);
    return LM_OK;
}

/* Index lists (<p>, <vcount>, <v>, <h>): assimp reads <p> with a loop that only stops at the end
 * of the text and does not advance over a character that is neither part of a number nor a
 * blank (it fills memory with zeros); such text, entities and markup inside are refused. */
static lm_status check_index_text(const dae_scan *s, const dae_tag *t)
{
    const char *q = s->p;
    while (q < s->end && *q != '<') {
        if (!strchr("0123456789+- \t\r\n", *q) || *q == '\0')
            return lm_fail(LM_E_FORMAT, "%s: <%.*s> holds something other than integers", s->name,
                           (int)t->len, t->name);
        q++;
    }
    if (q + 1 < s->end && q[1] != '/')
        return lm_fail(LM_E_FORMAT, "%s: markup inside <%.*s>", s->name, (int)t->len, t->name);
    return LM_OK;
}

static int is_index_list(const dae_tag *t)
{
    return tag_is(t->name, t->len, "p") || tag_is(t->name, t->len, "vcount") ||
           tag_is(t->name, t->len, "v") || tag_is(t->name, t->len, "h");
}

static int is_geometry_semantic(const char *sem)
{
    static const char *const geometric[] = {"POSITION", "NORMAL",   "TEXCOORD",   "COLOR",
                                            "TANGENT",  "BINORMAL", "TEXTANGENT", "TEXBINORMAL"};
    for (size_t i = 0; i < sizeof geometric / sizeof geometric[0]; i++)
        if (!strcmp(sem, geometric[i]))
            return 1;
    return 0;
}

static lm_status record_tag(dae_scan *s, const dae_tag *t)
{
    if (name_ends_with(t->name, t->len, "_array")) {
        uint64_t room = text_capacity(s);
        if (t->count > room)
            return lm_fail(LM_E_FORMAT,
                           "%s: <%.*s id=\"%s\"> claims %llu values but holds at most %llu",
                           s->name, (int)t->len, t->name, t->id, (unsigned long long)t->count,
                           (unsigned long long)room);
        if (!LM_GROW(&s->arrays, &s->cap_arrays, s->n_arrays + 1, 16))
            return lm_fail(LM_E_NOMEM, "%s: out of memory checking the file", s->name);
        dae_array *a = s->arrays;
        memcpy(a[s->n_arrays].id, t->id, sizeof t->id);
        a[s->n_arrays].strings =
            tag_is(t->name, t->len, "Name_array") || tag_is(t->name, t->len, "IDREF_array") ||
            tag_is(t->name, t->len, "SIDREF_array") || tag_is(t->name, t->len, "token_array");
        a[s->n_arrays++].count = t->has_count ? t->count : 0; /* assimp's default */
    } else if (tag_is(t->name, t->len, "accessor")) {
        if (!LM_GROW(&s->accessors, &s->cap_accessors, s->n_accessors + 1, 16))
            return lm_fail(LM_E_NOMEM, "%s: out of memory checking the file", s->name);
        dae_accessor *acc = &s->accessors[s->n_accessors++];
        memcpy(acc->source, t->source, sizeof t->source);
        memcpy(acc->owner, s->open_source, sizeof s->open_source);
        acc->count = t->count;
        acc->stride = t->has_stride ? t->stride : 1;
        acc->offset = t->offset;
        acc->params = 0;
        s->open_accessor = acc;
    } else if (tag_is(t->name, t->len, "source")) {
        memcpy(s->open_source, t->id, sizeof t->id);
    } else if (tag_is(t->name, t->len, "input") && is_geometry_semantic(t->semantic)) {
        if (!LM_GROW(&s->geometry_inputs, &s->cap_inputs, s->n_inputs + 1, 16))
            return lm_fail(LM_E_NOMEM, "%s: out of memory checking the file", s->name);
        memcpy(s->geometry_inputs[s->n_inputs++].id, t->source, sizeof t->source);
    } else if (tag_is(t->name, t->len, "param") && s->open_accessor) {
        s->open_accessor->params++;
    } else if (tag_is(t->name, t->len, "vcount") && text_sum(s) > s->size) {
        return lm_fail(LM_E_FORMAT, "%s: <vcount> adds up to more elements than the file holds",
                       s->name);
    }
    return LM_OK;
}

/* One element tag after '<'. */
static lm_status read_tag(dae_scan *s)
{
    if (s->p < s->end && *s->p == '/') {
        const char *n = ++s->p;
        while (s->p < s->end && is_name_char(*s->p))
            s->p++;
        if (tag_is(n, (size_t)(s->p - n), "accessor"))
            s->open_accessor = NULL;
        if (tag_is(n, (size_t)(s->p - n), "source"))
            s->open_source[0] = '\0';
        skip_past(s, ">");
        return LM_OK;
    }
    dae_tag t = {.name = s->p};
    while (s->p < s->end && is_name_char(*s->p))
        s->p++;
    t.len = (size_t)(s->p - t.name);
    for (;;) {
        while (s->p < s->end && (*s->p == ' ' || *s->p == '\t' || *s->p == '\r' || *s->p == '\n'))
            s->p++;
        if (s->p >= s->end)
            return LM_OK;
        if (*s->p == '>' || *s->p == '/') {
            int self_closing = *s->p == '/';
            skip_past(s, ">");
            lm_status st = record_tag(s, &t);
            if (self_closing && tag_is(t.name, t.len, "accessor"))
                s->open_accessor = NULL;
            if (st == LM_OK && !self_closing && is_index_list(&t))
                st = check_index_text(s, &t);
            return st;
        }
        lm_status st = read_attribute(s, &t);
        if (st != LM_OK)
            return st;
    }
}

static int read_as_geometry(const dae_scan *s, const char *source_id)
{
    for (size_t i = 0; i < s->n_inputs; i++)
        if (source_id[0] && !strcmp(s->geometry_inputs[i].id, source_id))
            return 1;
    return 0;
}

/* offset + (count - 1) * stride + width <= the array's count, without overflow. */
static int accessor_fits(const dae_accessor *a, uint64_t have)
{
    uint64_t width = a->params > a->stride ? a->params : a->stride;
    return width <= have && a->offset <= have - width &&
           a->count - 1 <= (have - width - a->offset) / a->stride;
}

/* Every element an accessor can address must lie inside every array of that id (assimp keeps
 * one of duplicates), and geometry must not be read from an array of strings. */
static lm_status check_accessor(const dae_scan *s, const dae_accessor *a)
{
    if (a->count == 0)
        return LM_OK;
    if (a->stride == 0)
        return lm_fail(LM_E_FORMAT, "%s: accessor of \"%s\" has stride 0", s->name, a->source);
    int geometry = read_as_geometry(s, a->owner);
    for (size_t i = 0; i < s->n_arrays; i++) {
        const dae_array *arr = &s->arrays[i];
        if (strcmp(arr->id, a->source) != 0)
            continue; /* unresolved sources are refused by assimp itself */
        if (arr->strings && geometry)
            return lm_fail(LM_E_FORMAT, "%s: geometry source \"%s\" reads an array of names",
                           s->name, a->owner);
        if (!accessor_fits(a, arr->count))
            return lm_fail(LM_E_FORMAT,
                           "%s: accessor of %llu x %llu values reaches past the end of \"%s\" "
                           "(%llu values)",
                           s->name, (unsigned long long)a->count, (unsigned long long)a->stride,
                           a->source, (unsigned long long)arr->count);
    }
    return LM_OK;
}

lm_status lm_io_guard_dae(const uint8_t *data, size_t size, const char *name)
{
    dae_scan s = {
        .p = (const char *)data, .end = (const char *)data + size, .name = name, .size = size};
    lm_status st = LM_OK;
    while (st == LM_OK && s.p < s.end) {
        if (*s.p++ != '<')
            continue;
        if (s.end - s.p >= 3 && !memcmp(s.p, "!--", 3))
            skip_past(&s, "-->");
        else if (s.end - s.p >= 8 && !memcmp(s.p, "![CDATA[", 8))
            skip_past(&s, "]]>");
        else if (s.p < s.end && (*s.p == '?' || *s.p == '!'))
            skip_past(&s, ">");
        else
            st = read_tag(&s);
    }
    for (size_t i = 0; st == LM_OK && i < s.n_accessors; i++)
        st = check_accessor(&s, &s.accessors[i]);
    free(s.arrays);
    free(s.accessors);
    free(s.geometry_inputs);
    return st;
}
