/* worker/render/cpu/cpu_shade_lanes.h — a fragment's colour and luminance WK_W pixels at a time
 * (see cpu_shade.h), written once for any lane count: included by cpu_shade.c (4 lanes) and
 * cpu_shade_avx2.c (8 lanes, and 4 for short runs), each with WK_W, WK_VF / WK_VI and WK_L(name)
 * defined (cpu_sample_lanes.h says how). Each operation is the IEEE one lane by lane and every
 * pixel's value depends on its sub and itself only, so all widths give the same bits. No include
 * guard: one inclusion per width. */
#include "worker/render/cpu/cpu_sample_lanes.h"

/* wk_cpu_lod_q8 of each lane, bit for bit (cpu_shade.c). */
static inline WK_VI WK_L(lod_q8)(WK_VF r2)
{
    const WK_VI b = (WK_VI)r2, e = ((b >> 23) & 0xFF) - 127, i = (b >> 15) & 0xFF,
                j = (b >> 7) & 0xFF;
    WK_VI t0, t1;
    for (int k = 0; k < WK_W; k++) {
        t0[k] = (int32_t)wk_cpu_log2_table[i[k]];
        t1[k] = (int32_t)wk_cpu_log2_table[i[k] + 1];
    }
    /* (t1 - t0) j is at most 369 * 255: exact in float, where SSE2 has a multiply */
    WK_VF step = __builtin_convertvector(t1 - t0, WK_VF) * __builtin_convertvector(j, WK_VF);
    WK_VI frac = t0 + (__builtin_convertvector(step, WK_VI) >> 8);
    WK_VI l =
        (e * 1024 + (frac >> 6)) >> 3; /* >> of a negative lane rounds down, as the scalar's */
    WK_VI tiny = ~(r2 >= 1.17549435e-38f), huge = ~(r2 <= 3.40282347e38f) & ~tiny; /* NaN: tiny */
    return (l & ~tiny & ~huge) | (-(1 << 20) & tiny) | ((1 << 20) & huge);
}

/* round(clamp(c, 0, 1) * 255) per lane, NaN as 0. */
static inline WK_VI WK_L(unorm8)(WK_VF c)
{
    WK_VI pos = c > 0.0f; /* false for NaN */
    c = (WK_VF)((WK_VI)c & pos);
    WK_VI low = c < 1.0f;
    WK_VF one = {0};
    one += 1.0f;
    c = (WK_VF)(((WK_VI)c & low) | ((WK_VI)one & ~low));
    return __builtin_convertvector(c * 255.0f + 0.5f, WK_VI);
}

/* (77 r + 150 g + 29 b + 128) >> 8 per lane for r, g, b in 0..255: the sums (at most 65,408)
 * are exact in float, where SSE2 has a multiply and 32-bit integers do not. */
static inline WK_VI WK_L(luma)(WK_VI r, WK_VI g, WK_VI b)
{
    WK_VF s = __builtin_convertvector(r, WK_VF) * 77.0f +
              __builtin_convertvector(g, WK_VF) * 150.0f +
              __builtin_convertvector(b, WK_VF) * 29.0f + 128.0f;
    return __builtin_convertvector(s, WK_VI) >> 8;
}

static inline WK_VF WK_L(plane_at)(const float p[3], WK_VF dx, WK_VF dy)
{
    return (p[0] + p[1] * dx) + p[2] * dy;
}

/* Texture tex (level 0 of tex_w x tex_h texels) at the lanes' pixels, channels in [0, 1]: uv =
 * N / D, the level of detail from the screen derivatives of uv, (N' - uv D') / D, in texels;
 * trilinear samples. */
static void WK_L(texture_at)(const wk_cpu_shade *sh, const wk_cpu_texture *tex, float tex_w,
                             float tex_h, WK_VF dx, WK_VF dy, WK_VF inv, WK_VF out[3])
{
    WK_VF u = WK_L(plane_at)(sh->uv[0], dx, dy) * inv, v = WK_L(plane_at)(sh->uv[1], dx, dy) * inv;
    WK_VF ux = (sh->uv[0][1] - u * sh->den[1]) * inv * tex_w;
    WK_VF vx = (sh->uv[1][1] - v * sh->den[1]) * inv * tex_h;
    WK_VF uy = (sh->uv[0][2] - u * sh->den[2]) * inv * tex_w;
    WK_VF vy = (sh->uv[1][2] - v * sh->den[2]) * inv * tex_h;
    WK_VF rx = ux * ux + vx * vx, ry = uy * uy + vy * vy;
    WK_VI xbig = rx > ry;
    WK_VF r2 = (WK_VF)(((WK_VI)rx & xbig) | ((WK_VI)ry & ~xbig));
    WK_L(sample)(tex, u, v, WK_L(lod_q8)(r2), out);
    for (int ch = 0; ch < 3; ch++)
        out[ch] *= 1.0f / 255.0f;
}

/* The texture's factor on the colour at the lanes' pixels. */
static void WK_L(texture_factor)(const wk_cpu_shade *sh, WK_VF dx, WK_VF dy, WK_VF inv,
                                 WK_VF out[3])
{
    WK_L(texture_at)(sh, sh->tex, sh->tex_w, sh->tex_h, dx, dy, inv, out);
}

/* The light of a normal-mapped pixel, 0.15 + 0.85 |n·l| with n = normalize(T x + B y + N z):
 * the frame interpolated perspective-correct, (x, y, z) = 2 texel - 1. Square roots lane by lane
 * (IEEE, correctly rounded); a zero n lights as 0.15. */
static WK_VF WK_L(normal_light)(const wk_cpu_shade *sh, WK_VF dx, WK_VF dy, WK_VF inv)
{
    WK_VF m[3], n[3];
    WK_L(texture_at)(sh, sh->nrm, sh->nrm_w, sh->nrm_h, dx, dy, inv, m);
    for (int c = 0; c < 3; c++)
        m[c] = m[c] * 2.0f - 1.0f;
    for (int a = 0; a < 3; a++)
        n[a] = (m[0] * (WK_L(plane_at)(sh->frame[a], dx, dy) * inv) +
                m[1] * (WK_L(plane_at)(sh->frame[3 + a], dx, dy) * inv)) +
               m[2] * (WK_L(plane_at)(sh->frame[6 + a], dx, dy) * inv);
    WK_VF len2 = (n[0] * n[0] + n[1] * n[1]) + n[2] * n[2];
    WK_VF dl = (n[0] * sh->light[0] + n[1] * sh->light[1]) + n[2] * sh->light[2];
    WK_VF len;
    for (int k = 0; k < WK_W; k++)
        len[k] = len2[k] > 0.0f ? __builtin_sqrtf(len2[k]) : 1.0f;
    WK_VI nonzero = len2 > 0.0f;
    WK_VF d = (WK_VF)((WK_VI)(dl / len) & 0x7FFFFFFF & nonzero); /* |n·l| / |n| */
    return 0.15f + 0.85f * d;
}

/* The factors of pixels i.. (WK_W of them, all < n) stored by pixel (r0 g0 b0 r1 ...), as
 * vectors by channel, and back. */
static inline void WK_L(factors_load)(const float *at, WK_VF tf[3])
{
#if WK_W == 4 /* three vectors and shuffles, not twelve lanes one by one */
    WK_VF a, b, c;
    memcpy(&a, at, sizeof a);
    memcpy(&b, at + 4, sizeof b);
    memcpy(&c, at + 8, sizeof c);
    tf[0] = __builtin_shufflevector(__builtin_shufflevector(a, b, 0, 3, 6, 7), c, 0, 1, 2, 5);
    tf[1] = __builtin_shufflevector(__builtin_shufflevector(a, b, 1, 4, 7, 7), c, 0, 1, 2, 6);
    tf[2] = __builtin_shufflevector(__builtin_shufflevector(a, b, 2, 5, 5, 5), c, 0, 1, 4, 7);
#else
    for (int k = 0; k < WK_W; k++)
        for (int ch = 0; ch < 3; ch++)
            tf[ch][k] = at[3 * k + ch];
#endif
}

static inline void WK_L(factors_store)(const WK_VF tf[3], float *at)
{
#if WK_W == 4
    WK_VF a = __builtin_shufflevector(__builtin_shufflevector(tf[0], tf[1], 0, 4, 1, 5), tf[2], 0,
                                      1, 4, 2);
    WK_VF b = __builtin_shufflevector(__builtin_shufflevector(tf[1], tf[2], 1, 5, 2, 6), tf[0], 0,
                                      1, 6, 2);
    WK_VF c = __builtin_shufflevector(__builtin_shufflevector(tf[0], tf[1], 3, 7, 3, 7), tf[2], 6,
                                      0, 1, 7);
    memcpy(at, &a, sizeof a);
    memcpy(at + 4, &b, sizeof b);
    memcpy(at + 8, &c, sizeof c);
#else
    for (int k = 0; k < WK_W; k++)
        for (int ch = 0; ch < 3; ch++)
            at[3 * k + ch] = tf[ch][k];
#endif
}

/* The texture's factors of pixels i..i+WK_W-1 (padded with the last of n), sampled or read from
 * and written to texf. */
static void WK_L(group_texture)(const wk_cpu_shade *sh, WK_VF dx, WK_VF dy, WK_VF inv, float *texf,
                                int reuse, size_t i, size_t n, WK_VF tf[3])
{
    if (texf && reuse && i + WK_W <= n) {
        WK_L(factors_load)(texf + 3 * i, tf);
        return;
    }
    if (texf && reuse) {
        for (int k = 0; k < WK_W; k++) {
            size_t at = i + (size_t)k < n ? i + (size_t)k : n - 1;
            for (int ch = 0; ch < 3; ch++)
                tf[ch][k] = texf[3 * at + (size_t)ch];
        }
        return;
    }
    WK_L(texture_factor)(sh, dx, dy, inv, tf);
    if (texf && i + WK_W <= n) {
        WK_L(factors_store)(tf, texf + 3 * i);
        return;
    }
    for (size_t k = 0; texf && k < WK_W && i + k < n; k++)
        for (int ch = 0; ch < 3; ch++)
            texf[3 * (i + k) + (size_t)ch] = tf[ch][k];
}

/* Pixels i..i+WK_W-1 of xy (the group padded with copies of the last pixel, n in all). */
static void WK_L(shade_group)(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy,
                              size_t i, size_t n, uint8_t *restrict c, uint8_t *restrict luma,
                              float *texf, int reuse)
{
    WK_VI px, py;
    for (int k = 0; k < WK_W; k++) {
        uint32_t q = xy[i + (size_t)k < n ? i + (size_t)k : n - 1];
        px[k] = (int32_t)(q & 0xFFFF) - s->x0;
        py[k] = (int32_t)(q >> 16) - s->y0;
    }
    WK_VF dx = __builtin_convertvector(px, WK_VF), dy = __builtin_convertvector(py, WK_VF);
    WK_VF inv = 1.0f / WK_L(plane_at)(sh->den, dx, dy);
    WK_VF col[3];
    for (int ch = 0; ch < 3; ch++)
        col[ch] = WK_L(plane_at)(sh->col[ch], dx, dy) * inv;
    if (sh->nrm) {
        WK_VF f = WK_L(normal_light)(sh, dx, dy, inv);
        for (int ch = 0; ch < 3; ch++)
            col[ch] *= f;
    }
    if (sh->tex) {
        WK_VF tf[3];
        WK_L(group_texture)(sh, dx, dy, inv, texf, reuse, i, n, tf);
        for (int ch = 0; ch < 3; ch++)
            col[ch] *= tf[ch];
    }
    WK_VI vr = WK_L(unorm8)(col[0]), vg = WK_L(unorm8)(col[1]), vb = WK_L(unorm8)(col[2]);
    WK_VI vl = WK_L(luma)(vr, vg, vb);
    for (size_t k = 0; k < WK_W && i + k < n; k++) {
        c[i + k] = (uint8_t)vr[k];
        c[n + i + k] = (uint8_t)vg[k];
        c[2 * n + i + k] = (uint8_t)vb[k];
        luma[i + k] = (uint8_t)vl[k];
    }
}
