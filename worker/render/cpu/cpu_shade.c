/* worker/render/cpu/cpu_shade.c — lighting at the corners, perspective-correct interpolation, the
 * level of detail and the final 8-bit colour of a fragment (see cpu_shade.h). Setup in double; the
 * pixels (cpu_shade_lanes.h) four at a time here, eight in cpu_shade_avx2.c where the processor has
 * AVX2, chosen once at run time: the same bits either way. */
#include "worker/render/cpu/cpu_shade.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "common/tangents.h"
#include "worker/render/cpu/cpu_simd.h"

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

/* The planes of the corners' unit frames (T, B, N; common/tangents.h: the triangle's own
 * UV-derivative frame made orthogonal to each corner's normal) over the sub, and the light. */
static void frame_planes(const wk_cpu_sub *s, const lm_tri_data *t, const float light[3],
                         wk_cpu_shade *out)
{
    float p[3][3], uv[3][2];
    for (int k = 0; k < 3; k++) {
        memcpy(p[k], t->c[k].pos, sizeof p[k]);
        memcpy(uv[k], t->c[k].uv, sizeof uv[k]);
    }
    double ft[3], fb[3], fr[3][9];
    lm_tri_tangent_frame(p, uv, ft, fb);
    for (int k = 0; k < 3; k++)
        lm_tangent_basis(t->c[k].normal, ft, fb, fr[k]);
    for (int a = 0; a < 9; a++) {
        double at[3];
        for (int j = 0; j < 3; j++)
            at[j] = s->beta[j][0] * fr[0][a] + s->beta[j][1] * fr[1][a] + s->beta[j][2] * fr[2][a];
        plane_of(s, at, out->frame[a]);
    }
    memcpy(out->light, light, sizeof out->light);
    out->nrm_w = (float)out->nrm->level[0].width;
    out->nrm_h = (float)out->nrm->level[0].height;
}

void wk_cpu_shade_setup(const wk_cpu_sub *s, const lm_tri_data *t, const float light[3],
                        const wk_cpu_materials *mats, wk_cpu_shade *out)
{
    const float *dif = mats->diffuse[t->material];
    out->nrm = mats->nrm ? mats->nrm[t->material] : NULL;
    double lit[3][3], at[6][3]; /* per source corner, then per sub corner: r, g, b, u, v, 1 */
    for (int k = 0; k < 3; k++) {
        const lm_corner *c = &t->c[k];
        double d = fabs((double)c->normal[0] * light[0] + (double)c->normal[1] * light[1] +
                        (double)c->normal[2] * light[2]);
        double f = out->nrm ? 1.0 : 0.15 + 0.85 * d; /* a normal map lights each pixel */
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
    for (int a = 0; (out->tex || out->nrm) && a < 2; a++) /* only a texture needs them */
        plane_of(s, at[3 + a], out->uv[a]);
    plane_of(s, at[5], out->den);
    out->tex_w = out->tex ? (float)out->tex->level[0].width : 0.0f;
    out->tex_h = out->tex ? (float)out->tex->level[0].height : 0.0f;
    if (out->nrm)
        frame_planes(s, t, light, out);
}

/* 65536 log2(1 + i / 256), rounded, for i = 0..256 (made once with exact arithmetic; a literal so
 * that no host's libm takes part). */
const uint32_t wk_cpu_log2_table[257] = {
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
    uint32_t frac =
        wk_cpu_log2_table[i] + (((wk_cpu_log2_table[i + 1] - wk_cpu_log2_table[i]) * j) >> 8);
    int l = e * 1024 + (int)(frac >> 6); /* 1024 log2(r2), rounded down; the lod is 128 log2 */
    return l >= 0 ? l >> 3 : -((7 - l) >> 3);
}

/* The pixel code at four lanes (SSE2 on x86-64, NEON on AArch64, scalar elsewhere). */
#define WK_W 4
#define WK_VF v4f
#define WK_VI v4i
#define WK_L(name) name##_w4
#include "worker/render/cpu/cpu_shade_lanes.h"

v4i wk_cpu_lod_q8_4(v4f r2)
{
    return lod_q8_w4(r2);
}

static void shade_pixels_4(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy,
                           size_t n, uint8_t *rgb, uint8_t *luma, float *texf, int reuse)
{
    for (size_t i = 0; i < n; i += 4)
        shade_group_w4(s, sh, xy, i, n, rgb, luma, texf, reuse);
}

/* The width in use: 0 until resolved (once; every thread resolves it alike). */
static _Atomic int lanes_now;

static int lanes_default(void)
{
    const char *env = getenv("LUMESH_CPU_LANES");
    if (env && strcmp(env, "4") == 0)
        return 4;
    return wk_cpu_shade_wide_supported() ? 8 : 4;
}

int wk_cpu_shade_lanes(void)
{
    int l = atomic_load_explicit(&lanes_now, memory_order_relaxed);
    if (!l) {
        l = lanes_default();
        atomic_store_explicit(&lanes_now, l, memory_order_relaxed);
    }
    return l;
}

int wk_cpu_shade_set_lanes(int lanes)
{
    int l = lanes == 8 && wk_cpu_shade_wide_supported() ? 8 : 4;
    atomic_store_explicit(&lanes_now, l, memory_order_relaxed);
    return l;
}

void wk_cpu_shade_pixels(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy, size_t n,
                         uint8_t *rgb, uint8_t *luma, float *texf, int reuse)
{
    if (wk_cpu_shade_lanes() == 8)
        wk_cpu_shade_pixels_wide(s, sh, xy, n, rgb, luma, texf, reuse);
    else
        shade_pixels_4(s, sh, xy, n, rgb, luma, texf, reuse);
}
