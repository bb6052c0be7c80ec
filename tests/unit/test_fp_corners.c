/* tests/unit/test_fp_corners.c — a change's footprint from its distinct corners
 * (coordinator/simplify/fp_corners.c) is, rectangle for rectangle, the one co_fp_add_tri gives
 * triangle by triangle: triangles that share corners on a grid, seen by views all around, and
 * the same with corners behind some views' eyes (the triangle-by-triangle fallback of a view). */
#include <stdlib.h>
#include <string.h>

#include "coordinator/simplify/fp_corners.h"
#include "test_support.h"

#define GRID 9

/* Triangles of a GRID x GRID patch of points, `spread` wide around the origin; the corners of
 * neighbouring triangles are bit-for-bit the same points. */
static uint32_t grid_tris(lm_tri_data *out, float spread, uint32_t seed)
{
    float p[GRID][GRID][3];
    srand(seed);
    for (int i = 0; i < GRID; i++)
        for (int j = 0; j < GRID; j++) {
            p[i][j][0] = spread * ((float)i / (GRID - 1) - 0.5f);
            p[i][j][1] = spread * ((float)j / (GRID - 1) - 0.5f);
            p[i][j][2] = spread * 0.3f * ((float)rand() / (float)RAND_MAX - 0.5f);
        }
    uint32_t n = 0;
    for (int i = 0; i + 1 < GRID; i++)
        for (int j = 0; j + 1 < GRID; j++) {
            const float *q[2][3] = {{p[i][j], p[i + 1][j], p[i][j + 1]},
                                    {p[i + 1][j], p[i + 1][j + 1], p[i][j + 1]}};
            for (int t = 0; t < 2; t++, n++) {
                memset(&out[n], 0, sizeof out[n]);
                for (int k = 0; k < 3; k++)
                    memcpy(out[n].c[k].pos, q[t][k], sizeof out[n].c[k].pos);
            }
        }
    return n;
}

/* Both ways over the first n triangles; returns how many views had a corner that does not
 * project (the fallback). */
static uint32_t compare(const lm_view_set *vs, const lm_tri_data *tris, uint32_t n)
{
    co_rect by_tri[LM_MAX_VIEWS], by_corner[LM_MAX_VIEWS];
    co_fp_clear(by_tri, vs->count);
    co_fp_clear(by_corner, vs->count);
    co_fp_corners c;
    co_fp_corners_init(&c);
    co_fp_corners_reset(&c);
    for (uint32_t t = 0; t < n; t++) {
        co_fp_add_tri(by_tri, vs, &tris[t]);
        assert_int_equal(co_fp_corners_add_tri(&c, &tris[t]), LM_OK);
    }
    assert_true(c.n_pos < 3 * n); /* shared corners were found */
    co_fp_corners_apply(&c, by_corner, vs);
    uint32_t fallback = 0;
    for (uint32_t h = 0; h < vs->count; h++) {
        assert_memory_equal(&by_tri[h], &by_corner[h], sizeof by_tri[h]);
        int whole = 0;
        for (uint32_t i = 0; i < c.n_pos && !whole; i++) {
            float win[2];
            whole = !co_fp_project(&vs->views[h], c.pos[i], win);
        }
        fallback += whole;
    }
    co_fp_corners_free(&c);
    return fallback;
}

static void same_rectangles_as_triangle_by_triangle(void **state)
{
    (void)state;
    lm_view_set vs;
    float centre[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(&vs, 20, 128, centre, 1.0f), LM_OK);
    lm_tri_data tris[2 * (GRID - 1) * (GRID - 1)];
    for (uint32_t seed = 1; seed <= 4; seed++) {
        uint32_t n = grid_tris(tris, 0.5f, seed);
        assert_int_equal(compare(&vs, tris, n), 0);
        assert_int_equal(compare(&vs, tris, 5), 0); /* a few, as a candidate has */
    }
}

static void same_rectangles_with_corners_behind_the_eye(void **state)
{
    (void)state;
    lm_view_set vs;
    float centre[3] = {0, 0, 0};
    assert_int_equal(lm_view_set_make(&vs, 20, 128, centre, 1.0f), LM_OK);
    lm_tri_data tris[2 * (GRID - 1) * (GRID - 1)];
    uint32_t fallback = 0;
    for (uint32_t seed = 1; seed <= 4; seed++) {
        uint32_t n = grid_tris(tris, 40.0f, seed); /* far wider than the cameras' orbit */
        fallback += compare(&vs, tris, n);
    }
    assert_true(fallback > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(same_rectangles_as_triangle_by_triangle),
        cmocka_unit_test(same_rectangles_with_corners_behind_the_eye),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
