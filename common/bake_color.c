/* common/bake_color.c — the base-colour map's sink on the shared texel walk (see bake_color.h). */
#include "common/bake_color.h"

#include <math.h>
#include <string.h>

void lm_bake_color_at(const lm_mesh *m, uint32_t t, const double b[3], double rgb[3])
{
    const lm_material *mat =
        m->tris[t].material < m->n_materials ? &m->materials[m->tris[t].material] : NULL;
    double c[3] = {1.0, 1.0, 1.0};
    if (mat)
        for (int ch = 0; ch < 3; ch++)
            c[ch] = mat->diffuse[ch];
    if (mat && mat->texture) {
        double uv[2] = {0.0, 0.0}, px[4];
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++)
                uv[a] += b[k] * m->wedges[m->tris[t].w[k]].uv[a];
        lm_bake_sample(mat->texture, uv[0], uv[1], px);
        for (int ch = 0; ch < 3; ch++)
            c[ch] *= px[ch] / 255.0;
    }
    for (int ch = 0; (m->attrs & LM_ATTR_COLOR) && ch < 3; ch++) {
        double v = 0.0;
        for (int k = 0; k < 3; k++)
            v += b[k] * m->wedges[m->tris[t].w[k]].color[ch];
        c[ch] *= v;
    }
    memcpy(rgb, c, sizeof c);
}

static uint8_t to_byte(double x)
{
    double v = floor(x * 255.0 + 0.5);
    return (uint8_t)(v < 0.0 ? 0.0 : v > 255.0 ? 255.0 : v);
}

static void color_texel(void *arg, const lm_bake_point *pt, size_t i)
{
    uint8_t *px = ((lm_image *)arg)->pixels + 4 * i;
    double rgb[3];
    if (pt->hit == LM_NONE)
        return;
    lm_bake_color_at(pt->orig, pt->hit, pt->hb, rgb);
    for (int ch = 0; ch < 3; ch++)
        px[ch] = to_byte(rgb[ch]);
    px[3] = 255;
}

void lm_bake_color_sink(lm_image *img, lm_bake_sink *sink)
{
    memset(img->pixels, 255, (size_t)img->width * img->height * 4);
    sink->texel = color_texel;
    sink->arg = img;
}

lm_status lm_bake_color(const lm_mesh *orig, const lm_mesh *res, int size, lm_image **out,
                        lm_bake_stats *stats)
{
    lm_image *img = NULL;
    lm_bake_sink sink;
    *out = NULL;
    lm_status st = lm_image_create(size, size, &img);
    if (st == LM_OK) {
        lm_bake_color_sink(img, &sink);
        st = lm_bake_walk(orig, res, size, &sink, 1, &img, 1, stats);
    }
    if (st != LM_OK) {
        lm_image_destroy(img);
        return st;
    }
    *out = img;
    return LM_OK;
}
