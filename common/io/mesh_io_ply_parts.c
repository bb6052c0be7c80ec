/* common/io/mesh_io_ply_parts.c — the part names a PLY file can carry. PLY has no groups or
 * objects; lumesh's writer puts each part's faces together and names the runs in header comments,
 * "comment lumesh part FIRST COUNT NAME" (FIRST and COUNT in faces, NAME to the end of the line),
 * which other readers skip as comments and lumesh's loader reads back. */
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io_internal.h"

#define PLY_PARTS_MAX_HEADER ((size_t)1 << 20)
#define PLY_PART_TAG "comment lumesh part "

void lm_io_ply_write_part(FILE *fp, uint64_t first, uint64_t count, const char *name)
{
    fprintf(fp, PLY_PART_TAG "%llu %llu ", (unsigned long long)first, (unsigned long long)count);
    for (const unsigned char *c = (const unsigned char *)name; *c; c++)
        fputc(*c < ' ' || *c == 127 ? '_' : *c, fp);
    fputc('\n', fp);
}

/* One "comment lumesh part" line (without its tag, `n` bytes) into *r; 0 if it is not one. */
static int parse_part(const char *line, size_t n, lm_face_part *r)
{
    char buf[LM_PART_NAME_MAX + 64];
    if (n >= sizeof buf)
        n = sizeof buf - 1;
    memcpy(buf, line, n);
    buf[n] = '\0';
    unsigned long long first, count;
    int used = 0;
    if (sscanf(buf, "%llu %llu %n", &first, &count, &used) != 2 || used == 0)
        return 0;
    r->first = first;
    r->count = count;
    snprintf(r->name, sizeof r->name, "%s", buf + used);
    size_t len = strlen(r->name);
    while (len && (r->name[len - 1] == '\r' || r->name[len - 1] == ' '))
        r->name[--len] = '\0';
    return 1;
}

static lm_status push_part(lm_face_part **out, uint32_t *n, const lm_face_part *r)
{
    lm_face_part *a = realloc(*out, ((size_t)*n + 1) * sizeof *a);
    if (!a)
        return lm_fail(LM_E_NOMEM, "out of memory reading PLY part names");
    a[(*n)++] = *r;
    *out = a;
    return LM_OK;
}

lm_status lm_io_ply_read_parts(const uint8_t *data, size_t size, lm_face_part **out, uint32_t *n)
{
    *out = NULL;
    *n = 0;
    const char *p = (const char *)data,
               *end = p + (size < PLY_PARTS_MAX_HEADER ? size : PLY_PARTS_MAX_HEADER);
    size_t tag = strlen(PLY_PART_TAG);
    lm_status s = LM_OK;
    while (!s && p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        size_t len = (size_t)((nl ? nl : end) - p);
        if (len >= 10 && !strncmp(p, "end_header", 10))
            break;
        lm_face_part r;
        if (len > tag && !strncmp(p, PLY_PART_TAG, tag) && parse_part(p + tag, len - tag, &r))
            s = push_part(out, n, &r);
        p += len + 1;
    }
    if (s) {
        free(*out);
        *out = NULL;
        *n = 0;
    }
    return s;
}
