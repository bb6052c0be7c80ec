/* worker/render/cpu/cpu_self_test.c — renders a known image with the CPU rasteriser and checks it
 * pixel by pixel: the background grey, then a red triangle (lit head-on, so full intensity) over
 * the lower-left half of a 32x32 view whose matrix is the identity (clip space = window space). */
#include "worker/render/cpu/cpu_self_test.h"

#include <string.h>

#include "worker/render/cpu/cpu_raster.h"
#include "worker/render/cpu/cpu_shade.h"

#define ST_SIZE 32

static const lm_tri_data st_tri = {
    .id = 0,
    .material = 0,
    .c = {{{-1, -1, 0}, {0, 0, 1}, {0, 0}, {1, 0, 0, 1}},
          {{1, -1, 0}, {0, 0, 1}, {0, 0}, {1, 0, 0, 1}},
          {{-1, 1, 0}, {0, 0, 1}, {0, 0}, {1, 0, 0, 1}}},
};

/* Keys and colours of the test image. */
static void render(uint64_t *key, uint8_t (*rgb)[3])
{
    lm_view view = {.width = ST_SIZE, .height = ST_SIZE, .dir = {0, 0, 1}};
    for (int i = 0; i < 4; i++)
        view.view_proj[5 * i] = 1.0f;
    for (int i = 0; i < ST_SIZE * ST_SIZE; i++) {
        key[i] = WK_CPU_KEY_BG;
        memset(rgb[i], WK_CPU_BACKGROUND, 3);
    }
    wk_cpu_keys k = {
        .key = key, .width = ST_SIZE, .height = ST_SIZE, .tiles_w = ST_SIZE / WK_CPU_TILE};
    const wk_cpu_clip all = {{0, 0, ST_SIZE, ST_SIZE}, NULL};
    float diffuse[1][4] = {{1, 1, 1, 1}};
    wk_cpu_texture *none[1] = {NULL};
    const wk_cpu_materials mats = {1, diffuse, none, NULL};
    wk_cpu_sub subs[WK_CPU_MAX_SUBS];
    uint32_t owned[ST_SIZE * ST_SIZE];
    wk_cpu_view cv;
    wk_cpu_view_init(&view, &cv);
    int n = wk_cpu_tri_setup(&cv, &st_tri, subs);
    for (int i = 0; i < n; i++)
        wk_cpu_draw(&subs[i], &k, &all, NULL, 0);
    for (int i = 0; i < n; i++) {
        wk_cpu_shade sh;
        wk_cpu_shade_setup(&subs[i], &st_tri, view.dir, &mats, &sh);
        size_t m = wk_cpu_owned(&subs[i], &k, &all.rect, owned, ST_SIZE * ST_SIZE);
        uint8_t c[3 * ST_SIZE * ST_SIZE], luma[ST_SIZE * ST_SIZE];
        wk_cpu_shade_pixels(&subs[i], &sh, owned, m, c, luma, NULL, 0);
        for (size_t j = 0; j < m; j++) {
            int x = WK_CPU_X(owned[j]), y = WK_CPU_Y(owned[j]);
            for (int ch = 0; ch < 3; ch++)
                rgb[y * ST_SIZE + x][ch] = c[ch * m + j];
        }
    }
}

lm_status wk_cpu_self_test_run(int *covered)
{
    uint64_t key[ST_SIZE * ST_SIZE];
    uint8_t rgb[ST_SIZE * ST_SIZE][3];
    render(key, rgb);
    int red = 0;
    for (int y = 0; y < ST_SIZE; y++)
        for (int x = 0; x < ST_SIZE; x++) {
            const uint8_t *p = rgb[y * ST_SIZE + x];
            int is_red = p[0] == 255 && p[1] == 0 && p[2] == 0;
            int is_grey = p[0] == WK_CPU_BACKGROUND && p[1] == p[0] && p[2] == p[0];
            int expect_red = x + y<ST_SIZE - 1, expect_grey = x + y> ST_SIZE - 1;
            if ((expect_red && !is_red) || (expect_grey && !is_grey) || (!is_red && !is_grey))
                return lm_fail(LM_E_DEVICE, "CPU self-test: pixel (%d,%d) is %u,%u,%u, expected %s",
                               x, y, p[0], p[1], p[2], expect_red ? "red" : "grey");
            red += is_red;
        }
    if (covered)
        *covered = red;
    return LM_OK;
}
