/* worker/cpu_texture.c — mip pyramids (box-filtered in integers, texels packed), trilinear
 * sampling of four points at a time with repeat wrapping, and the CPU backend's material tables
 * (see cpu_texture.h). */
#include "worker/cpu_texture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Level l + 1 (w x h, into dst) from level l (src bytes, above's size): each texel the rounded
 * mean of the 2x2 block above it (the last row or column repeated where a side is odd or 1). */
static void downsample(const wk_cpu_level *above, const uint8_t *src, uint8_t *dst, int w, int h)
{
    for (int y = 0; y < h; y++) {
        int y0 = 2 * y < above->height ? 2 * y : above->height - 1;
        int y1 = y0 + 1 < above->height ? y0 + 1 : y0;
        for (int x = 0; x < w; x++) {
            int x0 = 2 * x < above->width ? 2 * x : above->width - 1;
            int x1 = x0 + 1 < above->width ? x0 + 1 : x0;
            const uint8_t *a = src + ((size_t)y0 * above->width + x0) * 4;
            const uint8_t *b = src + ((size_t)y0 * above->width + x1) * 4;
            const uint8_t *c = src + ((size_t)y1 * above->width + x0) * 4;
            const uint8_t *d = src + ((size_t)y1 * above->width + x1) * 4;
            for (int k = 0; k < 4; k++)
                dst[((size_t)y * w + x) * 4 + k] = (uint8_t)((a[k] + b[k] + c[k] + d[k] + 2) >> 2);
        }
    }
}

/* The sizes of the pyramid's levels (down to 1x1); returns how many texels in all. */
static size_t plan_levels(wk_cpu_texture *t, int w, int h)
{
    size_t total = 0;
    int n = 0;
    for (;; n++) {
        t->width[n] = w;
        t->height[n] = h;
        t->offset[n] = (int32_t)total;
        total += (size_t)w * h;
        if ((w == 1 && h == 1) || n + 1 == WK_CPU_TEX_LEVELS)
            break;
        w = w > 1 ? w / 2 : 1;
        h = h > 1 ? h / 2 : 1;
    }
    t->n_levels = n + 1;
    return total;
}

/* The byte pyramid (levels one after the other), packed into t->data. */
static void pack_levels(wk_cpu_texture *t, const uint8_t *bytes)
{
    for (int l = 0; l < t->n_levels; l++) {
        size_t n = (size_t)t->width[l] * t->height[l];
        const uint8_t *src = bytes + (size_t)t->offset[l] * 4;
        uint32_t *dst = t->data + t->offset[l];
        for (size_t i = 0; i < n; i++)
            dst[i] = (uint32_t)src[4 * i] | (uint32_t)src[4 * i + 1] << 8 |
                     (uint32_t)src[4 * i + 2] << 16 | (uint32_t)src[4 * i + 3] << 24;
        t->level[l] = (wk_cpu_level){t->width[l], t->height[l], dst};
    }
}

lm_status wk_cpu_texture_create(const lm_image *img, wk_cpu_texture **out)
{
    if (img->channels != 4 || !img->pixels || img->width < 1 || img->height < 1)
        return lm_fail(LM_E_INVALID, "texture is not RGBA8 (%d channels)", img->channels);
    wk_cpu_texture *t = calloc(1, sizeof *t);
    if (!t)
        return lm_fail(LM_E_NOMEM, "out of memory for a texture");
    size_t total = plan_levels(t, img->width, img->height);
    uint8_t *bytes = malloc(total * 4);
    t->data = malloc(total * sizeof *t->data);
    if (!bytes || !t->data) {
        free(bytes);
        free(t->data);
        free(t);
        return lm_fail(LM_E_NOMEM, "out of memory for a %dx%d texture pyramid", img->width,
                       img->height);
    }
    size_t row = (size_t)img->width * 4;
    for (int y = 0; y < img->height; y++) /* bottom row first */
        memcpy(bytes + row * y, img->pixels + row * (img->height - 1 - y), row);
    for (int l = 1; l < t->n_levels; l++) {
        wk_cpu_level above = {t->width[l - 1], t->height[l - 1], NULL};
        downsample(&above, bytes + (size_t)t->offset[l - 1] * 4, bytes + (size_t)t->offset[l] * 4,
                   t->width[l], t->height[l]);
    }
    pack_levels(t, bytes);
    free(bytes);
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

/* u - floor(u) in [0, 1] per lane; 0 for huge (integral) or non-finite u. */
static v4f fraction4(v4f u)
{
    v4i ok = (u < wk_v4_splat(8388608.0f)) & (u > wk_v4_splat(-8388608.0f)); /* false: NaN */
    u = wk_v4_select(ok, u, wk_v4_splat(0.0f));
    v4f i = __builtin_convertvector(__builtin_convertvector(u, v4i), v4f);
    return u - wk_v4_select(i > u, i - 1.0f, i);
}

/* Texel pairs and weights along one axis: s = f size - 1/2, texel floor(s) and the next one,
 * repeating, and the weight of the next one. */
static void axis4(v4f f, v4i size, v4i *i0, v4i *i1, v4f *w)
{
    v4f s = f * __builtin_convertvector(size, v4f) - 0.5f; /* in [-0.5, size - 0.5] */
    v4i fl = __builtin_convertvector(s + 1.0f, v4i) - 1;   /* floor: s + 1 > 0 */
    *w = s - __builtin_convertvector(fl, v4f);             /* in [0, 1) */
    fl += (fl < 0) & size;                                 /* -1 -> size - 1 */
    fl -= (fl >= size) & size;
    *i0 = fl;
    *i1 = (fl + 1) & ~(fl + 1 == size); /* size -> 0 */
}

/* The bilinear mix of four texels a lane (texel[0], [1] along x, [2], [3] the row above) with the
 * weights of the second of each pair, channels 0..255. */
static void lerp_texels(const v4i texel[4], v4f wx, v4f wy, v4f out[3])
{
    for (int ch = 0; ch < 3; ch++) {
        v4f v[4];
        for (int c = 0; c < 4; c++)
            v[c] = __builtin_convertvector((texel[c] >> (8 * ch)) & 255, v4f);
        v4f lo = v[0] + (v[1] - v[0]) * wx, hi = v[2] + (v[3] - v[2]) * wx;
        out[ch] = lo + (hi - lo) * wy; /* lerps: exact where the texels agree */
    }
}

/* Bilinear samples of level lv[k] at lane k (fractions fu, fv), channels 0..255. */
static void bilinear4(const wk_cpu_texture *t, v4i lv, v4f fu, v4f fv, v4f out[3])
{
    v4i w, h, base;
    for (int k = 0; k < 4; k++) {
        w[k] = t->width[lv[k]];
        h[k] = t->height[lv[k]];
        base[k] = t->offset[lv[k]];
    }
    v4i x0, x1, y0, y1;
    v4f wx, wy;
    axis4(fu, w, &x0, &x1, &wx);
    axis4(fv, h, &y0, &y1, &wy);
    v4i r0 = base + y0 * w, r1 = base + y1 * w, at[4] = {r0 + x0, r0 + x1, r1 + x0, r1 + x1};
    v4i texel[4];
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < 4; k++)
            texel[c][k] = (int32_t)t->data[at[c][k]];
    lerp_texels(texel, wx, wy, out);
}

/* bilinear4 where every lane reads level l (neighbouring pixels nearly always do): the level's
 * size and place loaded once, the same bits. */
static void bilinear4_at(const wk_cpu_texture *t, int l, v4f fu, v4f fv, v4f out[3])
{
    const int32_t w = t->width[l], h = t->height[l];
    const v4i ws = {w, w, w, w}, hs = {h, h, h, h};
    v4i x0, x1, y0, y1;
    v4f wx, wy;
    axis4(fu, ws, &x0, &x1, &wx);
    axis4(fv, hs, &y0, &y1, &wy);
    const uint32_t *data = t->data + t->offset[l];
    v4i texel[4];
    for (int k = 0; k < 4; k++) {
        const uint32_t *r0 = data + (size_t)y0[k] * (size_t)w,
                       *r1 = data + (size_t)y1[k] * (size_t)w;
        texel[0][k] = (int32_t)r0[x0[k]];
        texel[1][k] = (int32_t)r0[x1[k]];
        texel[2][k] = (int32_t)r1[x0[k]];
        texel[3][k] = (int32_t)r1[x1[k]];
    }
    lerp_texels(texel, wx, wy, out);
}

static int same_lanes(v4i a)
{
    return a[0] == a[1] && a[0] == a[2] && a[0] == a[3];
}

void wk_cpu_texture_sample4(const wk_cpu_texture *t, v4f u, v4f v, v4i lod, v4f out[3])
{
    const v4i last = {t->n_levels - 1, t->n_levels - 1, t->n_levels - 1, t->n_levels - 1};
    v4i mag = lod <= 0, d = (lod >> 8) & ~mag;
    v4i top = d >= last;
    d = (d & ~top) | (last & top);
    v4i d1 = d + 1;
    d1 = (d1 & ~(d1 > last)) | (last & (d1 > last));
    v4f f = __builtin_convertvector(lod & 255 & ~mag & ~top, v4f) * (1.0f / 256.0f);
    v4f fu = fraction4(u), fv = fraction4(v), a[3], b[3];
    v4i flat = f == 0.0f; /* the finer level alone: a + (b - a) 0 is a, bit for bit */
    int one_level = same_lanes(d), fine_only = flat[0] & flat[1] & flat[2] & flat[3];
    if (one_level)
        bilinear4_at(t, d[0], fu, fv, a);
    else
        bilinear4(t, d, fu, fv, a);
    if (fine_only) {
        for (int ch = 0; ch < 3; ch++)
            out[ch] = a[ch];
        return;
    }
    if (one_level)
        bilinear4_at(t, d1[0], fu, fv, b);
    else
        bilinear4(t, d1, fu, fv, b);
    for (int ch = 0; ch < 3; ch++)
        out[ch] = a[ch] + (b[ch] - a[ch]) * f;
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
