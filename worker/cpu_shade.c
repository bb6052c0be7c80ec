/* worker/cpu_shade.c — lighting at the corners, perspective-correct interpolation, the level of
 * detail and the final 8-bit colour of a fragment (see cpu_shade.h). Double precision in a fixed
 * order (-ffp-contract=off), integer texture filtering. */
#include "worker/cpu_shade.h"

#include <math.h>
#include <string.h>

/* The plane of Σ_k q_k f_k over the sub's pixels, q_k = e_k / w_k. */
static void plane_of(const wk_cpu_sub *s, const double f[3], double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    for (int k = 0; k < 3; k++) {
        out[0] += (double)(s->e[k] + s->bias[k]) * s->invw[k] * f[k];
        out[1] += (double)s->a[k] * s->invw[k] * f[k];
        out[2] += (double)s->b[k] * s->invw[k] * f[k];
    }
}

void wk_cpu_shade_setup(const wk_cpu_sub *s, const lm_tri_data *t, const float light[3],
                        const wk_cpu_materials *mats, wk_cpu_shade *out)
{
    const float *dif = mats->diffuse[t->material];
    double lit[3][3], at[6][3]; /* per source corner, then per sub corner: r, g, b, u, v, 1 */
    for (int k = 0; k < 3; k++) {
        const lm_corner *c = &t->c[k];
        double d = fabs((double)c->normal[0] * light[0] + (double)c->normal[1] * light[1] +
                        (double)c->normal[2] * light[2]);
        double f = 0.15 + 0.85 * d;
        for (int ch = 0; ch < 3; ch++)
            lit[k][ch] = (double)c->color[ch] * dif[ch] * f;
    }
    for (int j = 0; j < 3; j++) { /* clipping interpolates the vertex stage's outputs */
        const double *b = s->beta[j];
        for (int ch = 0; ch < 3; ch++)
            at[ch][j] = b[0] * lit[0][ch] + b[1] * lit[1][ch] + b[2] * lit[2][ch];
        for (int a = 0; a < 2; a++)
            at[3 + a][j] = b[0] * t->c[0].uv[a] + b[1] * t->c[1].uv[a] + b[2] * t->c[2].uv[a];
        at[5][j] = 1.0;
    }
    for (int ch = 0; ch < 3; ch++)
        plane_of(s, at[ch], out->col[ch]);
    for (int a = 0; a < 2; a++)
        plane_of(s, at[3 + a], out->uv[a]);
    plane_of(s, at[5], out->den);
    for (int i = 0; i < 3; i++) {
        out->fden[i] = (float)out->den[i];
        for (int ch = 0; ch < 3; ch++)
            out->fcol[ch][i] = (float)out->col[ch][i];
    }
    out->tex = mats->tex[t->material];
    out->tex_w = out->tex ? out->tex->level[0].width : 0;
    out->tex_h = out->tex ? out->tex->level[0].height : 0;
}

int wk_cpu_lod_q8(double r2)
{
    if (!(r2 > 0.0))
        return -(1 << 20);
    if (!(r2 < 1e300))
        return 1 << 20;
    if (!(r2 >= 2.2250738585072014e-308))
        return -(1 << 20); /* subnormal: far below one texel */
    uint64_t b;
    memcpy(&b, &r2, sizeof b);               /* r2 = (1 + f) 2^(e - 1023) */
    int e = (int)((b >> 52) & 0x7ff) - 1022; /* r2 = m 2^e with m in [0.5, 1) */
    uint64_t x = ((b & 0xFFFFFFFFFFFFFull) | (1ull << 52)) >> 21, bits = 0; /* 2m as Q31 */
    for (int i = 0; i < 10; i++) { /* log2(2m) to 10 bits by squaring */
        x = (x * x) >> 31;
        bits <<= 1;
        if (x >= ((uint64_t)1 << 32)) {
            x >>= 1;
            bits |= 1;
        }
    }
    int l10 = (e - 1) * 1024 + (int)bits; /* 1024 log2(r2), rounded down; the lod is 128 log2 */
    return l10 >= 0 ? l10 >> 3 : -((7 - l10) >> 3);
}

static uint8_t to_unorm8(double c)
{
    c = c > 0.0 ? c : 0.0; /* NaN -> 0 */
    c = c < 1.0 ? c : 1.0;
    return (uint8_t)(c * 255.0 + 0.5);
}

/* Level of detail at a pixel with texture coordinates uv and 1 / D = inv: the screen derivatives
 * of N / D are (N' - uv D') / D. */
static int pixel_lod(const wk_cpu_shade *sh, const double uv[2], double inv)
{
    double ux = (sh->uv[0][1] - uv[0] * sh->den[1]) * inv * sh->tex_w;
    double vx = (sh->uv[1][1] - uv[1] * sh->den[1]) * inv * sh->tex_h;
    double uy = (sh->uv[0][2] - uv[0] * sh->den[2]) * inv * sh->tex_w;
    double vy = (sh->uv[1][2] - uv[1] * sh->den[2]) * inv * sh->tex_h;
    double rx = ux * ux + vx * vx, ry = uy * uy + vy * vy;
    return wk_cpu_lod_q8(rx > ry ? rx : ry);
}

static inline double plane_at(const double p[3], double dx, double dy)
{
    return (p[0] + p[1] * dx) + p[2] * dy;
}

/* A textured pixel. */
static void shade_pixel(const wk_cpu_sub *s, const wk_cpu_shade *sh, int x, int y, uint8_t rgb[3])
{
    double dx = (double)(x - s->x0), dy = (double)(y - s->y0);
    double inv = 1.0 / plane_at(sh->den, dx, dy);
    double c[3];
    for (int ch = 0; ch < 3; ch++)
        c[ch] = plane_at(sh->col[ch], dx, dy) * inv;
    if (sh->tex) {
        double uv[2] = {plane_at(sh->uv[0], dx, dy) * inv, plane_at(sh->uv[1], dx, dy) * inv};
        uint32_t tc[3];
        wk_cpu_texture_sample(sh->tex, uv[0], uv[1], pixel_lod(sh, uv, inv), tc);
        for (int ch = 0; ch < 3; ch++)
            c[ch] *= (double)tc[ch] / (double)WK_CPU_TEX_ONE;
    }
    for (int ch = 0; ch < 3; ch++)
        rgb[ch] = to_unorm8(c[ch]);
}

static inline uint8_t luma_of(const uint8_t c[3])
{
    return (uint8_t)((77u * c[0] + 150u * c[1] + 29u * c[2] + 128u) >> 8);
}

/* Four lanes of float or int (GCC vector extensions: SSE2 on x86-64, NEON on AArch64, scalar code
 * elsewhere; every operation is the IEEE one lane by lane, so the bits never depend on it). */
typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));

/* round(clamp(c, 0, 1) * 255) per lane, NaN as 0. */
static inline v4i unorm8v(v4f c)
{
    const v4f zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
    v4i pos = c > zero; /* false for NaN */
    c = (v4f)((v4i)c & pos);
    v4i low = c < one;
    c = (v4f)(((v4i)c & low) | ((v4i)one & ~low));
    return __builtin_convertvector(c * 255.0f + 0.5f, v4i);
}

/* Untextured pixels four at a time (the last group padded with copies of the last pixel):
 * interpolation in float, the planes' values and the division, clamp, 8 bits, luminance. Channels
 * go to c (3 n bytes, planar by channel). */
static void shade_plain(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy, size_t n,
                        uint8_t *restrict c, uint8_t *restrict luma)
{
    const float d0 = sh->fden[0], d1 = sh->fden[1], d2 = sh->fden[2];
    const float *r = sh->fcol[0], *g = sh->fcol[1], *b = sh->fcol[2];
    for (size_t i = 0; i < n; i += 4) {
        v4i px, py;
        for (int k = 0; k < 4; k++) {
            uint32_t q = xy[i + (size_t)k < n ? i + (size_t)k : n - 1];
            px[k] = (int32_t)(q & 0xFFFF) - s->x0;
            py[k] = (int32_t)(q >> 16) - s->y0;
        }
        v4f dx = __builtin_convertvector(px, v4f), dy = __builtin_convertvector(py, v4f);
        v4f inv = 1.0f / ((d0 + d1 * dx) + d2 * dy);
        v4i vr = unorm8v(((r[0] + r[1] * dx) + r[2] * dy) * inv);
        v4i vg = unorm8v(((g[0] + g[1] * dx) + g[2] * dy) * inv);
        v4i vb = unorm8v(((b[0] + b[1] * dx) + b[2] * dy) * inv);
        v4i vl = (77 * vr + 150 * vg + 29 * vb + 128) >> 8;
        for (size_t k = 0; k < 4 && i + k < n; k++) {
            c[i + k] = (uint8_t)vr[k];
            c[n + i + k] = (uint8_t)vg[k];
            c[2 * n + i + k] = (uint8_t)vb[k];
            luma[i + k] = (uint8_t)vl[k];
        }
    }
}

void wk_cpu_shade_pixels(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy, size_t n,
                         uint8_t *rgb, uint8_t *luma)
{
    if (!sh->tex) {
        shade_plain(s, sh, xy, n, rgb, luma);
        return;
    }
    for (size_t i = 0; i < n; i++) {
        uint8_t c[3];
        shade_pixel(s, sh, WK_CPU_X(xy[i]), WK_CPU_Y(xy[i]), c);
        luma[i] = luma_of(c);
        rgb[i] = c[0];
        rgb[n + i] = c[1];
        rgb[2 * n + i] = c[2];
    }
}
