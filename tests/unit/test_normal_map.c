/* tests/unit/test_normal_map.c — tangent-space normal maps: the tangents of a flat quad, the CPU
 * renderer's shading of a normal-mapped quad against a reference computed here pixel by pixel
 * (within one 8-bit level; the GL renderer on llvmpipe within four) and against the same quad
 * without the map, four lanes against eight,
 * a GLB round trip (normalTexture and TANGENT written, the map loaded back, the same image) and an
 * OBJ one (MTL "norm"), and the asset that ships it to workers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "common/io/mesh_io.h"
#include "common/tangents.h"
#include "common/view.h"
#include "proto/asset.h"
#include "test_support.h"
#include "worker/render/cpu/cpu_shade.h"
#include "worker/render/views_local.h"

#define SIZE 64
#define N_VIEWS 6
#define MAP 4 /* texels a side */

/* A MAP x MAP normal map of distinct, strongly tilted normals (rows top first, as images are). */
static lm_image *make_normal_map(void)
{
    lm_image *img;
    assert_int_equal(lm_image_create(MAP, MAP, &img), LM_OK);
    for (int i = 0; i < MAP * MAP; i++) {
        uint8_t *p = img->pixels + 4 * i;
        p[0] = (uint8_t)(40 + 55 * (i % MAP));      /* x: -0.69 .. 0.6 */
        p[1] = (uint8_t)(230 - 50 * (i / MAP));     /* y: 0.8 .. -0.38 */
        p[2] = (uint8_t)(150 + 30 * ((i * 7) % 4)); /* z: 0.18 .. 0.88 */
        p[3] = 255;
    }
    return img;
}

/* The unit quad [0,1]² in z = 0, uv = xy, normal +z; with the normal map when mapped. */
static lm_mesh *make_quad(int mapped)
{
    lm_mesh *m = lmt_make_grid(2);
    if (mapped)
        assert_int_equal(lm_mesh_set_normal_map(m, 0, "n.png", make_normal_map()), LM_OK);
    return m;
}

/* The map's bilinear sample at (u, v) (GL: texel centres at (i + 0.5) / MAP, repeat; uv (0,0) at
 * the image's bottom left), channel ch, in 0..255. */
static double bilinear(const lm_image *img, double u, double v, int ch)
{
    double s = u * MAP - 0.5, t = v * MAP - 0.5;
    int i0 = (int)floor(s), j0 = (int)floor(t);
    double fs = s - i0, ft = t - j0, sum = 0.0;
    for (int dj = 0; dj < 2; dj++)
        for (int di = 0; di < 2; di++) {
            int i = ((i0 + di) % MAP + MAP) % MAP, j = ((j0 + dj) % MAP + MAP) % MAP;
            double w = (di ? fs : 1.0 - fs) * (dj ? ft : 1.0 - ft);
            sum += w * img->pixels[4 * ((MAP - 1 - j) * MAP + i) + ch];
        }
    return sum;
}

/* Where pixel (px, py)'s centre ray meets z = 0 in view vw: (x, y) = (u, v) on the quad. */
static void unproject(const lm_view *vw, int px, int py, double *x, double *y)
{
    const float *m = vw->view_proj;
    double nx = 2.0 * (px + 0.5) / vw->width - 1.0, ny = 2.0 * (py + 0.5) / vw->height - 1.0;
    double a11 = m[0] - nx * m[3], a12 = m[4] - nx * m[7], c1 = -(m[12] - nx * m[15]);
    double a21 = m[1] - ny * m[3], a22 = m[5] - ny * m[7], c2 = -(m[13] - ny * m[15]);
    double det = a11 * a22 - a12 * a21;
    *x = (c1 * a22 - a12 * c2) / det;
    *y = (a11 * c2 - c1 * a21) / det;
}

/* The reference colour (8-bit, every channel alike: white corners and diffuse) of the mapped quad
 * at (u, v) lit along dir: 0.15 + 0.85 |n·l|, n the normalised sample (T = x, B = y, N = z). */
static int reference(const lm_image *map, double u, double v, const float dir[3])
{
    double n[3], len = 0.0, d = 0.0;
    for (int c = 0; c < 3; c++) {
        n[c] = bilinear(map, u, v, c) / 255.0 * 2.0 - 1.0;
        len += n[c] * n[c];
        d += n[c] * dir[c];
    }
    double f = 0.15 + 0.85 * fabs(d) / sqrt(len);
    return (int)floor(f * 255.0 + 0.5);
}

static lm_view_set *quad_views(void)
{
    lm_view_set *vs = malloc(sizeof *vs);
    const float centre[3] = {0.5f, 0.5f, 0.0f};
    assert_int_equal(lm_view_set_make(vs, N_VIEWS, SIZE, centre, 0.75f), LM_OK);
    return vs;
}

/* The RGBA and coverage images of m in every view on device dev; 0 where it cannot be opened. */
static int render_on(const char *dev, const lm_mesh *m, const lm_view_set *vs,
                     uint8_t (*rgba)[SIZE * SIZE * 4], uint8_t (*cover)[SIZE * SIZE])
{
    lm_views *v;
    if (wk_views_local_create(m, vs, 0, 0, dev, &v) != LM_OK)
        return 0;
    for (uint32_t k = 0; k < vs->count; k++) {
        assert_int_equal(v->ops->read_image(v, LM_IMAGE_RGBA, k, rgba[k]), LM_OK);
        assert_int_equal(v->ops->read_image(v, LM_IMAGE_COVERAGE, k, cover[k]), LM_OK);
    }
    lm_views_destroy(v);
    return 1;
}

/* ... on the CPU rasteriser. */
static void render(const lm_mesh *m, const lm_view_set *vs, uint8_t (*rgba)[SIZE * SIZE * 4],
                   uint8_t (*cover)[SIZE * SIZE])
{
    assert_true(render_on("cpu", m, vs, rgba, cover));
}

static uint8_t rgba[2][N_VIEWS][SIZE * SIZE * 4], cover[2][N_VIEWS][SIZE * SIZE];

static void test_quad_tangents(void **state)
{
    (void)state;
    lm_mesh *m = make_quad(0);
    float(*tan)[4];
    assert_int_equal(lm_mesh_tangents(m, &tan), LM_OK);
    for (uint32_t w = 0; w < m->n_wedges; w++) {
        assert_true(tan[w][0] == 1.0f && tan[w][1] == 0.0f && tan[w][2] == 0.0f);
        assert_true(tan[w][3] == 1.0f);
    }
    free(tan);
    for (uint32_t w = 0; w < m->n_wedges; w++) /* u mirrored: the tangent turns, w stays */
        m->wedges[w].uv[0] = 1.0f - m->wedges[w].uv[0];
    assert_int_equal(lm_mesh_tangents(m, &tan), LM_OK);
    assert_true(tan[0][0] == -1.0f && tan[0][3] == -1.0f);
    free(tan);
    lm_mesh_destroy(m);
}

/* The mapped quad rendered on dev equals the reference within tol levels at every pixel well
 * inside it (and 90 % of the channels within one), in every view that sees it at more than a
 * grazing angle; the unmapped quad differs. */
static void check_against_reference(const char *dev, int tol)
{
    lm_view_set *vs = quad_views();
    lm_mesh *mapped = make_quad(1), *plain = make_quad(0);
    if (!render_on(dev, mapped, vs, rgba[0], cover[0]) ||
        !render_on(dev, plain, vs, rgba[1], cover[1])) {
        printf("# device %s: not on this machine, skipped\n", dev);
        lm_mesh_destroy(mapped);
        lm_mesh_destroy(plain);
        free(vs);
        return;
    }
    const lm_image *map = mapped->materials[0].normal_map;
    int checked = 0, differ = 0, worst = 0, hist[4] = {0};
    for (uint32_t k = 0; k < vs->count; k++) {
        const lm_view *vw = &vs->views[k];
        if (fabsf(vw->dir[2]) < 0.3f)
            continue;
        for (int py = 0; py < SIZE; py++)
            for (int px = 0; px < SIZE; px++) {
                size_t i = (size_t)py * SIZE + px;
                double u, v;
                unproject(vw, px, py, &u, &v);
                if (!cover[0][k][i] || u < 0.02 || u > 0.98 || v < 0.02 || v > 0.98)
                    continue;
                int want = reference(map, u, v, vw->dir);
                for (int c = 0; c < 3; c++) {
                    int got = rgba[0][k][4 * i + (size_t)c], e = abs(got - want);
                    worst = e > worst ? e : worst;
                    hist[e < 3 ? e : 3]++;
                    if (e > tol)
                        fail_msg("view %u pixel (%d, %d) channel %d: %d, reference %d", k, px, py,
                                 c, got, want);
                }
                checked++;
                differ += rgba[0][k][4 * i] != rgba[1][k][4 * i];
            }
    }
    printf("# %s: %d pixels checked, worst difference %d (channels off by 0, 1, 2, more: %d %d %d "
           "%d), %d differ without the map\n",
           dev, checked, worst, hist[0], hist[1], hist[2], hist[3], differ);
    assert_true(checked > 2000);
    assert_true(hist[0] + hist[1] >= 3 * checked * 9 / 10); /* nearly all within one level */
    assert_true(differ > checked / 2);
    lm_mesh_destroy(mapped);
    lm_mesh_destroy(plain);
    free(vs);
}

/* The CPU rasteriser: within one 8-bit level. */
static void test_render_matches_reference(void **state)
{
    (void)state;
    check_against_reference("cpu", 1);
}

/* The GL renderer on Mesa's llvmpipe (where there is one): its frame comes from screen
 * derivatives and its filtering is the device's (8-bit weights), so within 4 levels (measured:
 * 3, and 2 % of the channels above 1). */
static void test_gl_render_matches_reference(void **state)
{
    (void)state;
    check_against_reference("host", 4);
}

/* Four and eight lanes shade the mapped quad to the same bytes. */
static void test_lanes_agree(void **state)
{
    (void)state;
    int before = wk_cpu_shade_lanes();
    if (wk_cpu_shade_set_lanes(8) != 8) {
        printf("# 8 lanes: not on this processor or build, skipped\n");
        wk_cpu_shade_set_lanes(before);
        return;
    }
    lm_view_set *vs = quad_views();
    lm_mesh *m = make_quad(1);
    m->materials[0].diffuse[1] = 0.5f;
    render(m, vs, rgba[0], cover[0]);
    wk_cpu_shade_set_lanes(4);
    render(m, vs, rgba[1], cover[1]);
    assert_memory_equal(rgba[0], rgba[1], sizeof rgba[0]);
    wk_cpu_shade_set_lanes(before);
    lm_mesh_destroy(m);
    free(vs);
}

static char *read_all(const char *path, size_t *n)
{
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    char *b = malloc((size_t)st.st_size + 1);
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    *n = fread(b, 1, (size_t)st.st_size, fp);
    fclose(fp);
    b[*n] = '\0';
    return b;
}

/* A normal-mapped GLB: normalTexture and TANGENT in its JSON, the map loaded back texel for texel,
 * and the loaded mesh renders as the saved one. */
static void test_glb_round_trip(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp(), path[1024];
    snprintf(path, sizeof path, "%s/quad.glb", dir);
    lm_mesh *m = make_quad(1), *back = NULL;
    assert_int_equal(lm_mesh_save(path, m), LM_OK);
    size_t n;
    char *bytes = read_all(path, &n);
    uint32_t json_len;
    memcpy(&json_len, bytes + 12, 4);
    bytes[20 + json_len] = '\0'; /* the JSON chunk alone */
    assert_non_null(strstr(bytes + 20, "\"normalTexture\":{\"index\":0}"));
    assert_non_null(strstr(bytes + 20, "\"TANGENT\":"));
    free(bytes);
    assert_int_equal(lm_mesh_load(path, NULL, &back), LM_OK);
    assert_int_equal(back->n_materials, 1);
    const lm_image *a = m->materials[0].normal_map, *b = back->materials[0].normal_map;
    assert_non_null(b);
    assert_int_equal(b->width, MAP);
    assert_int_equal(b->height, MAP);
    assert_memory_equal(a->pixels, b->pixels, MAP * MAP * 4);
    lm_view_set *vs = quad_views();
    render(m, vs, rgba[0], cover[0]);
    render(back, vs, rgba[1], cover[1]);
    assert_memory_equal(rgba[0], rgba[1], sizeof rgba[0]);
    free(vs);
    lm_mesh_destroy(back);
    lm_mesh_destroy(m);
    lmt_rmdir(dir);
}

/* An OBJ keeps the normal map too (an MTL "norm" beside the texture's "map_Kd"). */
static void test_obj_round_trip(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp(), path[1024];
    snprintf(path, sizeof path, "%s/quad.obj", dir);
    lm_mesh *m = make_quad(1), *back = NULL;
    assert_int_equal(lm_mesh_save(path, m), LM_OK);
    assert_int_equal(lm_mesh_load(path, NULL, &back), LM_OK);
    const lm_image *b = back->materials[0].normal_map;
    assert_non_null(b);
    assert_memory_equal(m->materials[0].normal_map->pixels, b->pixels, MAP * MAP * 4);
    lm_mesh_destroy(back);
    lm_mesh_destroy(m);
    lmt_rmdir(dir);
}

/* Workers get the normal map with the mesh's materials: it is one more texture the asset names. */
static void test_asset_round_trip(void **state)
{
    (void)state;
    lm_mesh *m = make_quad(1), *back = NULL;
    lm_asset_set set;
    lm_asset_set_init(&set);
    lm_asset_hash h;
    assert_int_equal(lm_asset_pack_mesh(m, &set, &h), LM_OK);
    const lm_asset *a = lm_asset_set_find(&set, &h);
    assert_non_null(a);
    lm_asset_hash *refs;
    uint32_t n;
    assert_int_equal(lm_asset_refs(a->data, a->size, &refs, &n), LM_OK);
    assert_int_equal(n, 1);
    assert_non_null(lm_asset_set_find(&set, &refs[0]));
    free(refs);
    assert_int_equal(lm_asset_unpack_mesh(a->data, a->size, &set, &back), LM_OK);
    assert_non_null(back->materials[0].normal_map);
    assert_memory_equal(m->materials[0].normal_map->pixels, back->materials[0].normal_map->pixels,
                        MAP * MAP * 4);
    lm_mesh_destroy(back);
    /* a table whose normal map is missing from the set, or cut short, is refused */
    lm_asset_set empty;
    lm_asset_set_init(&empty);
    assert_int_equal(lm_asset_unpack_mesh(a->data, a->size, &empty, &back), LM_E_FORMAT);
    assert_int_equal(lm_asset_unpack_mesh(a->data, a->size - 1, &set, &back), LM_E_FORMAT);
    lm_asset_set_free(&empty);
    lm_asset_set_free(&set);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quad_tangents),
        cmocka_unit_test(test_render_matches_reference),
        cmocka_unit_test(test_gl_render_matches_reference),
        cmocka_unit_test(test_lanes_agree),
        cmocka_unit_test(test_glb_round_trip),
        cmocka_unit_test(test_obj_round_trip),
        cmocka_unit_test(test_asset_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
