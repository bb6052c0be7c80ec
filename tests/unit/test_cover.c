/* tests/unit/test_cover.c — worker/cover: twins and the boundary test of patches, and the
 * per-view proof that the added triangles cover the removed ones' pixels (orientation, clipping,
 * depth), checked against a brute-force pixel count with a top-left fill rule. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"
#include "worker/render/shared/cover.h"

#define W 64
#define H 64

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double urand(void)
{
    return lmt_urand(&rng_state);
}

/* A triangle with corners at (x, y) in window pixels and window depth z (positions in "3D" are the
 * same numbers, so bitwise equality of positions is equality of these). */
static lm_tri_data tri(const float a[3], const float b[3], const float c[3])
{
    lm_tri_data t;
    memset(&t, 0, sizeof t);
    memcpy(t.c[0].pos, a, sizeof t.c[0].pos);
    memcpy(t.c[1].pos, b, sizeof t.c[1].pos);
    memcpy(t.c[2].pos, c, sizeof t.c[2].pos);
    return t;
}

/* The footprint of t if its positions were window coordinates (x, y, depth). */
static wk_footprint footprint(const lm_tri_data *t)
{
    wk_footprint f = {.projected = 1, .zmin = INFINITY, .zmax = -INFINITY};
    float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < 3; k++) {
        const float *p = t->c[k].pos;
        f.win[k][0] = p[0];
        f.win[k][1] = p[1];
        f.zmin = fminf(f.zmin, p[2]);
        f.zmax = fmaxf(f.zmax, p[2]);
        for (int a = 0; a < 2; a++) {
            lo[a] = fminf(lo[a], p[a]);
            hi[a] = fmaxf(hi[a], p[a]);
        }
    }
    f.rect.x0 = (int)fmaxf(0.0f, floorf(lo[0] - 1.0f));
    f.rect.y0 = (int)fmaxf(0.0f, floorf(lo[1] - 1.0f));
    f.rect.x1 = (int)fminf((float)W, ceilf(hi[0] + 1.0f));
    f.rect.y1 = (int)fminf((float)H, ceilf(hi[1] + 1.0f));
    return f;
}

/* A fan around centre c over the closed loop ring[0..n-1]. */
static void fan(const float c[3], float ring[][3], int n, lm_tri_data *out)
{
    for (int i = 0; i < n; i++)
        out[i] = tri(c, ring[i], ring[(i + 1) % n]);
}

typedef struct patch_case {
    lm_tri_data removed[16], added[16];
    uint32_t n_removed, n_added;
    wk_cover_patch cp;
    wk_cover cover;
} patch_case;

static void case_prepare(patch_case *pc)
{
    const lm_tri_data *rem[16];
    for (uint32_t i = 0; i < pc->n_removed; i++)
        rem[i] = &pc->removed[i];
    assert_int_equal(wk_cover_patch_prepare(&pc->cp, rem, pc->n_removed, pc->added, pc->n_added),
                     LM_OK);
    assert_int_equal(wk_cover_begin(&pc->cover, &pc->cp, pc->n_removed + pc->n_added, W, H), LM_OK);
    for (uint32_t i = 0; i < pc->n_removed; i++)
        if (!pc->cp.twin[i]) {
            wk_footprint f = footprint(&pc->removed[i]);
            wk_cover_feed(&pc->cover, &f, 0);
        }
    for (uint32_t i = 0; i < pc->n_added; i++)
        if (!pc->cp.twin[pc->n_removed + i]) {
            wk_footprint f = footprint(&pc->added[i]);
            wk_cover_feed(&pc->cover, &f, 1);
        }
}

static void case_free(patch_case *pc)
{
    wk_cover_patch_free(&pc->cp);
    wk_cover_free(&pc->cover);
}

static float ring6[6][3] = {{40, 32, 0.5f}, {36, 39, 0.5f}, {28, 39, 0.5f},
                            {24, 32, 0.5f}, {28, 25, 0.5f}, {36, 25, 0.5f}};

static void test_fan_move(void **state)
{
    (void)state;
    patch_case pc = {0};
    const float c0[3] = {32, 32, 0.4f}, c1[3] = {33, 31, 0.45f};
    fan(c0, ring6, 6, pc.removed);
    fan(c1, ring6, 6, pc.added);
    pc.n_removed = pc.n_added = 6;
    case_prepare(&pc);
    assert_true(pc.cp.same_boundary);
    for (int i = 0; i < 12; i++)
        assert_false(pc.cp.twin[i]);
    const wk_rect all = {0, 0, W, H}, away = {0, 0, 10, 10};
    /* the added fan reaches depth 0.5 (its rim): in front of 0.6, not of 0.5 */
    assert_true(wk_cover_front_of(&pc.cover, &all, 0.6f));
    assert_false(wk_cover_front_of(&pc.cover, &all, 0.5f));
    assert_true(wk_cover_front_of(&pc.cover, &away, 0.1f)); /* no patch triangle there */
    case_free(&pc);

    /* the centre moved across the rim: the new fan folds, orientations disagree */
    const float c2[3] = {44, 32, 0.4f};
    fan(c0, ring6, 6, pc.removed);
    fan(c2, ring6, 6, pc.added);
    case_prepare(&pc);
    assert_true(pc.cp.same_boundary);
    assert_false(wk_cover_front_of(&pc.cover, &all, 0.9f));
    case_free(&pc);

    /* a missing triangle leaves a hole: the boundaries differ */
    fan(c0, ring6, 6, pc.removed);
    fan(c1, ring6, 6, pc.added);
    pc.n_added = 5;
    case_prepare(&pc);
    assert_false(pc.cp.same_boundary);
    assert_false(wk_cover_front_of(&pc.cover, &away, 0.9f));
    case_free(&pc);
}

static void test_twins_and_clipping(void **state)
{
    (void)state;
    patch_case pc = {0};
    const float c0[3] = {32, 32, 0.4f}, c1[3] = {31, 33, 0.42f};
    const float n0[3] = {50, 50, 0.95f}, n1[3] = {60, 50, 0.95f}, n2[3] = {55, 60, 0.95f};
    fan(c0, ring6, 6, pc.removed);
    fan(c1, ring6, 6, pc.added);
    pc.removed[6] = tri(n0, n1, n2); /* a neighbour with new normals: same corners, rotated */
    pc.added[6] = tri(n1, n2, n0);
    pc.n_removed = pc.n_added = 7;
    case_prepare(&pc);
    assert_true(pc.cp.same_boundary);
    assert_true(pc.cp.twin[6] && pc.cp.twin[13]);
    assert_false(pc.cp.twin[0] || pc.cp.twin[7]);
    /* the twin is far back, yet it keeps its depths: the fan alone decides */
    assert_true(wk_cover_front_of(&pc.cover, &(wk_rect){0, 0, W, H}, 0.6f));
    case_free(&pc);

    /* reversed corners are not a twin (and their edges do not cancel) */
    pc.added[6] = tri(n0, n2, n1);
    case_prepare(&pc);
    assert_false(pc.cp.twin[6] || pc.cp.twin[13]);
    assert_false(pc.cp.same_boundary);
    case_free(&pc);

    /* a corner beyond the far plane: clipping may change coverage, no proof where it lies */
    float far_ring[6][3];
    memcpy(far_ring, ring6, sizeof far_ring);
    far_ring[0][2] = 1.5f;
    fan(c0, far_ring, 6, pc.removed);
    fan(c1, far_ring, 6, pc.added);
    pc.n_removed = pc.n_added = 6;
    case_prepare(&pc);
    assert_true(pc.cp.same_boundary);
    assert_false(wk_cover_front_of(&pc.cover, &(wk_rect){38, 30, 42, 34}, 2.0f));
    assert_true(wk_cover_front_of(&pc.cover, &(wk_rect){24, 24, 28, 28}, 0.6f)); /* away from it */
    case_free(&pc);
}

/* Whether pixel centre (px, py) is covered under a top-left fill rule (either orientation). */
static int covers(const lm_tri_data *t, double px, double py)
{
    const float *a = t->c[0].pos, *b = t->c[1].pos, *c = t->c[2].pos;
    double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (area == 0)
        return 0;
    const float *v[3] = {a, b, c};
    for (int k = 0; k < 3; k++) {
        const float *p = v[k], *q = v[(k + 1) % 3];
        double ex = q[0] - p[0], ey = q[1] - p[1];
        double e = (ex * (py - p[1]) - ey * (px - p[0])) * (area > 0 ? 1 : -1);
        double dx = area > 0 ? ex : -ex, dy = area > 0 ? ey : -ey;
        int top_left = dy < 0 || (dy == 0 && dx > 0);
        if (e < 0 || (e == 0 && !top_left))
            return 0;
    }
    return 1;
}

/* Random star-shaped rims and centre moves: whenever the proof holds on the whole view, every pixel
 * centre has as many added as removed triangles covering it. */
static void test_cover_counts_random(void **state)
{
    (void)state;
    int proved = 0;
    for (int trial = 0; trial < 300; trial++) {
        patch_case pc = {0};
        int n = 3 + (int)(urand() * 8);
        float ring[12][3];
        for (int i = 0; i < n; i++) {
            double ang = 6.283185307179586 * (i + 0.8 * urand()) / n, rad = 6 + 20 * urand();
            ring[i][0] = (float)floor((32 + rad * cos(ang)) * 256) / 256;
            ring[i][1] = (float)floor((32 + rad * sin(ang)) * 256) / 256;
            ring[i][2] = 0.5f;
        }
        float c0[3] = {32, 32, 0.4f};
        float c1[3] = {(float)(32 + 24 * (urand() - 0.5)), (float)(32 + 24 * (urand() - 0.5)),
                       0.4f};
        fan(c0, ring, n, pc.removed);
        fan(c1, ring, n, pc.added);
        pc.n_removed = pc.n_added = (uint32_t)n;
        case_prepare(&pc);
        if (wk_cover_front_of(&pc.cover, &(wk_rect){0, 0, W, H}, 0.9f)) {
            proved++;
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    int nr = 0, na = 0;
                    for (int i = 0; i < n; i++) {
                        nr += covers(&pc.removed[i], x + 0.5, y + 0.5);
                        na += covers(&pc.added[i], x + 0.5, y + 0.5);
                    }
                    assert_int_equal(nr, na);
                }
        }
        case_free(&pc);
    }
    assert_true(proved > 30 && proved < 300); /* both outcomes occur */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fan_move),
        cmocka_unit_test(test_twins_and_clipping),
        cmocka_unit_test(test_cover_counts_random),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
