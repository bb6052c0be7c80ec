/* tests/unit/test_cpu_raster.c — the CPU rasteriser's parts on their own: every drawn key equals
 * the direct evaluation of the subs (random triangles, clip rectangles, tile masks and depth-tile
 * rejection), the fill rule is watertight (a jittered grid covers each pixel centre of its inside
 * exactly once), drawing order does not matter, near-plane clipping makes a watertight fan, the
 * integer level of detail, texture sampling, shading of runs against single pixels, four lanes
 * against eight, and a golden hash of rendered images that pins the arithmetic (bump
 * WK_CPU_RASTERISER's version with it). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/view.h"
#include "test_support.h"
#include "worker/render/cpu/cpu_raster.h"
#include "worker/render/cpu/cpu_shade.h"
#include "worker/render/cpu/cpu_simd.h"
#include "worker/render/cpu/cpu_texture.h"
#include "worker/render/views_local.h"

#define W 64
#define H 48

static uint64_t rng = 0x2545F4914F6CDD1Dull;
static double urand(void)
{
    return lmt_urand(&rng);
}

/* A view whose clip space is the window: x, y in pixels map to themselves, z in (-1, 1). */
static void window_view(wk_cpu_view *v)
{
    memset(v, 0, sizeof *v);
    v->m[0] = 2.0 / W;
    v->m[5] = 2.0 / H;
    v->m[10] = 1.0;
    v->m[12] = -1.0;
    v->m[13] = -1.0;
    v->m[15] = 1.0;
    v->width = W;
    v->height = H;
}

static lm_tri_data random_tri(uint32_t id, double spread)
{
    lm_tri_data t;
    memset(&t, 0, sizeof t);
    t.id = id;
    double cx = urand() * W, cy = urand() * H;
    for (int k = 0; k < 3; k++) {
        t.c[k].pos[0] = (float)(cx + (urand() - 0.5) * spread);
        t.c[k].pos[1] = (float)(cy + (urand() - 0.5) * spread);
        t.c[k].pos[2] = (float)(urand() * 1.8 - 0.9);
        t.c[k].normal[2] = 1.0f;
        for (int ch = 0; ch < 4; ch++)
            t.c[k].color[ch] = (float)urand();
        t.c[k].uv[0] = (float)urand();
        t.c[k].uv[1] = (float)urand();
    }
    return t;
}

static void fill(uint64_t *key, size_t n, uint64_t value)
{
    for (size_t i = 0; i < n; i++)
        key[i] = value;
}

/* The least key over subs[0..n) at every pixel of clip (and of the mask), by direct evaluation. */
static void reference(const wk_cpu_sub *subs, int n, const wk_cpu_clip *clip, uint64_t *key)
{
    for (int y = clip->rect.y0; y < clip->rect.y1; y++)
        for (int x = clip->rect.x0; x < clip->rect.x1; x++) {
            if (clip->tile_mask &&
                !clip->tile_mask[(y / WK_CPU_TILE) * (W / WK_CPU_TILE) + x / WK_CPU_TILE])
                continue;
            for (int i = 0; i < n; i++) {
                uint64_t k;
                if (wk_cpu_sub_key_at(&subs[i], x, y, &k) && k < key[y * W + x])
                    key[y * W + x] = k;
            }
        }
}

static void test_draw_matches_direct_evaluation(void **state)
{
    (void)state;
    wk_cpu_view v;
    window_view(&v);
    static uint64_t got[W * H], want[W * H];
    static uint8_t mask[(W / WK_CPU_TILE) * (H / WK_CPU_TILE)];
    for (int round = 0; round < 400; round++) {
        wk_cpu_sub subs[64 * WK_CPU_MAX_SUBS];
        int n = 0, tris = 1 + (int)(urand() * 12);
        double spread = round % 4 == 0 ? 400.0 : round % 4 == 1 ? 3.0 : 30.0;
        for (int t = 0; t < tris; t++) {
            lm_tri_data tri = random_tri((uint32_t)t, spread);
            n += wk_cpu_tri_setup(&v, &tri, subs + n);
        }
        wk_cpu_clip clip = {{0, 0, W, H}, NULL};
        if (round % 3 == 1) {
            int x0 = (int)(urand() * W), y0 = (int)(urand() * H);
            clip.rect = (wk_rect){x0, y0, x0 + 1 + (int)(urand() * (W - x0)),
                                  y0 + 1 + (int)(urand() * (H - y0))};
        }
        if (round % 3 == 2) {
            for (size_t i = 0; i < sizeof mask; i++)
                mask[i] = urand() < 0.5;
            clip.tile_mask = mask;
        }
        fill(got, W * H, WK_CPU_KEY_BG);
        fill(want, W * H, WK_CPU_KEY_BG);
        wk_cpu_keys k = {.key = got, .width = W, .height = H, .tiles_w = W / WK_CPU_TILE};
        for (int i = 0; i < n; i++)
            wk_cpu_draw(&subs[i], &k, &clip, NULL, 0);
        reference(subs, n, &clip, want);
        assert_memory_equal(got, want, sizeof got);
    }
}

/* Drawing order, and skipping tiles by their maxima, change nothing. */
static void test_order_and_tile_rejection(void **state)
{
    (void)state;
    wk_cpu_view v;
    window_view(&v);
    static uint64_t a[W * H], b[W * H], tmax[(W / WK_CPU_TILE) * (H / WK_CPU_TILE)];
    for (int round = 0; round < 50; round++) {
        wk_cpu_sub subs[40 * WK_CPU_MAX_SUBS];
        int n = 0;
        for (int t = 0; t < 40; t++) {
            lm_tri_data tri = random_tri((uint32_t)t, 25.0);
            n += wk_cpu_tri_setup(&v, &tri, subs + n);
        }
        fill(a, W * H, WK_CPU_KEY_BG);
        fill(b, W * H, WK_CPU_KEY_BG);
        const wk_cpu_clip all = {{0, 0, W, H}, NULL};
        wk_cpu_keys ka = {.key = a, .width = W, .height = H, .tiles_w = W / WK_CPU_TILE};
        for (int i = 0; i < n; i++)
            wk_cpu_draw(&subs[i], &ka, &all, NULL, 0);
        fill(tmax, sizeof tmax / sizeof *tmax, WK_CPU_KEY_BG);
        wk_cpu_keys kb = {.key = b, .tmax = tmax, .width = W, .height = H, .tiles_w = W / 8};
        for (int i = n - 1; i >= 0; i--) { /* reverse order, maxima kept exact as it goes */
            wk_cpu_draw(&subs[i], &kb, &all, NULL, 0);
            wk_cpu_keys_update_tiles(&kb, &all.rect);
        }
        assert_memory_equal(a, b, sizeof a);
    }
}

/* A jittered grid of triangles (both diagonals, both orientations) covers every pixel centre of
 * its inside once: shared edges neither double nor drop a pixel. */
static void test_watertight(void **state)
{
    (void)state;
    wk_cpu_view v;
    window_view(&v);
    enum { N = 7 };
    float grid[N + 1][N + 1][2];
    for (int round = 0; round < 30; round++) {
        for (int i = 0; i <= N; i++)
            for (int j = 0; j <= N; j++) {
                int edge = i == 0 || j == 0 || i == N || j == N;
                grid[i][j][0] = (float)(4 + i * 7.3 + (edge ? 0 : (urand() - 0.5) * 5.0));
                grid[i][j][1] = (float)(3 + j * 5.3 + (edge ? 0 : (urand() - 0.5) * 3.5));
            }
        static uint8_t count[W * H];
        memset(count, 0, sizeof count);
        uint32_t id = 0;
        for (int i = 0; i < N; i++)
            for (int j = 0; j < N; j++) {
                const float *q[4] = {grid[i][j], grid[i + 1][j], grid[i + 1][j + 1],
                                     grid[i][j + 1]};
                int d = urand() < 0.5; /* which diagonal */
                const float *tri[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
                const float *other[2][3] = {{q[0], q[1], q[3]}, {q[1], q[2], q[3]}};
                if (d)
                    memcpy(tri, other, sizeof tri);
                for (int t = 0; t < 2; t++) {
                    lm_tri_data td;
                    memset(&td, 0, sizeof td);
                    td.id = id++;
                    int flip = urand() < 0.5; /* random winding */
                    for (int k = 0; k < 3; k++) {
                        const float *p = tri[t][flip ? 2 - k : k];
                        td.c[k].pos[0] = p[0];
                        td.c[k].pos[1] = p[1];
                    }
                    wk_cpu_sub subs[WK_CPU_MAX_SUBS];
                    int n = wk_cpu_tri_setup(&v, &td, subs);
                    for (int s = 0; s < n; s++)
                        for (int y = 0; y < H; y++)
                            for (int x = 0; x < W; x++) {
                                uint64_t key;
                                count[y * W + x] += wk_cpu_sub_key_at(&subs[s], x, y, &key);
                            }
                }
            }
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                double cx = x + 0.5, cy = y + 0.5;
                int inside = cx > 4 && cx < 4 + N * 7.3 && cy > 3 && cy < 3 + N * 5.3;
                if (count[y * W + x] != inside)
                    fail_msg("round %d: pixel (%d,%d) covered %d times", round, x, y,
                             count[y * W + x]);
            }
    }
}

/* A triangle through the near plane: several subs, none overlapping, keys inside the range. */
static void test_near_clipping(void **state)
{
    (void)state;
    lm_view_set *vs = malloc(sizeof *vs);
    const float c[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(vs, 1, 64, c, 1.0f), LM_OK);
    wk_cpu_view v;
    wk_cpu_view_init(&vs->views[0], &v);
    lm_tri_data t;
    memset(&t, 0, sizeof t);
    t.id = 5;
    for (int k = 0; k < 3; k++)
        memcpy(t.c[k].pos, c, sizeof c);
    const lm_view *lv = &vs->views[0];
    const float *eye = lv->eye, *dir = lv->dir;
    const float right[3] = {lv->view[0], lv->view[4], lv->view[8]};
    const float up[3] = {lv->view[1], lv->view[5], lv->view[9]};
    for (int a = 0; a < 3; a++) { /* one corner behind the eye, two beside the centre */
        t.c[0].pos[a] = eye[a] - 0.5f * dir[a] + 0.2f * up[a];
        t.c[1].pos[a] = 0.6f * right[a] + 0.3f * dir[a];
        t.c[2].pos[a] = -0.5f * right[a] - 0.4f * up[a] - 0.2f * dir[a];
    }
    wk_cpu_sub subs[WK_CPU_MAX_SUBS];
    int n = wk_cpu_tri_setup(&v, &t, subs);
    assert_true(n >= 1 && n <= WK_CPU_MAX_SUBS);
    int covered = 0;
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++) {
            int hits = 0;
            for (int s = 0; s < n; s++) {
                uint64_t key;
                if (wk_cpu_sub_key_at(&subs[s], x, y, &key)) {
                    hits++;
                    assert_int_equal(WK_CPU_KEY_ID(key), 5);
                }
            }
            assert_true(hits <= 1);
            covered += hits;
        }
    printf("# near-clipped triangle: %d subs, %d pixels\n", n, covered);
    assert_true(covered > 50);
    free(vs);
}

static void test_lod(void **state)
{
    (void)state;
    for (int k = -6; k <= 12; k++)
        assert_int_equal(wk_cpu_lod_q8(ldexp(1.0, 2 * k)), 256 * k);
    int last = wk_cpu_lod_q8(1e-9);
    for (int i = 0; i < 20000; i++) {
        float r2 = (float)(1e-9 * pow(1.0015, i));
        int l = wk_cpu_lod_q8(r2);
        assert_true(l >= last); /* monotone */
        double want = 128.0 * log2(r2);
        assert_true(l <= want + 0.01 && l >= want - 1.01);
        last = l;
    }
    assert_true(wk_cpu_lod_q8(0.0) < -100000 && wk_cpu_lod_q8(NAN) < -100000);
    assert_true(wk_cpu_lod_q8(INFINITY) > 100000);
}

/* Four lanes at once give each lane's scalar level, over every exponent, the edge cases and
 * random bit patterns. */
static void test_lod_lanes(void **state)
{
    (void)state;
    const float special[] = {0.0f,      -0.0f,    NAN,     -NAN,    INFINITY, -INFINITY, 1e-45f,
                             1.17e-38f, 1.2e-38f, 3.4e38f, FLT_MAX, -1.0f,    1.0f,      0.5f};
    uint64_t rng = 7;
    for (int i = 0; i < 200000; i++) {
        v4f r2;
        for (int k = 0; k < 4; k++) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            uint32_t bits = (uint32_t)(rng >> 32);
            float f;
            memcpy(&f, &bits, sizeof f);
            size_t n = sizeof special / sizeof *special;
            r2[k] = i < 1000 ? special[(size_t)(i * 4 + k) % n] : f;
        }
        v4i got = wk_cpu_lod_q8_4(r2);
        for (int k = 0; k < 4; k++)
            assert_int_equal(got[k], wk_cpu_lod_q8(r2[k]));
    }
}

/* One point's sample (the four lanes alike). */
static void sample1(const wk_cpu_texture *t, float u, float v, int lod, float out[3])
{
    v4f lanes[3];
    wk_cpu_texture_sample4(t, wk_v4_splat(u), wk_v4_splat(v), (v4i){lod, lod, lod, lod}, lanes);
    for (int ch = 0; ch < 3; ch++)
        out[ch] = lanes[ch][0];
}

static void test_texture(void **state)
{
    (void)state;
    lm_image *img;
    assert_int_equal(lm_image_create(4, 2, &img), LM_OK);
    for (int i = 0; i < 8 * 4; i++)
        img->pixels[i] = (uint8_t)(i * 7 + 3);
    wk_cpu_texture *t;
    assert_int_equal(wk_cpu_texture_create(img, &t), LM_OK);
    assert_int_equal(t->n_levels, 3); /* 4x2, 2x1, 1x1 */
    for (int y = 0; y < 2; y++)       /* texel centres read back exactly, bottom row first */
        for (int x = 0; x < 4; x++) {
            float out[3], again[3];
            sample1(t, (x + 0.5f) / 4.0f, (y + 0.5f) / 2.0f, -300, out);
            const uint8_t *px = img->pixels + ((1 - y) * 4 + x) * 4;
            for (int ch = 0; ch < 3; ch++)
                assert_true(out[ch] == (float)px[ch]);
            sample1(t, (x + 0.5f) / 4.0f - 3.0f, (y + 0.5f) / 2.0f + 5.0f, -300, again);
            assert_memory_equal(out, again, sizeof out); /* repeat wrapping */
        }
    uint32_t a = t->level[0].texel[0], b = t->level[0].texel[1], c = t->level[0].texel[4];
    uint32_t d = t->level[0].texel[5], l1 = t->level[1].texel[0];
    for (int ch = 0; ch < 4; ch++) { /* level 1 texel 0: the rounded mean of level 0's block */
        uint32_t sum = ((a >> 8 * ch) & 255) + ((b >> 8 * ch) & 255) + ((c >> 8 * ch) & 255) +
                       ((d >> 8 * ch) & 255);
        assert_int_equal((l1 >> 8 * ch) & 255, (sum + 2) >> 2);
    }
    float top[3], mid[3], lo[3], hi[3];
    sample1(t, 0.3f, 0.7f, 1 << 12, top); /* far minified: the 1x1 level */
    for (int ch = 0; ch < 3; ch++)
        assert_true(top[ch] == (float)((t->level[2].texel[0] >> 8 * ch) & 255));
    sample1(t, 0.3f, 0.7f, 256, lo); /* trilinear: a quarter of the way from level 1 to 2 */
    sample1(t, 0.3f, 0.7f, 512, hi);
    sample1(t, 0.3f, 0.7f, 256 + 64, mid);
    for (int ch = 0; ch < 3; ch++)
        assert_true(fabsf(mid[ch] - (0.75f * lo[ch] + 0.25f * hi[ch])) < 1e-3f);
    wk_cpu_texture_destroy(t);
    lm_image_destroy(img);
}

/* Two materials: untextured, and textured with a random w x h texture (*img, freed by the
 * caller after the table). */
static void random_materials(int w, int h, wk_cpu_materials *table, lm_image **img)
{
    assert_int_equal(lm_image_create(w, h, img), LM_OK);
    for (int i = 0; i < w * h * 4; i++)
        (*img)->pixels[i] = (uint8_t)(urand() * 256);
    lm_material mats[2] = {{.diffuse = {0.9f, 0.8f, 1.0f, 1}}, {.diffuse = {1, 1, 1, 1}}};
    mats[1].texture = *img;
    assert_int_equal(wk_cpu_materials_set(table, mats, 2), LM_OK);
}

/* The window's pixels that sub s covers, in scan order; returns how many. */
static size_t sub_pixels(const wk_cpu_sub *s, uint32_t *xy)
{
    size_t m = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint64_t key;
            if (wk_cpu_sub_key_at(s, x, y, &key))
                xy[m++] = WK_CPU_XY(x, y);
        }
    return m;
}

/* Shading a run of pixels gives each pixel what shading it alone gives. */
static void test_shade_runs(void **state)
{
    (void)state;
    wk_cpu_view v;
    window_view(&v);
    lm_image *img;
    wk_cpu_materials table = {0};
    random_materials(8, 8, &table, &img);
    const float light[3] = {0, 0, 1};
    for (int round = 0; round < 200; round++) {
        lm_tri_data t = random_tri(1, 40.0);
        t.material = (uint32_t)(round % 2);
        wk_cpu_sub subs[WK_CPU_MAX_SUBS];
        int n = wk_cpu_tri_setup(&v, &t, subs);
        for (int s = 0; s < n; s++) {
            uint32_t xy[W * H];
            size_t m = sub_pixels(&subs[s], xy);
            wk_cpu_shade sh;
            wk_cpu_shade_setup(&subs[s], &t, light, &table, &sh);
            static uint8_t rgb[3 * W * H], luma[W * H];
            static float texf[3 * W * H];
            wk_cpu_shade_pixels(&subs[s], &sh, xy, m, rgb, luma, texf, 0);
            for (size_t i = 0; i < m; i++) {
                uint8_t one[3], l;
                uint8_t again[3], l2;
                wk_cpu_shade_pixels(&subs[s], &sh, &xy[i], 1, one, &l, NULL, 0);
                wk_cpu_shade_pixels(&subs[s], &sh, &xy[i], 1, again, &l2, texf + 3 * i, 1);
                assert_int_equal(l2, l); /* reused texture factors give the same pixel */
                assert_memory_equal(again, one, 3);
                assert_int_equal(l, luma[i]);
                assert_int_equal(one[0], rgb[i]);
                assert_int_equal(one[1], rgb[m + i]);
                assert_int_equal(one[2], rgb[2 * m + i]);
                assert_int_equal(l, (77 * one[0] + 150 * one[1] + 29 * one[2] + 128) >> 8);
            }
        }
    }
    wk_cpu_materials_free(&table);
    lm_image_destroy(img);
}

static uint64_t fnv1a(uint64_t h, const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

/* The images of a fixed scene, hashed: the same bits on every host, compiler and build. A change
 * of the rasteriser's arithmetic changes this hash: then bump the version in WK_CPU_RASTERISER
 * (worker/render/device_choice.h), since images of two versions must not be compared, and update
 * it. */
#define GOLDEN_HASH 0xd5fc19749df55f46ull
static uint64_t golden_hash(void)
{
    lm_mesh *m = lmt_make_sphere(3), *coarse = lmt_make_sphere(1);
    lm_image *tex; /* a texture of 16x16 colour cells, so that sampling is pinned too */
    assert_int_equal(lm_image_create(64, 32, &tex), LM_OK);
    for (int i = 0; i < 64 * 32; i++)
        for (int ch = 0; ch < 4; ch++)
            tex->pixels[4 * i + ch] =
                (uint8_t)((((i % 64) / 16 + (i / 64) / 16) % 2) * 150 + ch * 40 + (i % 7));
    m->materials[0].texture = tex; /* the mesh owns it */
    float c[3], r;
    lm_mesh_bounding_sphere(m, c, &r);
    lm_view_set *vs = malloc(sizeof *vs);
    assert_int_equal(lm_view_set_make(vs, 6, 48, c, r), LM_OK);
    lm_views *v;
    assert_int_equal(wk_views_local_create(m, vs, 0, 0, "cpu", &v), LM_OK);
    lm_tri_data *tris;
    size_t n;
    assert_int_equal(lm_mesh_export_tris(coarse, &tris, &n), LM_OK);
    assert_int_equal(v->ops->set_mesh(v, tris, n), LM_OK);
    uint64_t h = 0xcbf29ce484222325ull;
    uint8_t rgba[48 * 48 * 4], y[48 * 48];
    for (uint32_t k = 0; k < 6; k++) {
        assert_int_equal(v->ops->read_image(v, LM_IMAGE_RGBA, k, rgba), LM_OK);
        assert_int_equal(v->ops->read_image(v, LM_IMAGE_TARGET_LUMA, k, y), LM_OK);
        h = fnv1a(fnv1a(h, rgba, sizeof rgba), y, sizeof y);
    }
    free(tris);
    lm_views_destroy(v);
    free(vs);
    lm_mesh_destroy(m);
    lm_mesh_destroy(coarse);
    return h;
}

/* ... at four lanes and, where the processor has AVX2, at eight. */
static void test_golden_images(void **state)
{
    (void)state;
    int before = wk_cpu_shade_lanes();
    for (int lanes = 4; lanes <= 8; lanes += 4) {
        if (wk_cpu_shade_set_lanes(lanes) != lanes) {
            printf("# %d lanes: not on this processor or build, skipped\n", lanes);
            continue;
        }
        uint64_t h = golden_hash();
        printf("# golden hash of the CPU images, %d lanes: 0x%016llxull\n", lanes,
               (unsigned long long)h);
        assert_true(h == GOLDEN_HASH);
    }
    wk_cpu_shade_set_lanes(before);
}

/* Eight lanes shade every run (lengths 1 to hundreds, so every tail) to the same bytes and
 * texture factors as four, sampling and reusing factors alike. */
static void test_lane_widths_agree(void **state)
{
    (void)state;
    int before = wk_cpu_shade_lanes();
    if (wk_cpu_shade_set_lanes(8) != 8) {
        printf("# 8 lanes: not on this processor or build, skipped\n");
        wk_cpu_shade_set_lanes(before);
        return;
    }
    wk_cpu_view v;
    window_view(&v);
    lm_image *img;
    wk_cpu_materials table = {0};
    random_materials(32, 16, &table, &img);
    const float light[3] = {0.3f, 0.1f, 0.9f};
    static uint8_t rgb[2][3 * W * H], luma[2][W * H];
    static float texf[2][3 * W * H];
    for (int round = 0; round < 300; round++) {
        lm_tri_data t = random_tri(1, 10.0 + urand() * 80.0);
        t.material = (uint32_t)(round % 3 != 0);
        wk_cpu_sub subs[WK_CPU_MAX_SUBS];
        int n = wk_cpu_tri_setup(&v, &t, subs);
        for (int s = 0; s < n; s++) {
            uint32_t xy[W * H];
            size_t m = sub_pixels(&subs[s], xy);
            size_t cut = m ? (size_t)(urand() * (double)m) : 0; /* two runs: every tail */
            wk_cpu_shade sh;
            wk_cpu_shade_setup(&subs[s], &t, light, &table, &sh);
            for (int w = 0; w < 2; w++) {
                wk_cpu_shade_set_lanes(w ? 8 : 4);
                wk_cpu_shade_pixels(&subs[s], &sh, xy, cut, rgb[w], luma[w], texf[w], 0);
                wk_cpu_shade_pixels(&subs[s], &sh, xy + cut, m - cut, rgb[w] + 3 * cut,
                                    luma[w] + cut, texf[w] + 3 * cut, 0);
            }
            assert_memory_equal(rgb[0], rgb[1], 3 * m);
            assert_memory_equal(luma[0], luma[1], m);
            if (sh.tex)
                assert_memory_equal(texf[0], texf[1], 3 * m * sizeof(float));
            wk_cpu_shade_pixels(&subs[s], &sh, xy, m, rgb[1], luma[1], texf[0], 1); /* reuse */
            assert_memory_equal(luma[0], luma[1], m);
        }
    }
    wk_cpu_materials_free(&table);
    lm_image_destroy(img);
    wk_cpu_shade_set_lanes(before);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_draw_matches_direct_evaluation),
        cmocka_unit_test(test_order_and_tile_rejection),
        cmocka_unit_test(test_watertight),
        cmocka_unit_test(test_near_clipping),
        cmocka_unit_test(test_lod),
        cmocka_unit_test(test_lod_lanes),
        cmocka_unit_test(test_texture),
        cmocka_unit_test(test_shade_runs),
        cmocka_unit_test(test_golden_images),
        cmocka_unit_test(test_lane_widths_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
