/* worker/render/cpu/cpu_texture.c — mip pyramids (box-filtered in integers, texels packed),
 * trilinear sampling of four points at a time with repeat wrapping (cpu_sample_lanes.h), and the
 * CPU backend's material tables (see cpu_texture.h; filled as the GL one is, shared/materials.h).
 */
#include "worker/render/cpu/cpu_texture.h"

#include <stdlib.h>
#include <string.h>

#include "worker/render/shared/materials.h"

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

/* Sampling at four lanes (cpu_sample_lanes.h; the shading code has its own instantiations). */
#define WK_W 4
#define WK_VF v4f
#define WK_VI v4i
#define WK_L(name) name##_w4
#include "worker/render/cpu/cpu_sample_lanes.h"

void wk_cpu_texture_sample4(const wk_cpu_texture *t, v4f u, v4f v, v4i lod, v4f out[3])
{
    sample_w4(t, u, v, lod, out);
}

void wk_cpu_materials_free(wk_cpu_materials *t)
{
    for (uint32_t i = 0; t->tex && i < t->n; i++)
        wk_cpu_texture_destroy(t->tex[i]);
    for (uint32_t i = 0; t->nrm && i < t->n; i++)
        wk_cpu_texture_destroy(t->nrm[i]);
    free(t->tex);
    free(t->nrm);
    free(t->diffuse);
    memset(t, 0, sizeof *t);
}

static lm_status make_texture(const lm_image *img, void *handle)
{
    return wk_cpu_texture_create(img, handle);
}

lm_status wk_cpu_materials_set(wk_cpu_materials *t, const lm_material *mats, uint32_t n)
{
    wk_cpu_materials_free(t);
    void *tex;
    lm_status st =
        wk_materials_fill(mats, n, sizeof *t->tex, make_texture, &t->n, &t->diffuse, &tex);
    t->tex = tex;
    void *nrm = NULL;
    if (st == LM_OK)
        st = wk_materials_fill_normal_maps(mats, n, sizeof *t->nrm, make_texture, &nrm);
    t->nrm = nrm;
    if (st != LM_OK)
        wk_cpu_materials_free(t);
    return st;
}
