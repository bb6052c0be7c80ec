/* coordinator/simplify/pm_write.c — writing a progressive mesh (format: SIMPLIFY.md): header,
 * materials with their textures as PNG, parts, the base mesh M0 (live elements by id), the vertex
 * splits from coarse to fine, the end mark. Little-endian, floats as raw bits; atomic. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/image.h"
#include "common/io/atomic_file.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
#include "common/optimizer/binio.h"
#include "coordinator/simplify/pm_internal.h"

static void put_str(lm_bin *b, const char *s)
{
    size_t n = s ? strlen(s) : 0;
    n = n < CO_PM_MAX_STRING ? n : CO_PM_MAX_STRING;
    lm_put_u32(b, (uint32_t)n);
    lm_put_bytes(b, s, n);
}

static void put_floats(lm_bin *b, const float *x, int n)
{
    for (int k = 0; k < n; k++)
        lm_put_f32(b, x[k]);
}

static void put_vert(lm_bin *b, uint32_t id, uint32_t alive, const float pos[3])
{
    lm_put_u32(b, id);
    lm_put_u32(b, alive);
    put_floats(b, pos, 3);
}

static void put_wedge(lm_bin *b, uint32_t id, uint32_t alive, const lm_wedge *w)
{
    lm_put_u32(b, id);
    lm_put_u32(b, alive);
    lm_put_u32(b, w->vertex);
    put_floats(b, w->normal, 3);
    put_floats(b, w->uv, 2);
    put_floats(b, w->color, 4);
}

static void put_tri(lm_bin *b, uint32_t id, uint32_t alive, const lm_tri *t)
{
    lm_put_u32(b, id);
    lm_put_u32(b, alive);
    for (int k = 0; k < 3; k++)
        lm_put_u32(b, t->w[k]);
    lm_put_u32(b, t->material);
    lm_put_u32(b, t->part);
}

static lm_status put_materials(lm_bin *b, const lm_mesh *m)
{
    for (uint32_t i = 0; i < m->n_materials; i++) {
        const lm_material *mat = &m->materials[i];
        put_str(b, mat->name);
        put_floats(b, mat->diffuse, 4);
        put_str(b, mat->texture_path);
        uint8_t *png = NULL;
        size_t len = 0;
        if (mat->texture) {
            lm_status st = lm_image_encode_png_memory(mat->texture, &png, &len);
            if (st)
                return st;
        }
        lm_put_u32(b, (uint32_t)len);
        lm_put_bytes(b, png, len);
        free(png);
    }
    for (uint32_t i = 0; i < m->n_parts; i++)
        put_str(b, m->parts[i].name);
    return LM_OK;
}

/* M0 as a split of live elements: three counts, then the vertices, wedges and triangles. */
static void put_base(lm_bin *b, const lm_mesh *m)
{
    uint32_t nw = 0;
    for (uint32_t w = 0; w < m->n_wedges; w++)
        nw += m->wedge_alive[w];
    lm_put_u32(b, m->live_verts);
    lm_put_u32(b, nw);
    lm_put_u32(b, m->live_tris);
    for (uint32_t v = 0; v < m->n_verts; v++)
        if (m->vert_alive[v])
            put_vert(b, v, 1, m->pos[v]);
    for (uint32_t w = 0; w < m->n_wedges; w++)
        if (m->wedge_alive[w])
            put_wedge(b, w, 1, &m->wedges[w]);
    for (uint32_t t = 0; t < m->n_tris; t++)
        if (m->tri_alive[t])
            put_tri(b, t, 1, &m->tris[t]);
}

static void put_split(lm_bin *b, const co_pm_split *s)
{
    lm_put_u32(b, s->n_verts);
    lm_put_u32(b, s->n_wedges);
    lm_put_u32(b, s->n_tris);
    for (uint32_t i = 0; i < s->n_verts; i++)
        put_vert(b, s->verts[i].id, s->verts[i].alive, s->verts[i].pos);
    for (uint32_t i = 0; i < s->n_wedges; i++)
        put_wedge(b, s->wedges[i].id, s->wedges[i].alive, &s->wedges[i].w);
    for (uint32_t i = 0; i < s->n_tris; i++)
        put_tri(b, s->tris[i].id, s->tris[i].alive, &s->tris[i].t);
}

static lm_status put_all(lm_bin *b, const lm_mesh *base, const co_pm_recorder *r,
                         uint32_t full_verts)
{
    uint32_t n = co_pm_recorder_count(r);
    lm_put_bytes(b, CO_PM_MAGIC, 4);
    uint32_t head[] = {CO_PM_VERSION,    base->attrs,       base->n_verts, base->n_wedges,
                       base->n_tris,     base->n_materials, base->n_parts, n,
                       base->live_verts, full_verts};
    for (size_t i = 0; i < sizeof head / sizeof *head; i++)
        lm_put_u32(b, head[i]);
    lm_status st = put_materials(b, base);
    if (st)
        return st;
    put_base(b, base);
    for (uint32_t i = n; i-- > 0;)
        put_split(b, co_pm_recorder_at(r, i));
    lm_put_bytes(b, CO_PM_END, 4);
    return b->status;
}

lm_status co_pm_write(const char *path, const lm_mesh *base, const co_pm_recorder *r,
                      uint32_t full_verts)
{
    if (full_verts != base->live_verts + co_pm_recorder_count(r))
        return lm_fail(LM_E_INTERNAL, "progressive mesh: %u vertices and %u splits do not make %u",
                       base->live_verts, co_pm_recorder_count(r), full_verts);
    lm_atomic_file f;
    lm_status st = lm_atomic_open(&f, path);
    if (st)
        return st;
    lm_bin b;
    lm_bin_init(&b, f.fp, path);
    st = put_all(&b, base, r, full_verts);
    if (st) {
        lm_atomic_abort(&f);
        return st;
    }
    return lm_atomic_commit(&f);
}
