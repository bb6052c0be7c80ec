/* worker/cpu_shade.c — lighting at the corners, perspective-correct interpolation, the level of
 * detail and the final 8-bit colour of a fragment (see cpu_shade.h). Setup in double, pixels four
 * at a time in IEEE float lanes (GCC vector extensions: SSE2 on x86-64, NEON on AArch64, scalar
 * code elsewhere; each operation is the IEEE one lane by lane, so the bits never depend on the
 * target), integer texture filtering. */
#include "worker/cpu_shade.h"

#include <math.h>
#include <string.h>

#include "worker/cpu_simd.h"

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
    out->tex = mats->tex[t->material];
    for (int ch = 0; ch < 3; ch++)
        plane_of(s, at[ch], out->col[ch]);
    for (int a = 0; out->tex && a < 2; a++) /* texture coordinates matter only with a texture */
        plane_of(s, at[3 + a], out->uv[a]);
    plane_of(s, at[5], out->den);
    out->tex_w = out->tex ? (float)out->tex->level[0].width : 0.0f;
    out->tex_h = out->tex ? (float)out->tex->level[0].height : 0.0f;
}

/* 65536 log2(1 + i / 256), rounded, for i = 0..256 (made once with exact arithmetic; a literal so
 * that no host's libm takes part). */
static const uint32_t log2_table[257] = {
    0,     369,   736,   1102,  1466,  1829,  2190,  2551,  2909,  3267,  3623,  3978,  4331,
    4683,  5034,  5384,  5732,  6079,  6425,  6769,  7112,  7454,  7795,  8134,  8473,  8810,
    9146,  9480,  9814,  10146, 10477, 10807, 11136, 11464, 11791, 12116, 12440, 12764, 13086,
    13407, 13727, 14046, 14363, 14680, 14996, 15310, 15624, 15937, 16248, 16559, 16868, 17177,
    17484, 17791, 18096, 18401, 18704, 19007, 19308, 19609, 19909, 20207, 20505, 20802, 21098,
    21393, 21687, 21980, 22272, 22564, 22854, 23144, 23433, 23720, 24007, 24293, 24579, 24863,
    25146, 25429, 25711, 25992, 26272, 26551, 26830, 27108, 27384, 27660, 27936, 28210, 28484,
    28757, 29029, 29300, 29571, 29840, 30109, 30378, 30645, 30912, 31178, 31443, 31707, 31971,
    32234, 32496, 32758, 33019, 33279, 33538, 33797, 34055, 34312, 34569, 34825, 35080, 35334,
    35588, 35841, 36094, 36346, 36597, 36847, 37097, 37346, 37595, 37842, 38090, 38336, 38582,
    38827, 39072, 39316, 39559, 39802, 40044, 40286, 40527, 40767, 41006, 41246, 41484, 41722,
    41959, 42196, 42432, 42667, 42902, 43137, 43370, 43603, 43836, 44068, 44300, 44530, 44761,
    44990, 45220, 45448, 45676, 45904, 46131, 46357, 46583, 46809, 47034, 47258, 47482, 47705,
    47928, 48150, 48372, 48593, 48813, 49034, 49253, 49472, 49691, 49909, 50127, 50344, 50560,
    50776, 50992, 51207, 51422, 51636, 51850, 52063, 52276, 52488, 52700, 52911, 53122, 53332,
    53542, 53751, 53960, 54169, 54377, 54584, 54791, 54998, 55204, 55410, 55615, 55820, 56025,
    56229, 56432, 56635, 56838, 57040, 57242, 57443, 57644, 57845, 58045, 58245, 58444, 58643,
    58841, 59039, 59237, 59434, 59631, 59827, 60023, 60219, 60414, 60609, 60803, 60997, 61190,
    61384, 61576, 61769, 61961, 62152, 62343, 62534, 62725, 62915, 63104, 63294, 63483, 63671,
    63859, 64047, 64234, 64421, 64608, 64794, 64980, 65166, 65351, 65536};

int wk_cpu_lod_q8(float r2)
{
    if (!(r2 >= 1.17549435e-38f)) /* NaN, negative, zero, subnormal: far below one texel */
        return -(1 << 20);
    if (!(r2 <= 3.40282347e38f))
        return 1 << 20;
    uint32_t b;
    memcpy(&b, &r2, sizeof b); /* r2 = (1 + f) 2^(e - 127), f = (b & 0x7FFFFF) / 2^23 */
    int e = (int)((b >> 23) & 0xFF) - 127;
    uint32_t i = (b >> 15) & 0xFF, j = (b >> 7) & 0xFF; /* f's top 8 bits, then the next 8 */
    uint32_t frac = log2_table[i] + (((log2_table[i + 1] - log2_table[i]) * j) >> 8);
    int l = e * 1024 + (int)(frac >> 6); /* 1024 log2(r2), rounded down; the lod is 128 log2 */
    return l >= 0 ? l >> 3 : -((7 - l) >> 3);
}

static inline v4i lod_q8_4(v4f r2)
{
    const v4i b = (v4i)r2, e = ((b >> 23) & 0xFF) - 127, i = (b >> 15) & 0xFF, j = (b >> 7) & 0xFF;
    v4i t0, t1;
    for (int k = 0; k < 4; k++) {
        t0[k] = (int32_t)log2_table[i[k]];
        t1[k] = (int32_t)log2_table[i[k] + 1];
    }
    /* (t1 - t0) j is at most 369 * 255: exact in float, where SSE2 has a multiply */
    v4f step = __builtin_convertvector(t1 - t0, v4f) * __builtin_convertvector(j, v4f);
    v4i frac = t0 + (__builtin_convertvector(step, v4i) >> 8);
    v4i l = (e * 1024 + (frac >> 6)) >> 3; /* >> of a negative lane rounds down, as the scalar's */
    const v4f lo = {1.17549435e-38f, 1.17549435e-38f, 1.17549435e-38f, 1.17549435e-38f};
    const v4f hi = {3.40282347e38f, 3.40282347e38f, 3.40282347e38f, 3.40282347e38f};
    v4i tiny = ~(r2 >= lo), huge = ~(r2 <= hi) & ~tiny; /* NaN is tiny, as in the scalar */
    l = (l & ~tiny & ~huge) | (-(1 << 20) & tiny) | ((1 << 20) & huge);
    return l;
}

v4i wk_cpu_lod_q8_4(v4f r2)
{
    return lod_q8_4(r2);
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

/* (77 r + 150 g + 29 b + 128) >> 8 per lane for r, g, b in 0..255: the sums (at most 65,408)
 * are exact in float, where SSE2 has a multiply and 32-bit integers do not. */
static inline v4i luma4(v4i r, v4i g, v4i b)
{
    v4f s = __builtin_convertvector(r, v4f) * 77.0f + __builtin_convertvector(g, v4f) * 150.0f +
            __builtin_convertvector(b, v4f) * 29.0f + 128.0f;
    return __builtin_convertvector(s, v4i) >> 8;
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
    wk_cpu_texture_sample4(sh->tex, u, v, lod_q8_4(r2), out);
    for (int ch = 0; ch < 3; ch++)
        out[ch] *= 1.0f / 255.0f;
}

/* Four pixels' factors stored by pixel (r0 g0 b0 r1 | g1 b1 r2 g2 | b2 r3 g3 b3) as three
 * vectors by channel, and back: whole vectors and shuffles, not twelve lanes one by one. */
static void factors_load(const float *at, v4f tf[3])
{
    v4f a, b, c;
    memcpy(&a, at, sizeof a);
    memcpy(&b, at + 4, sizeof b);
    memcpy(&c, at + 8, sizeof c);
    tf[0] = __builtin_shufflevector(__builtin_shufflevector(a, b, 0, 3, 6, 7), c, 0, 1, 2, 5);
    tf[1] = __builtin_shufflevector(__builtin_shufflevector(a, b, 1, 4, 7, 7), c, 0, 1, 2, 6);
    tf[2] = __builtin_shufflevector(__builtin_shufflevector(a, b, 2, 5, 5, 5), c, 0, 1, 4, 7);
}

static void factors_store(const v4f tf[3], float *at)
{
    v4f a = __builtin_shufflevector(__builtin_shufflevector(tf[0], tf[1], 0, 4, 1, 5), tf[2], 0, 1,
                                    4, 2);
    v4f b = __builtin_shufflevector(__builtin_shufflevector(tf[1], tf[2], 1, 5, 2, 6), tf[0], 0, 1,
                                    6, 2);
    v4f c = __builtin_shufflevector(__builtin_shufflevector(tf[0], tf[1], 3, 7, 3, 7), tf[2], 6, 0,
                                    1, 7);
    memcpy(at, &a, sizeof a);
    memcpy(at + 4, &b, sizeof b);
    memcpy(at + 8, &c, sizeof c);
}

/* The texture's factors of pixels i..i+3 (padded with the last of n), sampled or read from and
 * written to texf. */
static void group_texture(const wk_cpu_shade *sh, v4f dx, v4f dy, v4f inv, float *texf, int reuse,
                          size_t i, size_t n, v4f tf[3])
{
    if (texf && reuse && i + 4 <= n) {
        factors_load(texf + 3 * i, tf);
        return;
    }
    if (texf && reuse) {
        for (int k = 0; k < 4; k++) {
            size_t at = i + (size_t)k < n ? i + (size_t)k : n - 1;
            for (int ch = 0; ch < 3; ch++)
                tf[ch][k] = texf[3 * at + (size_t)ch];
        }
        return;
    }
    texture_factor(sh, dx, dy, inv, tf);
    if (texf && i + 4 <= n) {
        factors_store(tf, texf + 3 * i);
        return;
    }
    for (size_t k = 0; texf && k < 4 && i + k < n; k++)
        for (int ch = 0; ch < 3; ch++)
            texf[3 * (i + k) + (size_t)ch] = tf[ch][k];
}

/* Pixels i..i+3 of xy (the group padded with copies of the last pixel, n in all). */
static void shade_group(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy, size_t i,
                        size_t n, uint8_t *restrict c, uint8_t *restrict luma, float *texf,
                        int reuse)
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
        group_texture(sh, dx, dy, inv, texf, reuse, i, n, tf);
        for (int ch = 0; ch < 3; ch++)
            col[ch] *= tf[ch];
    }
    v4i vr = unorm8v(col[0]), vg = unorm8v(col[1]), vb = unorm8v(col[2]);
    v4i vl = luma4(vr, vg, vb);
    for (size_t k = 0; k < 4 && i + k < n; k++) {
        c[i + k] = (uint8_t)vr[k];
        c[n + i + k] = (uint8_t)vg[k];
        c[2 * n + i + k] = (uint8_t)vb[k];
        luma[i + k] = (uint8_t)vl[k];
    }
}

void wk_cpu_shade_pixels(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy, size_t n,
                         uint8_t *rgb, uint8_t *luma, float *texf, int reuse)
{
    for (size_t i = 0; i < n; i += 4)
        shade_group(s, sh, xy, i, n, rgb, luma, texf, reuse);
}
