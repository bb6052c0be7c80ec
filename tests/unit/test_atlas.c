/* tests/unit/test_atlas.c — the packed chart atlas (common/uv_charts.h, common/uv_atlas.h): the
 * 2-D overlap test, a planar grid as one chart with one wedge a vertex (a larger one cut at
 * LM_CHART_MAX_TRIS), a cube as six or more charts without flips, a helical ramp (near-planar
 * but folding over itself in projection) split so it does not overlap, charts that never share a
 * texel and keep their gutters (rasterised coverage), every triangle inside [0, 1]², the source's
 * order, positions and normals kept, the same bytes twice, a map too small refused, and how far
 * the renderers' per-triangle frames lie from the wedges' tangents on a curved mesh. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/bake_normal.h"
#include "common/bake_walk.h"
#include "common/io/mesh_io.h"
#include "common/tangents.h"
#include "common/uv_atlas.h"
#include "common/uv_charts.h"
#include "test_support.h"

static void test_tri2_overlap(void **state)
{
    (void)state;
    const double a[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    const double edge[3][2] = {{1, 0}, {1, 1}, {0, 1}};   /* shares a's edge */
    const double corner[3][2] = {{1, 0}, {2, 0}, {1, 1}}; /* shares a corner */
    const double cross[3][2] = {{0.2, 0.2}, {2, 0.2}, {0.2, 2}};
    const double inside[3][2] = {{0.1, 0.1}, {0.3, 0.1}, {0.1, 0.3}};
    const double apart[3][2] = {{2, 2}, {3, 2}, {2, 3}};
    const double flat[3][2] = {{0, 0}, {1, 1}, {2, 2}};
    assert_false(lm_tri2_overlap(a, edge));
    assert_false(lm_tri2_overlap(a, corner));
    assert_true(lm_tri2_overlap(a, cross));
    assert_true(lm_tri2_overlap(a, inside));
    assert_true(lm_tri2_overlap(inside, a));
    assert_false(lm_tri2_overlap(a, apart));
    assert_false(lm_tri2_overlap(a, flat));
}

/* Every live triangle's corners inside [0, 1]² and counter-clockwise in UV (no flip). */
static void assert_inside_unflipped(const lm_mesh *a)
{
    for (uint32_t t = 0; t < a->n_tris; t++) {
        if (!a->tri_alive[t])
            continue;
        const float *uv[3];
        for (int k = 0; k < 3; k++) {
            uv[k] = a->wedges[a->tris[t].w[k]].uv;
            assert_true(uv[k][0] >= 0.0f && uv[k][0] <= 1.0f && uv[k][1] >= 0.0f &&
                        uv[k][1] <= 1.0f);
        }
        double r = ((double)uv[1][0] - uv[0][0]) * ((double)uv[2][1] - uv[0][1]) -
                   ((double)uv[2][0] - uv[0][0]) * ((double)uv[1][1] - uv[0][1]);
        assert_true(r > 0.0);
    }
}

/* Texel-centre coverage by chart: no texel claimed by two charts, no other chart's texel within
 * LM_ATLAS_GUTTER - 1 texels of a chart's (Chebyshev), no texel strictly inside two triangles. */
static void assert_charts_apart(const lm_mesh *a, const lm_charts *c, int size)
{
    uint32_t *own = malloc((size_t)size * size * sizeof *own);
    assert_non_null(own);
    for (size_t i = 0; i < (size_t)size * size; i++)
        own[i] = LM_NONE;
    for (uint32_t i = 0; i < c->n_tris; i++) {
        const lm_tri *t = &a->tris[c->tri[i]];
        double p[3][2];
        for (int k = 0; k < 3; k++)
            p[k][0] = a->wedges[t->w[k]].uv[0] * (double)size,
            p[k][1] = (1.0 - a->wedges[t->w[k]].uv[1]) * (double)size;
        double area =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        double lo[2] = {p[0][0], p[0][1]}, hi[2] = {p[0][0], p[0][1]};
        for (int k = 1; k < 3; k++)
            for (int d = 0; d < 2; d++)
                lo[d] = p[k][d] < lo[d] ? p[k][d] : lo[d],
                hi[d] = p[k][d] > hi[d] ? p[k][d] : hi[d];
        for (int y = (int)lo[1]; y <= (int)hi[1] && y < size; y++)
            for (int x = (int)lo[0]; x <= (int)hi[0] && x < size && area != 0.0; x++) {
                int in = 1;
                for (int k = 0; k < 3; k++) {
                    const double *q = p[(k + 1) % 3], *r = p[(k + 2) % 3];
                    double b =
                        ((r[0] - q[0]) * (y + 0.5 - q[1]) - (x + 0.5 - q[0]) * (r[1] - q[1])) /
                        area;
                    in = in && b >= -1e-9;
                }
                if (!in)
                    continue;
                size_t j = (size_t)y * size + x;
                assert_true(own[j] == LM_NONE || own[j] == c->chart[i]);
                own[j] = c->chart[i];
            }
    }
    int g = LM_ATLAS_GUTTER - 1;
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++) {
            uint32_t o = own[(size_t)y * size + x];
            for (int dy = -g; o != LM_NONE && dy <= g; dy++)
                for (int dx = -g; dx <= g; dx++) {
                    int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= size || ny >= size)
                        continue;
                    uint32_t q = own[(size_t)ny * size + nx];
                    assert_true(q == LM_NONE || q == o);
                }
        }
    free(own);
    lm_bake_stats st;
    assert_int_equal(lm_bake_uv_check(a, size, &st), LM_OK);
    assert_int_equal(st.overlaps, 0);
    assert_true(st.texels > 0);
}

/* The packed atlas of m at size: valid, the source's triangles in order (positions, normals),
 * charts apart; returns it (caller destroys) and its charts in *c (caller frees). */
static lm_mesh *packed_checked(const lm_mesh *m, int size, lm_charts *c)
{
    lm_mesh *a;
    uint32_t n_charts;
    assert_int_equal(lm_atlas_packed(m, size, &a, &n_charts), LM_OK);
    assert_int_equal(lm_charts_make(m, c), LM_OK);
    assert_int_equal(n_charts, c->n_charts);
    assert_int_equal(a->live_tris, m->live_tris);
    assert_true(a->attrs & LM_ATTR_UV);
    for (uint32_t i = 0; i < c->n_tris; i++) /* live order: a's triangle i is m's i-th live */
        for (int k = 0; k < 3; k++)
            for (int x = 0; x < 3; x++) {
                uint32_t t = c->tri[i];
                assert_true(a->pos[lm_tri_vertex(a, i, k)][x] == m->pos[lm_tri_vertex(m, t, k)][x]);
                assert_true(a->wedges[a->tris[i].w[k]].normal[x] ==
                            m->wedges[m->tris[t].w[k]].normal[x]);
            }
    assert_inside_unflipped(a);
    /* the atlas has the source's live triangles first to last: its charts are the same */
    for (uint32_t i = 0; i < c->n_tris; i++)
        c->tri[i] = i;
    assert_charts_apart(a, c, size);
    return a;
}

/* The largest angle (degrees) between a wedge's tangent and its triangles' own frames made
 * orthogonal to the wedge's normal (the renderers'); *median too. */
static double frame_spread(const lm_mesh *a, double *median)
{
    float(*tan)[4];
    assert_int_equal(lm_mesh_tangents(a, &tan), LM_OK);
    double *ang = malloc(3 * (size_t)a->n_tris * sizeof *ang), worst = 0.0;
    size_t n = 0;
    for (uint32_t t = 0; t < a->n_tris; t++) {
        float p[3][3], uv[3][2], want[4];
        for (int k = 0; k < 3; k++) {
            const lm_wedge *w = &a->wedges[a->tris[t].w[k]];
            memcpy(p[k], a->pos[w->vertex], sizeof p[k]);
            memcpy(uv[k], w->uv, sizeof uv[k]);
        }
        double ft[3], fb[3];
        lm_tri_tangent_frame(p, uv, ft, fb);
        for (int k = 0; k < 3; k++) {
            uint32_t w = a->tris[t].w[k];
            lm_tangent_orthogonal(a->wedges[w].normal, ft, fb, want);
            assert_true(want[3] == tan[w][3]); /* the same handedness */
            double d = (double)want[0] * tan[w][0] + (double)want[1] * tan[w][1] +
                       (double)want[2] * tan[w][2];
            ang[n] = acos(d > 1.0 ? 1.0 : d) * 180.0 / 3.14159265358979323846;
            worst = ang[n] > worst ? ang[n] : worst;
            n++;
        }
    }
    for (size_t i = 1; i < n; i++) /* insertion sort: small */
        for (size_t j = i; j > 0 && ang[j - 1] > ang[j]; j--) {
            double x = ang[j];
            ang[j] = ang[j - 1], ang[j - 1] = x;
        }
    *median = ang[n / 2];
    free(ang);
    free(tan);
    return worst;
}

static void test_grid_is_one_chart(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_grid(12);
    lm_charts c;
    lm_mesh *a = packed_checked(m, 256, &c);
    assert_int_equal(c.n_charts, 1);
    assert_int_equal(a->n_wedges, m->n_verts); /* inside a chart a vertex keeps one wedge */
    double median, worst = frame_spread(a, &median);
    assert_true(worst < 0.01); /* planar: the renderers' frames are the tangents */
    lm_bake_stats st;
    assert_int_equal(lm_bake_uv_check(a, 256, &st), LM_OK);
    /* one square chart fills the map but for the gutters: (256 - 4)² of 256² */
    assert_true(st.texels > (uint64_t)(0.95 * 252 * 252));
    lm_charts_free(&c);
    lm_mesh_destroy(a);
    lm_mesh_destroy(m);
}

/* A planar grid past LM_CHART_MAX_TRIS triangles: cut into a few charts, still apart. */
static void test_large_grid_capped(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_grid(40); /* 3042 triangles */
    lm_charts c;
    lm_mesh *a = packed_checked(m, 512, &c);
    assert_true(c.n_charts >= 2 && c.n_charts <= 4);
    lm_charts_free(&c);
    lm_mesh_destroy(a);
    lm_mesh_destroy(m);
}

/* A unit cube, 8 vertices, each face two triangles, one wedge per corner with its face's
 * normal. */
static lm_mesh *make_cube(void)
{
    static const float v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                  {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    static const int f[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    lm_mesh *m;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "default", NULL, NULL, NULL, NULL), LM_OK);
    m->attrs = LM_ATTR_NORMAL;
    for (int i = 0; i < 8; i++)
        assert_int_equal(lm_mesh_add_vertex(m, v[i], NULL), LM_OK);
    for (int i = 0; i < 6; i++) {
        uint32_t w[4];
        for (int k = 0; k < 4; k++) {
            lm_wedge we = {.vertex = (uint32_t)f[i][k], .color = {1, 1, 1, 1}};
            for (int x = 0; x < 3; x++) { /* the face normal: (p1 - p0) x (p3 - p0) */
                const float *p0 = v[f[i][0]], *p1 = v[f[i][1]], *p3 = v[f[i][3]];
                double e1 = p1[(x + 1) % 3] - p0[(x + 1) % 3],
                       e2 = p3[(x + 2) % 3] - p0[(x + 2) % 3],
                       e3 = p1[(x + 2) % 3] - p0[(x + 2) % 3],
                       e4 = p3[(x + 1) % 3] - p0[(x + 1) % 3];
                we.normal[x] = (float)(e1 * e2 - e3 * e4);
            }
            assert_int_equal(lm_mesh_add_wedge(m, &we, &w[k]), LM_OK);
        }
        uint32_t t1[3] = {w[0], w[1], w[2]}, t2[3] = {w[0], w[2], w[3]};
        assert_int_equal(lm_mesh_add_tri(m, t1, 0, NULL), LM_OK);
        assert_int_equal(lm_mesh_add_tri(m, t2, 0, NULL), LM_OK);
    }
    return m;
}

static void test_cube_charts(void **state)
{
    (void)state;
    lm_mesh *m = make_cube();
    lm_charts c;
    lm_mesh *a = packed_checked(m, 128, &c);
    assert_true(c.n_charts >= 6);
    for (uint32_t i = 0; i < c.n_tris; i++) /* a chart never spans two faces */
        for (uint32_t j = 0; j < c.n_tris; j++)
            if (c.chart[i] == c.chart[j])
                assert_int_equal(i / 2, j / 2);
    lm_charts_free(&c);
    lm_mesh_destroy(a);
    lm_mesh_destroy(m);
}

/* Two turns of a helical ramp between radii 1 and 2, 48 steps a turn, rising 0.05 a turn: every
 * normal within 2° of +z, but its projection on z = 0 covers the annulus twice. */
static lm_mesh *make_ramp(void)
{
    lm_mesh *m;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "default", NULL, NULL, NULL, NULL), LM_OK);
    m->attrs = LM_ATTR_NORMAL;
    int steps = 96;
    for (int i = 0; i <= steps; i++)
        for (int r = 1; r <= 2; r++) {
            double th = 2.0 * 3.14159265358979323846 * i / 48.0;
            float p[3] = {(float)(r * cos(th)), (float)(r * sin(th)), (float)(0.05 * i / 48.0)};
            uint32_t v, w;
            assert_int_equal(lm_mesh_add_vertex(m, p, &v), LM_OK);
            lm_wedge we = {.vertex = v, .normal = {0, 0, 1}, .color = {1, 1, 1, 1}};
            assert_int_equal(lm_mesh_add_wedge(m, &we, &w), LM_OK);
        }
    for (uint32_t i = 0; i < (uint32_t)steps; i++) {
        uint32_t a = 2 * i, b = a + 1, c = a + 2, d = a + 3; /* inner a, c; outer b, d */
        uint32_t t1[3] = {a, b, d}, t2[3] = {a, d, c};
        assert_int_equal(lm_mesh_add_tri(m, t1, 0, NULL), LM_OK);
        assert_int_equal(lm_mesh_add_tri(m, t2, 0, NULL), LM_OK);
    }
    return m;
}

static void test_ramp_splits_where_it_folds(void **state)
{
    (void)state;
    lm_mesh *m = make_ramp();
    lm_charts c;
    lm_mesh *a = packed_checked(m, 512, &c);
    assert_true(c.n_charts >= 2);
    assert_true(c.n_charts <= 4);
    lm_charts_free(&c);
    lm_mesh_destroy(a);
    lm_mesh_destroy(m);
}

static void test_sphere_charts_and_frames(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(3);
    lm_charts c;
    lm_mesh *a = packed_checked(m, 512, &c), *b;
    assert_true(c.n_charts > 6 && c.n_charts < m->live_tris / 4);
    double median, worst = frame_spread(a, &median);
    printf("sphere(3): %u triangles, %u charts; renderer frame vs tangent: median %.2f, max %.2f "
           "degrees\n",
           m->live_tris, c.n_charts, median, worst);
    assert_true(median < 3.0);
    assert_true(worst < 20.0);
    assert_int_equal(lm_atlas_packed(m, 512, &b, NULL), LM_OK); /* the same bytes again */
    assert_int_equal(lm_mesh_hash(a), lm_mesh_hash(b));
    lm_mesh_destroy(b);
    lm_charts_free(&c);
    lm_mesh_destroy(a);
    lm_mesh_destroy(m);
}

/* A packed atlas baked, written as GLB and read back: the same triangles and wedges, the texture
 * coordinates (within float rounding) and the tangents a reader derives (the file's TANGENT
 * comes from the same function as the bake's) close to the ones the bake used. */
static void test_packed_glb_round_trip(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2), *a, *back;
    assert_int_equal(lm_atlas_packed(m, 256, &a, NULL), LM_OK);
    lm_image *img;
    assert_int_equal(lm_bake_normal(m, a, 256, NULL, &img, NULL), LM_OK);
    assert_int_equal(lm_mesh_set_normal_map(a, 0, "n.png", img), LM_OK);
    char *dir = lmt_mkdtemp(), path[512];
    snprintf(path, sizeof path, "%s/packed.glb", dir);
    assert_int_equal(lm_mesh_save(path, a), LM_OK);
    assert_int_equal(lm_mesh_load(path, NULL, &back), LM_OK);
    assert_int_equal(back->live_tris, a->live_tris);
    assert_int_equal(back->n_wedges, a->n_wedges);
    float(*ta)[4], (*tb)[4];
    assert_int_equal(lm_mesh_tangents(a, &ta), LM_OK);
    assert_int_equal(lm_mesh_tangents(back, &tb), LM_OK);
    for (uint32_t t = 0; t < a->n_tris; t++)
        for (int k = 0; k < 3; k++) {
            const lm_wedge *wa = &a->wedges[a->tris[t].w[k]],
                           *wb = &back->wedges[back->tris[t].w[k]];
            const float *xa = ta[a->tris[t].w[k]], *xb = tb[back->tris[t].w[k]];
            for (int c = 0; c < 2; c++) /* glTF's v runs down: 1 - v twice loses low bits */
                assert_true(fabsf(wa->uv[c] - wb->uv[c]) < 1e-6f);
            for (int c = 0; c < 3; c++)
                assert_true(fabsf(xa[c] - xb[c]) < 1e-4f);
            assert_true(xa[3] == xb[3]);
        }
    free(ta);
    free(tb);
    lm_mesh_destroy(back);
    lm_mesh_destroy(a);
    lm_mesh_destroy(m);
    lmt_rmdir(dir);
}

static void test_too_small_refused(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(3), *a = (lm_mesh *)1;
    assert_int_equal(lm_atlas_packed(m, 16, &a, NULL), LM_E_INVALID);
    assert_null(a);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tri2_overlap),
        cmocka_unit_test(test_grid_is_one_chart),
        cmocka_unit_test(test_large_grid_capped),
        cmocka_unit_test(test_cube_charts),
        cmocka_unit_test(test_ramp_splits_where_it_folds),
        cmocka_unit_test(test_sphere_charts_and_frames),
        cmocka_unit_test(test_packed_glb_round_trip),
        cmocka_unit_test(test_too_small_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
