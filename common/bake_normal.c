/* common/bake_normal.c — the normal map's and the colour transfer's sinks on the shared texel walk
 * (see bake_normal.h, bake_walk.h). */
#include "common/bake_normal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The original's unit normal at barycentrics b of its triangle t: its wedges' normals
 * interpolated, the face normal where the mesh has none or they cancel. */
static void orig_normal(const lm_mesh *m, uint32_t t, const double b[3], double n[3])
{
    n[0] = n[1] = n[2] = 0.0;
    if (m->attrs & LM_ATTR_NORMAL)
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++)
                n[a] += b[k] * m->wedges[m->tris[t].w[k]].normal[a];
    if (lm_bake_unit3(n))
        return;
    const float *p0 = m->pos[lm_tri_vertex(m, t, 0)], *p1 = m->pos[lm_tri_vertex(m, t, 1)],
                *p2 = m->pos[lm_tri_vertex(m, t, 2)];
    double e1[3], e2[3];
    for (int a = 0; a < 3; a++)
        e1[a] = (double)p1[a] - p0[a], e2[a] = (double)p2[a] - p0[a];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    if (!lm_bake_unit3(n))
        n[0] = 0.0, n[1] = 0.0, n[2] = 1.0;
}

static uint8_t encode(double x)
{
    double v = floor((x * 0.5 + 0.5) * 255.0 + 0.5);
    return (uint8_t)(v < 0.0 ? 0.0 : v > 255.0 ? 255.0 : v);
}

static void flat(uint8_t *px)
{
    px[0] = 128, px[1] = 128, px[2] = 255, px[3] = 255;
}

static void normal_texel(void *arg, const lm_bake_point *pt, size_t i)
{
    uint8_t *px = ((lm_image *)arg)->pixels + 4 * i;
    double n[3];
    flat(px);
    if (!pt->framed)
        return;
    orig_normal(pt->orig, pt->hit, pt->hb, n);
    px[0] = encode(lm_bake_dot3(n, pt->f)), px[1] = encode(lm_bake_dot3(n, pt->f + 3)),
    px[2] = encode(lm_bake_dot3(n, pt->f + 6));
}

void lm_bake_normal_sink(lm_image *img, lm_bake_sink *sink)
{
    for (size_t i = 0; i < (size_t)img->width * img->height; i++)
        flat(img->pixels + 4 * i);
    sink->texel = normal_texel;
    sink->arg = img;
}

/* Texel i of atlas triangle pt->tri from `from`'s texture. */
static void transfer_texel(void *arg, const lm_bake_point *pt, size_t i)
{
    const lm_bake_colour *c = arg;
    uint32_t mat = pt->res->tris[pt->tri].material;
    const lm_mesh *from = c->from;
    if (pt->hit == LM_NONE || !c->out[mat] || mat >= from->n_materials ||
        !from->materials[mat].texture)
        return;
    double uv[2] = {0.0, 0.0}, px[4];
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 2; a++)
            uv[a] += pt->b[k] * from->wedges[from->tris[c->from_tri[pt->tri]].w[k]].uv[a];
    lm_bake_sample(from->materials[mat].texture, uv[0], uv[1], px);
    for (int ch = 0; ch < 4; ch++)
        c->out[mat]->pixels[4 * i + ch] = (uint8_t)floor(px[ch] + 0.5);
}

lm_status lm_bake_transfer_begin(const lm_mesh *res, int size, lm_bake_colour *c,
                                 lm_bake_sink *sink)
{
    const lm_mesh *from = c->from;
    c->from_tri = malloc(((size_t)res->n_tris + 1) * sizeof *c->from_tri);
    if (!c->from_tri)
        return lm_fail(LM_E_NOMEM, "out of memory for a colour transfer");
    uint32_t i = 0;
    for (uint32_t t = 0; t < from->n_tris && i < res->n_tris; t++)
        if (from->tri_alive[t])
            c->from_tri[i++] = t;
    if (i != res->n_tris || from->live_tris != res->live_tris)
        return lm_fail(LM_E_INTERNAL, "a colour transfer from a mesh that is not the atlas's");
    for (uint32_t m = 0; m < res->n_materials && m < from->n_materials; m++) {
        if (!from->materials[m].texture)
            continue;
        lm_status st = lm_image_create(size, size, &c->out[m]);
        if (st != LM_OK)
            return st;
    }
    sink->texel = transfer_texel;
    sink->arg = c;
    return LM_OK;
}

void lm_bake_transfer_end(lm_bake_colour *c)
{
    free(c->from_tri);
    c->from_tri = NULL;
}

lm_status lm_bake_normal(const lm_mesh *orig, const lm_mesh *res, int size, lm_bake_colour *colour,
                         lm_image **out, lm_bake_stats *stats)
{
    *out = NULL;
    lm_image *img = NULL, **imgs = NULL;
    lm_bake_sink sinks[2];
    lm_status st = lm_image_create(size, size, &img);
    if (st == LM_OK) {
        imgs = calloc((size_t)res->n_materials + 1, sizeof *imgs);
        st = imgs ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for a bake's gutters");
    }
    if (st == LM_OK)
        lm_bake_normal_sink(img, &sinks[0]), imgs[0] = img;
    if (st == LM_OK && colour)
        st = lm_bake_transfer_begin(res, size, colour, &sinks[1]);
    for (uint32_t m = 0; st == LM_OK && colour && m < res->n_materials; m++)
        imgs[1 + m] = colour->out[m];
    if (st == LM_OK)
        st = lm_bake_walk(orig, res, size, sinks, colour ? 2 : 1, imgs,
                          colour ? 1 + (int)res->n_materials : 1, stats);
    if (colour)
        lm_bake_transfer_end(colour);
    free(imgs);
    if (st != LM_OK) {
        lm_image_destroy(img);
        return st;
    }
    *out = img;
    return LM_OK;
}
