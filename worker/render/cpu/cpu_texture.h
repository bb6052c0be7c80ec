/* worker/render/cpu/cpu_texture.h — the CPU backend's materials: diffuse colours and textures as
 * mip pyramids (RGBA8 box-filtered in integers down to 1x1, bottom row first so that uv (0,0) is
 * the image's bottom-left corner as in GL, each texel packed as r | g << 8 | b << 16 | a << 24),
 * sampled four points at a time with repeat wrapping and trilinear filtering in IEEE float lanes
 * (the level's weight in 1/256): the same bits on every host. */
#ifndef LM_WORKER_CPU_TEXTURE_H
#define LM_WORKER_CPU_TEXTURE_H

#include <stdint.h>

#include "common/error.h"
#include "common/image.h"
#include "common/mesh.h"

#include "worker/render/cpu/cpu_simd.h"

#define WK_CPU_TEX_LEVELS 16

typedef struct wk_cpu_level {
    int width, height;
    const uint32_t *texel; /* width * height packed texels, bottom row first */
} wk_cpu_level;

typedef struct wk_cpu_texture {
    int n_levels;
    wk_cpu_level level[WK_CPU_TEX_LEVELS];
    uint32_t *data;                                              /* all levels */
    int32_t width[WK_CPU_TEX_LEVELS], height[WK_CPU_TEX_LEVELS]; /* the levels' sizes, and */
    int32_t offset[WK_CPU_TEX_LEVELS];                           /* where they start in data */
} wk_cpu_texture;

/* The pyramid of an RGBA8 image (rows top first, as lm_image holds them). */
lm_status wk_cpu_texture_create(const lm_image *img, wk_cpu_texture **out);
void wk_cpu_texture_destroy(wk_cpu_texture *t);

/* Texture colour at four points (u, v) with levels of detail lod (log2 of the texel footprint,
 * 8 fractional bits; <= 0 magnifies: bilinear on level 0), per channel 0..255 in out[channel]
 * lane by lane. u and v may be any finite numbers (repeat); others read as 0. */
void wk_cpu_texture_sample4(const wk_cpu_texture *t, v4f u, v4f v, v4i lod, v4f out[3]);

/* A material table: diffuse colours, textures (NULL where untextured) and tangent-space normal
 * maps (nrm NULL, or NULL where a material has none). */
typedef struct wk_cpu_materials {
    uint32_t n;
    float (*diffuse)[4];
    wk_cpu_texture **tex;
    wk_cpu_texture **nrm;
} wk_cpu_materials;

/* Replace the table's contents with copies of mats (textures become pyramids). */
lm_status wk_cpu_materials_set(wk_cpu_materials *t, const lm_material *mats, uint32_t n);
void wk_cpu_materials_free(wk_cpu_materials *t);

#endif
