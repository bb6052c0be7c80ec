/* worker/cpu_texture.c — integer mip pyramids, trilinear sampling with repeat wrapping, and the
 * CPU backend's material tables (see cpu_texture.h). */
#include "worker/cpu_texture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Level l + 1 from level l: each texel the rounded mean of the 2x2 block above it (the last row or
 * column repeated where a side is odd or already 1). */
static void downsample(const wk_cpu_level *src, uint8_t *dst, int w, int h)
{
    for (int y = 0; y < h; y++) {
        int y0 = 2 * y < src->height ? 2 * y : src->height - 1;
        int y1 = y0 + 1 < src->height ? y0 + 1 : y0;
        for (int x = 0; x < w; x++) {
            int x0 = 2 * x < src->width ? 2 * x : src->width - 1;
            int x1 = x0 + 1 < src->width ? x0 + 1 : x0;
            const uint8_t *a = src->rgba + ((size_t)y0 * src->width + x0) * 4;
            const uint8_t *b = src->rgba + ((size_t)y0 * src->width + x1) * 4;
            const uint8_t *c = src->rgba + ((size_t)y1 * src->width + x0) * 4;
            const uint8_t *d = src->rgba + ((size_t)y1 * src->width + x1) * 4;
            for (int k = 0; k < 4; k++)
                dst[((size_t)y * w + x) * 4 + k] = (uint8_t)((a[k] + b[k] + c[k] + d[k] + 2) >> 2);
        }
    }
}

lm_status wk_cpu_texture_create(const lm_image *img, wk_cpu_texture **out)
{
    if (img->channels != 4 || !img->pixels || img->width < 1 || img->height < 1)
        return lm_fail(LM_E_INVALID, "texture is not RGBA8 (%d channels)", img->channels);
    wk_cpu_texture *t = calloc(1, sizeof *t);
    if (!t)
        return lm_fail(LM_E_NOMEM, "out of memory for a texture");
    size_t total = 0;
    int w = img->width, h = img->height, n = 0;
    for (;; n++) {
        t->level[n].width = w;
        t->level[n].height = h;
        total += (size_t)w * h * 4;
        if ((w == 1 && h == 1) || n + 1 == WK_CPU_TEX_LEVELS)
            break;
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
    }
    t->n_levels = n + 1;
    t->data = malloc(total);
    if (!t->data) {
        free(t);
        return lm_fail(LM_E_NOMEM, "out of memory for a %dx%d texture pyramid", img->width,
                       img->height);
    }
    size_t row = (size_t)img->width * 4, off = 0;
    for (int y = 0; y < img->height; y++) /* bottom row first */
        memcpy(t->data + row * y, img->pixels + row * (img->height - 1 - y), row);
    for (int l = 0; l < t->n_levels; l++) {
        wk_cpu_level *lv = &t->level[l];
        lv->rgba = t->data + off;
        if (l > 0)
            downsample(&t->level[l - 1], t->data + off, lv->width, lv->height);
        off += (size_t)lv->width * lv->height * 4;
    }
    *out = t;
    return LM_OK;
}

void wk_cpu_texture_destroy(wk_cpu_texture *t)
{
    if (!t)
        return;
    free(t->data);
    free(t);
}

/* u - floor(u) in [0, 1]; 0 for huge (integral) or non-finite u. */
static float fraction(float u)
{
    if (!(fabsf(u) < 8388608.0f))
        return 0.0f;
    float i = (float)(int32_t)u;
    return u - (i > u ? i - 1.0f : i);
}

/* Texel column (or row) pair and 8-bit weight of the second for fraction f on a side of size
 * texels, repeating: packed as first << 8 | weight, the second in *i1. */
static int wrap(float f, int size, int *i1)
{
    int32_t s = (int32_t)((f * (float)size + 0.5f) * 256.0f); /* >= 128: floor, a texel ahead */
    int i0 = (int)(s >> 8) - 1, frac = (int)(s & 255);
    i0 += i0 < 0 ? size : i0 >= size ? -size : 0;
    *i1 = i0 + 1 == size ? 0 : i0 + 1;
    return frac | i0 << 8;
}

/* Bilinear sample of one level at fractions (fu, fv), per channel in units of 255 << 16: the
 * four texels weighted by the products of the 8-bit weights (sum 2^16). */
static void bilinear(const wk_cpu_level *lv, float fu, float fv, uint32_t out[3])
{
    int x1, y1, xs = wrap(fu, lv->width, &x1), ys = wrap(fv, lv->height, &y1);
    int x0 = xs >> 8, y0 = ys >> 8;
    uint32_t fx = (uint32_t)(xs & 255), fy = (uint32_t)(ys & 255);
    uint32_t w00 = (256 - fx) * (256 - fy), w10 = fx * (256 - fy), w01 = (256 - fx) * fy;
    uint32_t w11 = fx * fy;
    const uint8_t *r0 = lv->rgba + (size_t)y0 * lv->width * 4;
    const uint8_t *r1 = lv->rgba + (size_t)y1 * lv->width * 4;
    const uint8_t *a = r0 + x0 * 4, *b = r0 + x1 * 4, *c = r1 + x0 * 4, *d = r1 + x1 * 4;
    for (int k = 0; k < 3; k++)
        out[k] = a[k] * w00 + b[k] * w10 + c[k] * w01 + d[k] * w11;
}

void wk_cpu_texture_sample(const wk_cpu_texture *t, float u, float v, int lod, uint32_t out[3])
{
    int last = t->n_levels - 1, d = lod > 0 ? lod >> 8 : 0;
    float fu = fraction(u), fv = fraction(v);
    if (lod <= 0 || d >= last) {
        bilinear(&t->level[lod <= 0 ? 0 : last], fu, fv, out);
        for (int k = 0; k < 3; k++)
            out[k] <<= 8;
        return;
    }
    uint32_t a[3], b[3], f = (uint32_t)(lod & 255);
    bilinear(&t->level[d], fu, fv, a);
    bilinear(&t->level[d + 1], fu, fv, b);
    for (int k = 0; k < 3; k++)
        out[k] = a[k] * (256 - f) + b[k] * f;
}

void wk_cpu_materials_free(wk_cpu_materials *t)
{
    for (uint32_t i = 0; t->tex && i < t->n; i++)
        wk_cpu_texture_destroy(t->tex[i]);
    free(t->tex);
    free(t->diffuse);
    memset(t, 0, sizeof *t);
}

lm_status wk_cpu_materials_set(wk_cpu_materials *t, const lm_material *mats, uint32_t n)
{
    wk_cpu_materials_free(t);
    t->tex = calloc(n ? n : 1, sizeof *t->tex);
    t->diffuse = calloc(n ? n : 1, sizeof *t->diffuse);
    if (!t->tex || !t->diffuse) {
        wk_cpu_materials_free(t);
        return lm_fail(LM_E_NOMEM, "out of memory for %u materials", n);
    }
    t->n = n;
    lm_status st = LM_OK;
    for (uint32_t i = 0; st == LM_OK && i < n; i++) {
        memcpy(t->diffuse[i], mats[i].diffuse, sizeof t->diffuse[i]);
        if (mats[i].texture)
            st = wk_cpu_texture_create(mats[i].texture, &t->tex[i]);
    }
    if (st != LM_OK)
        wk_cpu_materials_free(t);
    return st;
}
