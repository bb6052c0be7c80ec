/* tests/unit/test_view_buckets.c — the GL-free parts of rendering: view sets (uniform
 * directions, framing, held-out views distinct, up vector at the poles), triangle footprints and
 * bucket queries against brute force, the image store's exact sums (region ΔE, commits, the
 * oracle's box blur) and its "certainly hidden" tests (whose tile maxima follow every commit). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/view.h"
#include "test_support.h"
#include "worker/render/shared/buckets.h"
#include "worker/render/shared/image_store.h"

static uint64_t rng_state = 88172645463325252ull;
static double urand(void)
{
    return lmt_urand(&rng_state);
}

static float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void check_set(const lm_view_set *vs, uint32_t n, float min_sep_cos)
{
    const float c[3] = {1, 2, 3};
    assert_int_equal(vs->count, n);
    for (uint32_t i = 0; i < n; i++) {
        const lm_view *v = &vs->views[i];
        assert_true(fabsf(dot3(v->dir, v->dir) - 1.0f) < 1e-5f);
        float win[2], w;
        assert_true(lm_view_project(v, c, win, &w)); /* the centre projects to the middle */
        assert_true(fabsf(win[0] - 64.0f) < 1e-3f && fabsf(win[1] - 64.0f) < 1e-3f);
        for (uint32_t j = 0; j < i; j++)
            assert_true(dot3(v->dir, vs->views[j].dir) < min_sep_cos);
        /* the whole bounding sphere is inside the image: points at radius 2 around the centre */
        for (int k = 0; k < 6; k++) {
            float p[3] = {c[0], c[1], c[2]};
            p[k / 2] += (k % 2 ? 2.0f : -2.0f);
            assert_true(lm_view_project(v, p, win, &w));
            assert_true(win[0] > 0 && win[0] < 128 && win[1] > 0 && win[1] < 128);
        }
    }
}

static void test_view_sets(void **state)
{
    (void)state;
    lm_view_set *a = malloc(sizeof *a), *b = malloc(sizeof *b);
    const float c[3] = {1, 2, 3};
    assert_int_equal(lm_view_set_make(a, 12, 128, c, 2.0f), LM_OK);
    check_set(a, 12, 0.95f);
    assert_int_equal(lm_view_set_make(a, 20, 128, c, 2.0f), LM_OK);
    check_set(a, 20, 0.95f);
    assert_int_equal(lm_view_set_make(a, 7, 128, c, 2.0f), LM_OK);
    check_set(a, 7, 0.95f);
    assert_int_equal(lm_view_set_make_heldout(b, 128, c, 2.0f), LM_OK);
    check_set(b, 24, 0.99f);
    /* held-out directions differ from every optimisation set's */
    const uint32_t sizes[] = {1, 6, 12, 20, 24, 32};
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
        assert_int_equal(lm_view_set_make(a, sizes[s], 128, c, 2.0f), LM_OK);
        for (uint32_t i = 0; i < b->count; i++)
            for (uint32_t j = 0; j < a->count; j++)
                assert_true(dot3(b->views[i].dir, a->views[j].dir) < 0.9999f);
    }
    assert_int_equal(lm_view_set_make(a, 0, 128, c, 2.0f), LM_E_RANGE);
    assert_int_equal(lm_view_set_make(a, 12, 8, c, 2.0f), LM_E_RANGE);
    assert_int_equal(lm_view_set_make(a, 12, 128, c, NAN), LM_E_RANGE);
    free(a);
    free(b);
}

static void random_tri(lm_tri_data *t, uint32_t id)
{
    memset(t, 0, sizeof *t);
    t->id = id;
    float cx = (float)(urand() * 2 - 1), cy = (float)(urand() * 2 - 1), cz = (float)(urand() - 0.5);
    for (int k = 0; k < 3; k++) {
        t->c[k].pos[0] = cx + (float)(urand() - 0.5) * 0.3f;
        t->c[k].pos[1] = cy + (float)(urand() - 0.5) * 0.3f;
        t->c[k].pos[2] = cz + (float)(urand() - 0.5) * 0.3f;
    }
}

/* Queries return exactly the present triangles whose footprint may touch the rectangle. */
static void test_buckets_brute_force(void **state)
{
    (void)state;
    lm_view_set *vs = malloc(sizeof *vs);
    const float c[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(vs, 12, 128, c, 1.5f), LM_OK);
    const lm_view *v = &vs->views[3];
    enum { N = 600 };
    lm_tri_data *tris = malloc(N * sizeof *tris);
    wk_footprint *fp = malloc(N * sizeof *fp);
    uint8_t *present = calloc(N, 1), *seen = calloc(N, 1);
    wk_buckets *b;
    assert_int_equal(wk_buckets_create(128, 128, 8, &b), LM_OK);
    for (uint32_t i = 0; i < N; i++) {
        random_tri(&tris[i], i);
        wk_tri_footprint(v, &tris[i], &fp[i]);
        if (urand() < 0.8) {
            assert_int_equal(wk_buckets_insert(b, i, &fp[i]), LM_OK);
            present[i] = 1;
        }
    }
    for (uint32_t i = 0; i < N; i += 3) /* some go away again */
        if (present[i]) {
            wk_buckets_remove(b, i);
            present[i] = 0;
        }
    wk_idlist got = {0};
    for (int q = 0; q < 300; q++) {
        int x0 = (int)(urand() * 128), y0 = (int)(urand() * 128);
        wk_rect r = {x0, y0, x0 + 1 + (int)(urand() * 40), y0 + 1 + (int)(urand() * 40)};
        got.n = 0;
        assert_int_equal(wk_buckets_query(b, &r, &got), LM_OK);
        memset(seen, 0, N);
        for (size_t k = 0; k < got.n; k++) {
            assert_true(got.ids[k] < N && present[got.ids[k]] && !seen[got.ids[k]]);
            seen[got.ids[k]] = 1;
        }
        wk_rect clip = {r.x0, r.y0, r.x1 < 128 ? r.x1 : 128, r.y1 < 128 ? r.y1 : 128};
        for (uint32_t i = 0; i < N; i++) {
            int want = present[i] && wk_footprint_overlaps(&fp[i], &clip);
            if (seen[i] != want)
                fail_msg("query %d (%d,%d)-(%d,%d): triangle %u rect (%d,%d)-(%d,%d) %s", q, r.x0,
                         r.y0, r.x1, r.y1, i, fp[i].rect.x0, fp[i].rect.y0, fp[i].rect.x1,
                         fp[i].rect.y1, seen[i] ? "returned wrongly" : "missed");
        }
    }
    free(got.ids);
    wk_buckets_destroy(b);
    free(tris);
    free(fp);
    free(present);
    free(seen);
    free(vs);
}

/* A footprint contains every pixel centre inside the projected triangle, and a triangle behind the
 * eye covers the whole view. */
static void test_footprint_conservative(void **state)
{
    (void)state;
    lm_view_set *vs = malloc(sizeof *vs);
    const float c[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(vs, 20, 64, c, 1.0f), LM_OK);
    const lm_view *v = &vs->views[0];
    for (int n = 0; n < 200; n++) {
        lm_tri_data t;
        random_tri(&t, 0);
        wk_footprint f;
        wk_tri_footprint(v, &t, &f);
        assert_true(f.projected);
        for (int y = 0; y < 64; y++)
            for (int x = 0; x < 64; x++) {
                float px = x + 0.5f, py = y + 0.5f, e[3];
                for (int k = 0; k < 3; k++) {
                    const float *a = f.win[k], *b = f.win[(k + 1) % 3];
                    e[k] = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
                }
                int inside =
                    (e[0] >= 0 && e[1] >= 0 && e[2] >= 0) || (e[0] <= 0 && e[1] <= 0 && e[2] <= 0);
                wk_rect pix = {x, y, x + 1, y + 1};
                if (inside)
                    assert_true(wk_footprint_overlaps(&f, &pix));
            }
    }
    lm_tri_data t;
    random_tri(&t, 0);
    memcpy(t.c[1].pos, v->eye, sizeof t.c[1].pos); /* a corner at the eye */
    wk_footprint f;
    wk_tri_footprint(v, &t, &f);
    assert_false(f.projected);
    assert_int_equal(f.rect.x1 - f.rect.x0, 64);
    assert_int_equal(f.rect.y1 - f.rect.y0, 64);
    free(vs);
}

/* Window depth of a point whose clip w is known (as the rasteriser takes it). */
static double depth_of(const lm_view *v, const float p[3], float w)
{
    const float *m = v->view_proj;
    return ((double)m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14]) / w * 0.5 + 0.5;
}

/* A footprint's depth range holds every fragment of a rasteriser that snaps the corners (here: a
 * random shift of up to WK_DEPTH_REACH in x and y) and interpolates depth on the unsnapped plane,
 * as llvmpipe does: at a pixel centre just outside a sliver the plane is extrapolated, and a
 * sliver's plane is steep (found by test_render_exact on the spider: a kept triangle taken as
 * hidden behind its own pixel). Half the triangles are slivers. */
static void test_footprint_depths_hold_the_fragments(void **state)
{
    (void)state;
    lm_view_set *vs = malloc(sizeof *vs);
    const float c[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(vs, 20, 64, c, 1.0f), LM_OK);
    const lm_view *v = &vs->views[1];
    int outside = 0; /* fragments at pixel centres outside the unsnapped triangle */
    for (int n = 0; n < 400; n++) {
        lm_tri_data t;
        random_tri(&t, 0);
        if (n % 2) /* the third corner a hair off the first two's segment */
            for (int a = 0; a < 3; a++)
                t.c[2].pos[a] =
                    0.6f * t.c[0].pos[a] + 0.4f * t.c[1].pos[a] + (float)(urand() - 0.5) * 2e-3f;
        wk_footprint f;
        wk_tri_footprint(v, &t, &f);
        assert_true(f.projected);
        double win[3][2], z[3], snap[3][2];
        for (int k = 0; k < 3; k++) {
            float wf[2], w;
            assert_true(lm_view_project(v, t.c[k].pos, wf, &w));
            win[k][0] = wf[0], win[k][1] = wf[1], z[k] = depth_of(v, t.c[k].pos, w);
            for (int a = 0; a < 2; a++)
                snap[k][a] = win[k][a] + (urand() * 2 - 1) * WK_DEPTH_REACH;
        }
        double ex1 = win[1][0] - win[0][0], ey1 = win[1][1] - win[0][1];
        double ex2 = win[2][0] - win[0][0], ey2 = win[2][1] - win[0][1], a2 = ex1 * ey2 - ey1 * ex2;
        if (a2 == 0.0)
            continue;
        double gx = ((z[1] - z[0]) * ey2 - (z[2] - z[0]) * ey1) / a2;
        double gy = ((z[2] - z[0]) * ex1 - (z[1] - z[0]) * ex2) / a2;
        double lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30};
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++) {
                lo[a] = snap[k][a] < lo[a] ? snap[k][a] : lo[a];
                hi[a] = snap[k][a] > hi[a] ? snap[k][a] : hi[a];
            }
        for (int i = 0; i < 2000; i++) { /* sample points: pixel centres of shifted grids */
            double px = lo[0] + urand() * (hi[0] - lo[0]), py = lo[1] + urand() * (hi[1] - lo[1]);
            double e[3], u[3];
            for (int k = 0; k < 3; k++) {
                const double *p = snap[k], *q = snap[(k + 1) % 3];
                e[k] = (q[0] - p[0]) * (py - p[1]) - (q[1] - p[1]) * (px - p[0]);
                const double *r = win[k], *s2 = win[(k + 1) % 3];
                u[k] = (s2[0] - r[0]) * (py - r[1]) - (s2[1] - r[1]) * (px - r[0]);
            }
            if (!((e[0] >= 0 && e[1] >= 0 && e[2] >= 0) || (e[0] <= 0 && e[1] <= 0 && e[2] <= 0)))
                continue; /* not covered by the snapped triangle */
            outside +=
                !((u[0] >= 0 && u[1] >= 0 && u[2] >= 0) || (u[0] <= 0 && u[1] <= 0 && u[2] <= 0));
            double zp = z[0] + gx * (px - win[0][0]) + gy * (py - win[0][1]);
            if (!(zp >= (double)f.zmin - 1e-6 && zp <= (double)f.zmax + 1e-6))
                fail_msg(
                    "triangle %d: a fragment at (%.4f,%.4f) of depth %.9f outside [%.9f, %.9f]", n,
                    px, py, zp, (double)f.zmin, (double)f.zmax);
        }
    }
    assert_true(outside > 0); /* the case in question came up */
    free(vs);
}

static void fill(uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        p[i] = (uint8_t)(urand() * 256);
}

static int brute_hidden(const float *z, int w, const wk_rect *r, float limit)
{
    for (int y = r->y0; y < r->y1; y++)
        for (int x = r->x0; x < r->x1; x++)
            if (!(z[y * w + x] < limit))
                return 0;
    return 1;
}

static wk_rect random_rect(int w, int h)
{
    wk_rect r;
    r.x0 = (int)(urand() * w);
    r.y0 = (int)(urand() * h);
    r.x1 = r.x0 + 1 + (int)(urand() * (w - r.x0));
    r.y1 = r.y0 + 1 + (int)(urand() * (h - r.y0));
    return r;
}

/* The hidden tests skip rows by tile maxima of the depth images: after any sequence of whole and
 * region updates (NaN included) they still answer exactly as a scan of every pixel. */
static void test_hidden_tiles(void **state)
{
    (void)state;
    enum { W = 45, H = 37 }; /* not multiples of the tile side */
    wk_image_store *s;
    assert_int_equal(wk_image_store_create(2, W, H, &s), LM_OK);
    assert_int_equal(wk_image_store_enable_depth(s), LM_OK);
    static float z[W * H], region[W * H];
    for (int i = 0; i < W * H; i++)
        z[i] = 0.2f + 0.3f * (float)urand();
    wk_image_store_set_depth(s, 1, z);
    int agreed_hidden = 0;
    for (int it = 0; it < 4000; it++) {
        if (it % 7 == 0) { /* a commit: a region gets new depths, sometimes far or NaN */
            wk_rect r = random_rect(W, H);
            int rw = r.x1 - r.x0;
            for (int y = r.y0; y < r.y1; y++)
                for (int x = r.x0; x < r.x1; x++) {
                    double u = urand();
                    float v = u < 0.02 ? NAN : u < 0.1 ? 1.0f : 0.2f + 0.3f * (float)urand();
                    region[(y - r.y0) * rw + (x - r.x0)] = v;
                    z[y * W + x] = v;
                }
            wk_image_store_commit_depth(s, 1, &r, region);
        }
        wk_rect q = random_rect(W, H);
        float zmin = 0.3f + 0.7f * (float)urand(), eps = 1e-5f;
        int want = brute_hidden(z, W, &q, zmin - eps);
        assert_int_equal(wk_image_store_hidden(s, 1, &q, zmin, eps), want);
        wk_footprint f = {.rect = q, .projected = 0, .zmin = zmin};
        assert_int_equal(wk_image_store_hidden_tri(s, 1, &f, eps), want);
        agreed_hidden += want;
    }
    assert_true(agreed_hidden > 100); /* both answers occur */
    wk_image_store_destroy(s);
}

static void test_image_store_sums(void **state)
{
    (void)state;
    const int W = 40, H = 30;
    wk_image_store *s;
    assert_int_equal(wk_image_store_create(2, W, H, &s), LM_OK);
    uint8_t t[40 * 30], y[40 * 30], region[40 * 30];
    fill(t, sizeof t);
    fill(y, sizeof y);
    wk_image_store_set_target(s, 1, t);
    wk_image_store_set_current(s, 1, y);
    int64_t e = 0;
    for (int i = 0; i < W * H; i++)
        e += (int64_t)(t[i] - y[i]) * (t[i] - y[i]);
    assert_true(wk_image_store_energy(s, 1) == e);
    for (int n = 0; n < 50; n++) {
        int x0 = (int)(urand() * W), y0 = (int)(urand() * H);
        wk_rect r = {x0, y0, x0 + 1 + (int)(urand() * (W - x0 - 1)),
                     y0 + 1 + (int)(urand() * (H - y0 - 1))};
        fill(region, (size_t)(r.x1 - r.x0) * (r.y1 - r.y0));
        int64_t before = wk_image_store_energy_recompute(s, 1);
        int64_t d = wk_image_store_region_delta(s, 1, &r, region);
        wk_image_store_commit_region(s, 1, &r, region);
        int64_t after = wk_image_store_energy_recompute(s, 1);
        assert_true(after - before == d);
        assert_true(wk_image_store_energy(s, 1) == after);
    }
    /* box blur against brute force */
    uint32_t *blur = malloc((size_t)W * H * sizeof *blur);
    assert_int_equal(wk_image_store_blurred_diff(s, 1, 3, blur), LM_OK);
    const uint8_t *tt = wk_image_store_target(s, 1), *yy = wk_image_store_current(s, 1);
    for (int py = 0; py < H; py++)
        for (int px = 0; px < W; px++) {
            uint32_t sum = 0;
            for (int dy = -3; dy <= 3; dy++)
                for (int dx = -3; dx <= 3; dx++) {
                    int qx = px + dx, qy = py + dy;
                    if (qx < 0 || qy < 0 || qx >= W || qy >= H)
                        continue;
                    int d = tt[qy * W + qx] - yy[qy * W + qx];
                    sum += (uint32_t)(d * d);
                }
            assert_int_equal(blur[py * W + px], sum);
        }
    free(blur);
    assert_int_equal(wk_image_store_blurred_diff(s, 1, 99, NULL), LM_E_RANGE);
    wk_image_store_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_view_sets),
        cmocka_unit_test(test_buckets_brute_force),
        cmocka_unit_test(test_footprint_conservative),
        cmocka_unit_test(test_footprint_depths_hold_the_fragments),
        cmocka_unit_test(test_image_store_sums),
        cmocka_unit_test(test_hidden_tiles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
