/* worker/cpu_texture.h — the CPU backend's materials: diffuse colours and textures as integer mip
 * pyramids (RGBA8, box-filtered levels down to 1x1, bottom row first so that uv (0,0) is the
 * image's bottom-left corner as in GL), sampled with repeat wrapping and trilinear filtering in
 * integer arithmetic (8-bit sub-texel and level weights): the same bits on every host. */
#ifndef LM_WORKER_CPU_TEXTURE_H
#define LM_WORKER_CPU_TEXTURE_H

#include <stdint.h>

#include "common/error.h"
#include "common/image.h"
#include "common/mesh.h"

#define WK_CPU_TEX_LEVELS 16
/* A filtered channel: 255 << 24 is full intensity. */
#define WK_CPU_TEX_ONE (255u << 24)

typedef struct wk_cpu_level {
    int width, height;
    const uint8_t *rgba; /* width * height * 4 bytes, bottom row first */
} wk_cpu_level;

typedef struct wk_cpu_texture {
    int n_levels;
    wk_cpu_level level[WK_CPU_TEX_LEVELS];
    uint8_t *data; /* all levels */
} wk_cpu_texture;

/* The pyramid of an RGBA8 image (rows top first, as lm_image holds them). */
lm_status wk_cpu_texture_create(const lm_image *img, wk_cpu_texture **out);
void wk_cpu_texture_destroy(wk_cpu_texture *t);

/* Texture colour at (u, v) with level of detail lod (log2 of the texel footprint, 8 fractional
 * bits; <= 0 magnifies: bilinear on level 0), per channel in units of WK_CPU_TEX_ONE. u and v
 * may be any finite numbers (repeat); others read as 0. */
void wk_cpu_texture_sample(const wk_cpu_texture *t, float u, float v, int lod, uint32_t out[3]);

/* A material table: diffuse colours and textures (NULL where untextured). */
typedef struct wk_cpu_materials {
    uint32_t n;
    float (*diffuse)[4];
    wk_cpu_texture **tex;
} wk_cpu_materials;

/* Replace the table's contents with copies of mats (textures become pyramids). */
lm_status wk_cpu_materials_set(wk_cpu_materials *t, const lm_material *mats, uint32_t n);
void wk_cpu_materials_free(wk_cpu_materials *t);

#endif
