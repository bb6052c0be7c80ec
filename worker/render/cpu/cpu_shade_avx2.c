/* worker/render/cpu/cpu_shade_avx2.c — the pixels of wk_cpu_shade_pixels eight at a time, for
 * processors with AVX2 (built with -mavx2 on x86-64 only; chosen at run time by
 * wk_cpu_shade_lanes): the code of cpu_shade_lanes.h at eight lanes, and at four for a run's last
 * few pixels. The same IEEE operations lane by lane as the four-lane code and never a fused
 * multiply-add (-ffp-contract=off, no -mfma), so the same bits. Elsewhere it reports itself
 * unsupported. */
#include "worker/render/cpu/cpu_shade.h"

#if defined(__AVX2__)

#include <immintrin.h>
#include <string.h>

typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));

#define WK_W 8
#define WK_VF v8f
#define WK_VI v8i
#define WK_L(name) name##_w8
#include "worker/render/cpu/cpu_shade_lanes.h"
#undef WK_W
#undef WK_VF
#undef WK_VI
#undef WK_L

#define WK_W 4
#define WK_VF v4f
#define WK_VI v4i
#define WK_L(name) name##_w4
#include "worker/render/cpu/cpu_shade_lanes.h"

int wk_cpu_shade_wide_supported(void)
{
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
}

void wk_cpu_shade_pixels_wide(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy,
                              size_t n, uint8_t *rgb, uint8_t *luma, float *texf, int reuse)
{
    size_t i = 0;
    for (; i < n && n - i > 4; i += 8) /* groups of eight while more than four are left */
        shade_group_w8(s, sh, xy, i, n, rgb, luma, texf, reuse);
    if (i < n)
        shade_group_w4(s, sh, xy, i, n, rgb, luma, texf, reuse);
}

#else

#include <stdlib.h>

int wk_cpu_shade_wide_supported(void)
{
    return 0;
}

void wk_cpu_shade_pixels_wide(const wk_cpu_sub *s, const wk_cpu_shade *sh, const uint32_t *xy,
                              size_t n, uint8_t *rgb, uint8_t *luma, float *texf, int reuse)
{
    (void)s, (void)sh, (void)xy, (void)n, (void)rgb, (void)luma, (void)texf, (void)reuse;
    abort(); /* wk_cpu_shade_lanes never picks eight lanes here */
}

#endif
