/* worker/render/cpu/cpu_sample_lanes.h — trilinear texture sampling of WK_W points at a time
 * (repeat wrapping, the level's weight in 1/256), written once for any lane count: included by the
 * files that instantiate it, with WK_W (4 or 8), WK_VF / WK_VI (float and int32 vectors of WK_W
 * lanes) and WK_L(name) (the name with the width's suffix) defined. Every operation is the IEEE (or
 * two's complement) one lane by lane, so a point's result never depends on the width nor on the
 * other points of its group. At eight lanes with AVX2 the includer provides <immintrin.h> (texel
 * gathers). No include guard: one inclusion per width. */

/* u - floor(u) in [0, 1] per lane; 0 for huge (integral) or non-finite u. */
static inline WK_VF WK_L(fraction)(WK_VF u)
{
    WK_VI ok = (u < 8388608.0f) & (u > -8388608.0f); /* false: NaN */
    u = (WK_VF)((WK_VI)u & ok);
    WK_VF i = __builtin_convertvector(__builtin_convertvector(u, WK_VI), WK_VF);
    WK_VI above = i > u;
    return u - (WK_VF)(((WK_VI)(i - 1.0f) & above) | ((WK_VI)i & ~above));
}

/* Texel pairs and weights along one axis: s = f size - 1/2, texel floor(s) and the next one,
 * repeating, and the weight of the next one. */
static inline void WK_L(axis)(WK_VF f, WK_VI size, WK_VI *i0, WK_VI *i1, WK_VF *w)
{
    WK_VF s = f * __builtin_convertvector(size, WK_VF) - 0.5f; /* in [-0.5, size - 0.5] */
    WK_VI fl = __builtin_convertvector(s + 1.0f, WK_VI) - 1;   /* floor: s + 1 > 0 */
    *w = s - __builtin_convertvector(fl, WK_VF);               /* in [0, 1) */
    fl += (fl < 0) & size;                                     /* -1 -> size - 1 */
    fl -= (fl >= size) & size;
    *i0 = fl;
    *i1 = (fl + 1) & ~(fl + 1 == size); /* size -> 0 */
}

/* The bilinear mix of four texels a lane (texel[0], [1] along x, [2], [3] the row above) with the
 * weights of the second of each pair, channels 0..255. */
static inline void WK_L(lerp_texels)(const WK_VI texel[4], WK_VF wx, WK_VF wy, WK_VF out[3])
{
    for (int ch = 0; ch < 3; ch++) {
        WK_VF v[4];
        for (int c = 0; c < 4; c++)
            v[c] = __builtin_convertvector((texel[c] >> (8 * ch)) & 255, WK_VF);
        WK_VF lo = v[0] + (v[1] - v[0]) * wx, hi = v[2] + (v[3] - v[2]) * wx;
        out[ch] = lo + (hi - lo) * wy; /* lerps: exact where the texels agree */
    }
}

/* Bilinear samples of level lv[k] at lane k (fractions fu, fv), channels 0..255. */
static void WK_L(bilinear)(const wk_cpu_texture *t, WK_VI lv, WK_VF fu, WK_VF fv, WK_VF out[3])
{
    WK_VI w, h, base;
    for (int k = 0; k < WK_W; k++) {
        w[k] = t->width[lv[k]];
        h[k] = t->height[lv[k]];
        base[k] = t->offset[lv[k]];
    }
    WK_VI x0, x1, y0, y1;
    WK_VF wx, wy;
    WK_L(axis)(fu, w, &x0, &x1, &wx);
    WK_L(axis)(fv, h, &y0, &y1, &wy);
    WK_VI r0 = base + y0 * w, r1 = base + y1 * w, at[4] = {r0 + x0, r0 + x1, r1 + x0, r1 + x1};
    WK_VI texel[4];
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < WK_W; k++)
            texel[c][k] = (int32_t)t->data[at[c][k]];
    WK_L(lerp_texels)(texel, wx, wy, out);
}

/* The bilinear samples where every lane reads level l (neighbouring pixels nearly always do):
 * the level's size and place loaded once, the same bits. */
static void WK_L(bilinear_at)(const wk_cpu_texture *t, int l, WK_VF fu, WK_VF fv, WK_VF out[3])
{
    const int32_t w = t->width[l], h = t->height[l];
    WK_VI x0, x1, y0, y1, ws = {0}, hs = {0};
    WK_VF wx, wy;
    WK_L(axis)(fu, ws + w, &x0, &x1, &wx);
    WK_L(axis)(fv, hs + h, &y0, &y1, &wy);
    const int32_t *data = (const int32_t *)(t->data + t->offset[l]);
    WK_VI r0 = y0 * w, r1 = y1 * w, texel[4];
#if WK_W == 8 && defined(__AVX2__)
    const WK_VI at[4] = {r0 + x0, r0 + x1, r1 + x0, r1 + x1}; /* < 2^31: a level's texels */
    for (int c = 0; c < 4; c++)
        texel[c] = (WK_VI)_mm256_i32gather_epi32(data, (__m256i)at[c], 4);
#else
    for (int k = 0; k < WK_W; k++) {
        texel[0][k] = data[r0[k] + x0[k]];
        texel[1][k] = data[r0[k] + x1[k]];
        texel[2][k] = data[r1[k] + x0[k]];
        texel[3][k] = data[r1[k] + x1[k]];
    }
#endif
    WK_L(lerp_texels)(texel, wx, wy, out);
}

static inline int WK_L(same_lanes)(WK_VI a)
{
    int same = 1;
    for (int k = 1; k < WK_W; k++)
        same &= a[k] == a[0];
    return same;
}

/* Texture colour at WK_W points (as wk_cpu_texture_sample4, cpu_texture.h). */
static void WK_L(sample)(const wk_cpu_texture *t, WK_VF u, WK_VF v, WK_VI lod, WK_VF out[3])
{
    const int32_t n = t->n_levels - 1;
    WK_VI last = {0}, mag = lod <= 0, d = (lod >> 8) & ~mag;
    last += n;
    WK_VI top = d >= last;
    d = (d & ~top) | (last & top);
    WK_VI d1 = d + 1;
    d1 = (d1 & ~(d1 > last)) | (last & (d1 > last));
    WK_VF f = __builtin_convertvector(lod & 255 & ~mag & ~top, WK_VF) * (1.0f / 256.0f);
    WK_VF fu = WK_L(fraction)(u), fv = WK_L(fraction)(v), a[3], b[3];
    WK_VI flat = f == 0.0f; /* the finer level alone: a + (b - a) 0 is a, bit for bit */
    int one_level = WK_L(same_lanes)(d), fine_only = 1;
    for (int k = 0; k < WK_W; k++)
        fine_only &= flat[k] != 0;
    if (one_level)
        WK_L(bilinear_at)(t, d[0], fu, fv, a);
    else
        WK_L(bilinear)(t, d, fu, fv, a);
    if (fine_only) {
        for (int ch = 0; ch < 3; ch++)
            out[ch] = a[ch];
        return;
    }
    if (one_level)
        WK_L(bilinear_at)(t, d1[0], fu, fv, b);
    else
        WK_L(bilinear)(t, d1, fu, fv, b);
    for (int ch = 0; ch < 3; ch++)
        out[ch] = a[ch] + (b[ch] - a[ch]) * f;
}
