/* worker/render/cpu/cpu_shade.h — the CPU backend's fragment colour, the light model of the GL
 * shaders (worker/render/gl/render_program.c): per corner colour × material diffuse × (0.15 + 0.85
 * |n·l|) with the light along the view direction (normals as given, two-sided), interpolated
 * perspective-correct, times the texture (trilinear, level of detail from the exact screen
 * derivatives of the texture coordinates at the pixel), clamped and rounded to 8 bits. A pure
 * function of the sub, the triangle, the material and the pixel: a full render and a redrawn region
 * agree bit for bit. */
#ifndef LM_WORKER_CPU_SHADE_H
#define LM_WORKER_CPU_SHADE_H

#include <stdint.h>

#include "common/patch.h"
#include "worker/render/cpu/cpu_raster.h"
#include "worker/render/cpu/cpu_texture.h"

#define WK_CPU_BACKGROUND 128 /* background grey (8-bit), as the GL renderer's WK_BACKGROUND */

typedef struct wk_cpu_shade {
    /* Perspective-correct interpolation as planes over the sub's pixels, each evaluated at (x, y)
     * as (p[0] + p[1] dx) + p[2] dy with dx = x - x0, dy = y - y0 in float: the denominator
     * D = Σ e_k / w_k and the numerators Σ e_k a_k / w_k of the lit colour's channels and of the
     * texture coordinates; an attribute is its numerator / D. Made in double, rounded once. */
    float den[3], col[3][3], uv[2][3];
    const wk_cpu_texture *tex; /* NULL: untextured */
    float tex_w, tex_h;        /* level 0 size */
    /* With a normal map (nrm not NULL; else none of these is set): col holds the unlit colour
     * (corner colour × diffuse), frame the planes of the corners' unit tangent, bitangent and
     * normal (frame[3 f + axis]: f = 0 T, 1 B, 2 N), and each pixel is lit by 0.15 + 0.85 |n·l|
     * with n = normalize(T x + B y + N z), (x, y, z) the map's texel (trilinear) scaled to
     * [-1, 1]. */
    const wk_cpu_texture *nrm;
    float nrm_w, nrm_h;
    float frame[9][3];
    float light[3];
} wk_cpu_shade;

/* Shading constants of sub s of triangle t (material table mats; t->material < mats->n). */
void wk_cpu_shade_setup(const wk_cpu_sub *s, const lm_tri_data *t, const float light[3],
                        const wk_cpu_materials *mats, wk_cpu_shade *out);

/* RGB8 and luminance of the sub at n pixels xy[i] (WK_CPU_XY, each covered by it): colour into
 * rgb (3 n bytes, by channel: red i at rgb[i], green at rgb[n + i], blue at rgb[2 n + i]),
 * luminance (wk_luma of it) into luma[i]. Pixels go four or eight at a time through IEEE float
 * lanes; each pixel's value depends on the sub and the pixel only, never on the others of the call.
 * texf (textured materials only; 3 floats a pixel, texf[3 i + channel]; may be NULL): the
 * texture's factors, written as sampled, or with reuse read instead of sampling (factors a call
 * made for a sub of the same corners, texture coordinates and material: the same bits). */
void wk_cpu_shade_pixels(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy, size_t n,
                         uint8_t *rgb, uint8_t *luma, float *texf, int reuse);

/* The lane width wk_cpu_shade_pixels uses, resolved once: 8 where this build has the AVX2 code
 * (x86-64) and the processor has AVX2, unless the environment sets LUMESH_CPU_LANES=4; else 4.
 * Every width gives the same bits. */
int wk_cpu_shade_lanes(void);
/* Tests: use 8 lanes (where supported) or 4 from now on; returns the width now used. */
int wk_cpu_shade_set_lanes(int lanes);

/* The eight-lane instantiation (cpu_shade_avx2.c): whether this build has it and the processor
 * runs it, and wk_cpu_shade_pixels through it (only where supported). */
int wk_cpu_shade_wide_supported(void);
void wk_cpu_shade_pixels_wide(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy,
                              size_t n, uint8_t *rgb, uint8_t *luma, float *texf, int reuse);

/* 65536 log2(1 + i / 256), rounded, for i = 0..256 (the level of detail's table). */
extern const uint32_t wk_cpu_log2_table[257];

/* 2^8 log2(sqrt(r2)) = 128 log2(r2) rounded down (the level of detail of a footprint whose squared
 * size is r2 texels²), from a table of log2 over the mantissa's top bits, interpolated in integers;
 * very negative for r2 <= 0, NaN and subnormals, large for infinite r2. */
int wk_cpu_lod_q8(float r2);
/* The same, four lanes at once (wk_cpu_lod_q8 of each lane, bit for bit). */
v4i wk_cpu_lod_q8_4(v4f r2);

#endif
