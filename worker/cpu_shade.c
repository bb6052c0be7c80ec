/* worker/cpu_shade.c — lighting at the corners, perspective-correct interpolation, the level of
 * detail and the final 8-bit colour of a fragment (see cpu_shade.h). Setup in double, pixels four
 * at a time in IEEE float lanes (GCC vector extensions: SSE2 on x86-64, NEON on AArch64, scalar
 * code elsewhere; each operation is the IEEE one lane by lane, so the bits never depend on the
 * target), integer texture filtering. */
#include "worker/cpu_shade.h"

#include <math.h>
#include <string.h>

typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));

/* The plane of Σ_k q_k f_k over the sub's pixels, q_k = e_k / w_k, rounded to float. */
static void plane_of(const wk_cpu_sub *s, const double f[3], float out[3])
{
    double p[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        p[0] += (double)(s->e[k] + s->bias[k]) * s->invw[k] * f[k];
        p[1] += (double)s->a[k] * s->invw[k] * f[k];
        p[2] += (double)s->b[k] * s->invw[k] * f[k];
    }
    for (int i = 0; i < 3; i++)
        out[i] = (float)p[i];
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
    out->tex = mats->tex[t->material];
    out->tex_w = out->tex ? (float)out->tex->level[0].width : 0.0f;
    out->tex_h = out->tex ? (float)out->tex->level[0].height : 0.0f;
}

int wk_cpu_lod_q8(float r2)
{
    if (!(r2 >= 1.17549435e-38f)) /* NaN, negative, zero, subnormal: far below one texel */
        return -(1 << 20);
    if (!(r2 <= 3.40282347e38f))
        return 1 << 20;
    uint32_t b;
    memcpy(&b, &r2, sizeof b);              /* r2 = (1 + f) 2^(e - 127) */
    int e = (int)((b >> 23) & 0xFF) - 127;
    uint64_t x = (uint64_t)((b & 0x7FFFFF) | 0x800000) << 8, bits = 0; /* 1 + f as Q31 */
    for (int i = 0; i < 10; i++) { /* log2(1 + f) to 10 bits by squaring, without branches */
        x = (x * x) >> 31;
        uint64_t carry = x >> 32; /* 1 when the square reached 2 */
        x >>= carry;
        bits = bits << 1 | carry;
    }
    int l10 = e * 1024 + (int)bits; /* 1024 log2(r2), rounded down; the lod is 128 log2 */
    return l10 >= 0 ? l10 >> 3 : -((7 - l10) >> 3);
}

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

static inline v4f plane_at(const float p[3], v4f dx, v4f dy)
{
    return (p[0] + p[1] * dx) + p[2] * dy;
}

/* The texture's factor on the colour at four pixels: uv = N / D, the level of detail from the
 * screen derivatives of uv, (N' - uv D') / D, in texels; trilinear samples lane by lane. */
static void texture_factor(const wk_cpu_shade *sh, v4f dx, v4f dy, v4f inv, v4f out[3])
{
    v4f u = plane_at(sh->uv[0], dx, dy) * inv, v = plane_at(sh->uv[1], dx, dy) * inv;
    v4f ux = (sh->uv[0][1] - u * sh->den[1]) * inv * sh->tex_w;
    v4f vx = (sh->uv[1][1] - v * sh->den[1]) * inv * sh->tex_h;
    v4f uy = (sh->uv[0][2] - u * sh->den[2]) * inv * sh->tex_w;
    v4f vy = (sh->uv[1][2] - v * sh->den[2]) * inv * sh->tex_h;
    v4f rx = ux * ux + vx * vx, ry = uy * uy + vy * vy;
    v4i xbig = rx > ry;
    v4f r2 = (v4f)(((v4i)rx & xbig) | ((v4i)ry & ~xbig));
    v4i t[3];
    for (int k = 0; k < 4; k++) {
        uint32_t tc[3];
        wk_cpu_texture_sample(sh->tex, u[k], v[k], wk_cpu_lod_q8(r2[k]), tc);
        for (int ch = 0; ch < 3; ch++)
            t[ch][k] = (int32_t)(tc[ch] >> 8); /* below 2^24: exact in float */
    }
    for (int ch = 0; ch < 3; ch++)
        out[ch] = __builtin_convertvector(t[ch], v4f) * (1.0f / 16711680.0f); /* / (255 << 16) */
}

/* Pixels i..i+3 of xy (the group padded with copies of the last pixel, n in all). */
static void shade_group(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy, size_t i,
                        size_t n, uint8_t *restrict c, uint8_t *restrict luma)
{
    v4i px, py;
    for (int k = 0; k < 4; k++) {
        uint32_t q = xy[i + (size_t)k < n ? i + (size_t)k : n - 1];
        px[k] = (int32_t)(q & 0xFFFF) - s->x0;
        py[k] = (int32_t)(q >> 16) - s->y0;
    }
    v4f dx = __builtin_convertvector(px, v4f), dy = __builtin_convertvector(py, v4f);
    v4f inv = 1.0f / plane_at(sh->den, dx, dy);
    v4f col[3];
    for (int ch = 0; ch < 3; ch++)
        col[ch] = plane_at(sh->col[ch], dx, dy) * inv;
    if (sh->tex) {
        v4f tf[3];
        texture_factor(sh, dx, dy, inv, tf);
        for (int ch = 0; ch < 3; ch++)
            col[ch] *= tf[ch];
    }
    v4i vr = unorm8v(col[0]), vg = unorm8v(col[1]), vb = unorm8v(col[2]);
    v4i vl = (77 * vr + 150 * vg + 29 * vb + 128) >> 8;
    for (size_t k = 0; k < 4 && i + k < n; k++) {
        c[i + k] = (uint8_t)vr[k];
        c[n + i + k] = (uint8_t)vg[k];
        c[2 * n + i + k] = (uint8_t)vb[k];
        luma[i + k] = (uint8_t)vl[k];
    }
}

void wk_cpu_shade_pixels(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy, size_t n,
                         uint8_t *rgb, uint8_t *luma)
{
    for (size_t i = 0; i < n; i += 4)
        shade_group(s, sh, xy, i, n, rgb, luma);
}
