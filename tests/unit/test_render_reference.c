/* tests/unit/test_render_reference.c — the renderer still draws what a person once checked: the
 * textured spider (assimp test models) from 4 views of 128x128, laid out 2x2, is compared with
 * tests/data/reference/spider_4x128.png (looked at by eye when it was made) and with the
 * luminance sums recorded below. Exact pixels depend on the rasteriser, so the comparison runs
 * only on the renderer that made the reference and is skipped, saying so, on any other. The CPU
 * rasteriser (another renderer, always there) must look like it: a small mean squared luminance
 * difference (edges and texture filtering differ a little).
 * LUMESH_UPDATE_REFERENCE=1 rewrites the PNG and prints the sums to paste here. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/image.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
#include "common/view.h"
#include "test_support.h"
#include "worker/render/shared/image_store.h"
#include "worker/render/views_local.h"

#define N_VIEWS 4
#define SIZE 128
#define REFERENCE "reference/spider_4x128.png"
/* The renderer that made the reference (GL_RENDERER and GL_VERSION as in the description). */
#define REFERENCE_RENDERER "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL ES 3.2 Mesa 22.3.6"
/* Σ luminance of each view of the reference. */
static const long long reference_sums[N_VIEWS] = {1951827, 1979374, 1967749, 1959909};
/* Tolerances: a pixel may differ by at most 2 levels; at most 0.2% of pixels may differ more; a
 * view's luminance sum may drift by 0.05%. */
#define PIXEL_TOL 2
#define PIXEL_FRACTION 0.002
#define SUM_FRACTION 0.0005

/* The 2x2 montage of the views' colour images, top row first (views 0, 1 / 2, 3). */
static lm_image *render_montage(lm_views *v)
{
    lm_image *img;
    assert_int_equal(lm_image_create(2 * SIZE, 2 * SIZE, &img), LM_OK);
    uint8_t *rgba = malloc((size_t)SIZE * SIZE * 4);
    for (uint32_t h = 0; h < N_VIEWS; h++) {
        assert_int_equal(v->ops->read_image(v, LM_IMAGE_RGBA, h, rgba), LM_OK);
        int ox = (int)(h % 2) * SIZE, oy = (int)(h / 2) * SIZE;
        for (int y = 0; y < SIZE; y++) /* GL rows are bottom first */
            memcpy(img->pixels + (((size_t)(oy + y) * 2 * SIZE) + ox) * 4,
                   rgba + (size_t)(SIZE - 1 - y) * SIZE * 4, (size_t)SIZE * 4);
    }
    free(rgba);
    return img;
}

static long long view_sum(const lm_image *img, uint32_t h)
{
    int ox = (int)(h % 2) * SIZE, oy = (int)(h / 2) * SIZE;
    long long s = 0;
    for (int y = 0; y < SIZE; y++)
        for (int x = 0; x < SIZE; x++)
            s += lm_luma(img->pixels + (((size_t)(oy + y) * 2 * SIZE) + ox + x) * 4);
    return s;
}

static void update_reference(const lm_image *img)
{
    assert_int_equal(lm_image_write(lmt_data_path(REFERENCE), img), LM_OK);
    printf("# wrote %s; sums:", lmt_data_path(REFERENCE));
    for (uint32_t h = 0; h < N_VIEWS; h++)
        printf(" %lld,", view_sum(img, h));
    printf("\n");
}

static void compare(const lm_image *img, const lm_image *ref)
{
    assert_int_equal(ref->width, img->width);
    assert_int_equal(ref->height, img->height);
    size_t n = (size_t)img->width * img->height, off = 0;
    for (size_t i = 0; i < n; i++) {
        int d = (int)lm_luma(img->pixels + 4 * i) - (int)lm_luma(ref->pixels + 4 * i);
        off += (d > PIXEL_TOL || d < -PIXEL_TOL);
    }
    printf("# %zu of %zu pixels differ by more than %d levels\n", off, n, PIXEL_TOL);
    assert_true((double)off <= PIXEL_FRACTION * (double)n);
    for (uint32_t h = 0; h < N_VIEWS; h++) {
        long long s = view_sum(img, h), r = reference_sums[h];
        if (llabs(s - r) > (long long)(SUM_FRACTION * (double)r))
            fail_msg("view %u: luminance sum %lld, reference %lld", h, s, r);
    }
}

static void test_spider_reference(void **state)
{
    (void)state;
    const char *path = lmt_spider_path();
    if (!path) {
        printf("# spider.obj missing (run scripts/install-deps.sh): skipped\n");
        skip();
    }
    lm_mesh *m;
    assert_int_equal(lm_mesh_load(path, NULL, &m), LM_OK);
    float c[3], r;
    lm_mesh_bounding_sphere(m, c, &r);
    lm_view_set *vs = malloc(sizeof *vs);
    assert_int_equal(lm_view_set_make(vs, N_VIEWS, SIZE, c, r), LM_OK);
    lm_views *v;
    assert_int_equal(wk_views_local_create(m, vs, 0, 0, "host", &v), LM_OK);
    lm_views_info info;
    v->ops->info(v, &info);
    lm_image *img = render_montage(v);
    const char *upd = getenv("LUMESH_UPDATE_REFERENCE");
    int other_renderer = !strstr(info.renderer, REFERENCE_RENDERER);
    if (upd && *upd == '1') {
        update_reference(img);
    } else if (other_renderer) {
        printf("# renderer '%s' is not the reference's '%s': comparison skipped\n", info.renderer,
               REFERENCE_RENDERER);
    } else {
        lm_image *ref;
        assert_int_equal(lm_image_read(lmt_data_path(REFERENCE), &ref), LM_OK);
        compare(img, ref);
        lm_image_destroy(ref);
    }
    lm_image_destroy(img);
    lm_views_destroy(v);
    free(vs);
    lm_mesh_destroy(m);
    if (other_renderer && !(upd && *upd == '1'))
        skip();
}

/* The CPU rasteriser's montage against the reference: mean squared luminance difference and the
 * views' luminance sums. */
#define CPU_MSE_MAX 2.0
#define CPU_SUM_FRACTION 0.005
static void test_cpu_looks_like_reference(void **state)
{
    (void)state;
    const char *path = lmt_spider_path();
    if (!path)
        skip();
    lm_mesh *m;
    assert_int_equal(lm_mesh_load(path, NULL, &m), LM_OK);
    float c[3], r;
    lm_mesh_bounding_sphere(m, c, &r);
    lm_view_set *vs = malloc(sizeof *vs);
    assert_int_equal(lm_view_set_make(vs, N_VIEWS, SIZE, c, r), LM_OK);
    lm_views *v;
    assert_int_equal(wk_views_local_create(m, vs, 0, 0, "cpu", &v), LM_OK);
    lm_image *img = render_montage(v), *ref;
    assert_int_equal(lm_image_read(lmt_data_path(REFERENCE), &ref), LM_OK);
    size_t n = (size_t)img->width * img->height;
    double se = 0;
    for (size_t i = 0; i < n; i++) {
        int d = (int)lm_luma(img->pixels + 4 * i) - (int)lm_luma(ref->pixels + 4 * i);
        se += d * d;
    }
    printf("# CPU rasteriser against the reference: mean squared luminance difference %.3f\n",
           se / (double)n);
    assert_true(se / (double)n < CPU_MSE_MAX);
    for (uint32_t h = 0; h < N_VIEWS; h++) {
        long long s = view_sum(img, h), want = reference_sums[h];
        if (llabs(s - want) > (long long)(CPU_SUM_FRACTION * (double)want))
            fail_msg("view %u: luminance sum %lld, reference %lld", h, s, want);
    }
    lm_image_destroy(ref);
    lm_image_destroy(img);
    lm_views_destroy(v);
    free(vs);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_spider_reference),
                                       cmocka_unit_test(test_cpu_looks_like_reference)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
