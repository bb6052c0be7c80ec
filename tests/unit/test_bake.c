/* tests/unit/test_bake.c — the normal-map and base-colour bakes (common/bake_normal.h,
 * common/bake_color.h) and what they stand on: the hierarchy's line query against every triangle,
 * the texture-coordinate check (overlaps, leaving [0, 1], none), a bake of a tilted original onto
 * a flat quad (texel by texel, also with u mirrored), a colour bake of a textured quad onto the
 * same UVs (the texture back texel by texel), mirrored and rotated UVs (the right texels), factor
 * and vertex colours (their product), both maps in one walk (the bytes of each alone), and the
 * per-triangle atlas (valid, and each wedge's tangent its triangle's frame: the renderers'
 * per-triangle frame and the GLB's TANGENT agree on it), and its variant keyed by triangle id. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/bake_color.h"
#include "common/bake_normal.h"
#include "common/bvh.h"
#include "common/io/mesh_io.h"
#include "common/tangents.h"
#include "common/uv_atlas.h"
#include "test_support.h"

/* Reference: the line o + t d against triangle (a, b, c) by its plane, then inside by barycentrics.
 */
static int ref_hit(const float tr[3][3], const double o[3], const double d[3], double *t)
{
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++)
        e1[k] = (double)tr[1][k] - tr[0][k], e2[k] = (double)tr[2][k] - tr[0][k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double nd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    if (fabs(nd) < 1e-15)
        return 0;
    double s =
        (n[0] * (tr[0][0] - o[0]) + n[1] * (tr[0][1] - o[1]) + n[2] * (tr[0][2] - o[2])) / nd;
    double p[3] = {o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2]};
    for (int k = 0; k < 3; k++) { /* p on the inner side of each edge */
        const float *a = tr[k], *b = tr[(k + 1) % 3];
        double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
               ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        double c[3] = {ab[1] * ap[2] - ab[2] * ap[1], ab[2] * ap[0] - ab[0] * ap[2],
                       ab[0] * ap[1] - ab[1] * ap[0]};
        if (c[0] * n[0] + c[1] * n[1] + c[2] * n[2] < -1e-12)
            return 0;
    }
    *t = s;
    return 1;
}

static void test_line_hit_against_every_triangle(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(3);
    lm_bvh *b;
    assert_int_equal(lm_bvh_create(m, &b), LM_OK);
    uint64_t seed = 12345;
    int hits = 0;
    for (int q = 0; q < 400; q++) {
        double o[3], d[3], tmax = 0.2 + lmt_urand(&seed);
        for (int k = 0; k < 3; k++)
            o[k] = 2.4 * lmt_urand(&seed) - 1.2, d[k] = 2.0 * lmt_urand(&seed) - 1.0;
        for (int facing = 0; facing < 2; facing++) {
            double best = INFINITY;
            for (uint32_t t = 0; t < m->n_tris; t++) {
                float tr[3][3];
                for (int v = 0; v < 3; v++)
                    memcpy(tr[v], m->pos[lm_tri_vertex(m, t, v)], sizeof tr[v]);
                double s, e1[3], e2[3];
                for (int k = 0; k < 3; k++)
                    e1[k] = (double)tr[1][k] - tr[0][k], e2[k] = (double)tr[2][k] - tr[0][k];
                double fn = (e1[1] * e2[2] - e1[2] * e2[1]) * d[0] +
                            (e1[2] * e2[0] - e1[0] * e2[2]) * d[1] +
                            (e1[0] * e2[1] - e1[1] * e2[0]) * d[2];
                if (m->tri_alive[t] && (!facing || fn > 0) && ref_hit(tr, o, d, &s) &&
                    fabs(s) <= tmax && fabs(s) < best)
                    best = fabs(s);
            }
            uint32_t tri;
            double t, bary[3];
            int hit = lm_bvh_line_hit(b, o, d, tmax, facing, &tri, &t, bary);
            assert_int_equal(hit, best != INFINITY);
            if (!hit)
                continue;
            hits++;
            assert_true(fabs(fabs(t) - best) < 1e-9);
            double p[3] = {0, 0, 0};
            for (int k = 0; k < 3; k++)
                for (int a = 0; a < 3; a++)
                    p[a] += bary[k] * m->pos[lm_tri_vertex(m, tri, k)][a];
            for (int a = 0; a < 3; a++)
                assert_true(fabs(p[a] - (o[a] + t * d[a])) < 1e-9);
        }
    }
    assert_true(hits > 100);
    lm_bvh_destroy(b);
    lm_mesh_destroy(m);
}

static void test_uv_check(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_grid(3);
    lm_bake_stats s;
    assert_int_equal(lm_bake_uv_check(m, 64, &s), LM_OK);
    assert_int_equal(s.texels, 64 * 64);
    assert_int_equal(s.overlaps, 0);
    /* the last triangle's corners moved onto the first one's coordinates: an overlap */
    uint32_t last = m->n_tris - 1, w[3];
    memcpy(w, m->tris[last].w, sizeof w);
    for (int k = 0; k < 3; k++) {
        lm_wedge copy = m->wedges[w[k]];
        memcpy(copy.uv, m->wedges[m->tris[0].w[k]].uv, sizeof copy.uv);
        assert_int_equal(lm_mesh_add_wedge(m, &copy, &m->tris[last].w[k]), LM_OK);
    }
    assert_int_equal(lm_bake_uv_check(m, 64, &s), LM_E_INVALID);
    assert_true(s.overlaps > 100);
    assert_non_null(strstr(lm_last_error(), "overlap"));
    lm_mesh_destroy(m);

    m = lmt_make_grid(3);
    m->wedges[0].uv[0] = 1.5f;
    assert_int_equal(lm_bake_uv_check(m, 64, NULL), LM_E_INVALID);
    assert_non_null(strstr(lm_last_error(), "[0, 1]"));
    m->wedges[0].uv[0] = 0.0f;
    m->attrs &= ~(uint32_t)LM_ATTR_UV;
    assert_int_equal(lm_bake_uv_check(m, 64, NULL), LM_E_INVALID);
    lm_mesh_destroy(m);
}

static uint8_t enc(double x)
{
    return (uint8_t)floor((x * 0.5 + 0.5) * 255.0 + 0.5);
}

/* A flat quad (normal +z) baked from a copy 0.01 above whose normals lean 30 degrees towards +x:
 * every texel is that normal in the quad's frame (T = ±x as u runs along ±x, B = +y). */
static void bake_tilted(int mirrored)
{
    lm_mesh *res = lmt_make_grid(2), *orig = lmt_make_grid(2);
    double s = sin(M_PI / 6), c = cos(M_PI / 6);
    for (uint32_t v = 0; v < orig->n_verts; v++)
        orig->pos[v][2] = 0.01f;
    for (uint32_t w = 0; w < orig->n_wedges; w++) {
        orig->wedges[w].normal[0] = (float)s, orig->wedges[w].normal[2] = (float)c;
        if (mirrored)
            res->wedges[w].uv[0] = 1.0f - res->wedges[w].uv[0];
    }
    if (mirrored) /* the mirrored chart faces the other way in u, v: still one layer */
        assert_int_equal(lm_bake_uv_check(res, 16, NULL), LM_OK);
    lm_image *img;
    lm_bake_stats st;
    assert_int_equal(lm_bake_normal(orig, res, 16, NULL, &img, &st), LM_OK);
    assert_int_equal(st.texels, 256);
    assert_int_equal(st.hits, 256);
    float(*tan)[4];
    assert_int_equal(lm_mesh_tangents(res, &tan), LM_OK);
    assert_true(tan[0][3] == (mirrored ? -1.0f : 1.0f));
    free(tan);
    for (int i = 0; i < 256; i++) {
        const uint8_t *p = img->pixels + 4 * i;
        assert_int_equal(p[0], enc(mirrored ? -s : s));
        assert_int_equal(p[1], 128);
        assert_int_equal(p[2], enc(c));
        assert_int_equal(p[3], 255);
    }
    lm_image_destroy(img);
    lm_mesh_destroy(res);
    lm_mesh_destroy(orig);
}

static void test_bake_tilted_normals(void **state)
{
    (void)state;
    bake_tilted(0);
    bake_tilted(1);
}

/* Gutters: a quad whose chart covers the left half of the map fills the right half too. */
static void test_bake_gutters(void **state)
{
    (void)state;
    lm_mesh *res = lmt_make_grid(2), *orig = lmt_make_grid(2);
    for (uint32_t w = 0; w < res->n_wedges; w++)
        res->wedges[w].uv[0] *= 0.5f;
    for (uint32_t w = 0; w < orig->n_wedges; w++)
        orig->wedges[w].normal[1] = 1.0f, orig->wedges[w].normal[2] = 1.0f;
    lm_image *img;
    lm_bake_stats st;
    assert_int_equal(lm_bake_normal(orig, res, 32, NULL, &img, &st), LM_OK);
    assert_int_equal(st.texels, 32 * 16);
    for (int i = 0; i < 32 * 32; i++) {
        assert_int_equal(img->pixels[4 * i + 0], 128);
        assert_int_equal(img->pixels[4 * i + 1], enc(sqrt(0.5)));
    }
    lm_image_destroy(img);
    lm_mesh_destroy(res);
    lm_mesh_destroy(orig);
}

/* A 16 x 16 texture of 4 x 4 blocks, each an arbitrary colour (fixed seed). */
static lm_image *block_texture(void)
{
    lm_image *img;
    uint64_t seed = 39;
    assert_int_equal(lm_image_create(16, 16, &img), LM_OK);
    uint8_t block[16][3];
    for (int b = 0; b < 16; b++)
        for (int ch = 0; ch < 3; ch++)
            block[b][ch] = (uint8_t)(lmt_urand(&seed) * 256.0);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            uint8_t *px = img->pixels + 4 * (y * 16 + x);
            memcpy(px, block[(y / 4) * 4 + x / 4], 3);
            px[3] = 255;
        }
    return img;
}

/* The original: a unit quad 0.01 above the result's, textured with block_texture. */
static lm_mesh *textured_quad(void)
{
    lm_mesh *m = lmt_make_grid(2);
    for (uint32_t v = 0; v < m->n_verts; v++)
        m->pos[v][2] = 0.01f;
    m->materials[0].texture = block_texture();
    return m;
}

static void assert_near(int got, int want)
{
    if (abs(got - want) > 1)
        fail_msg("texel %d, expected %d (within 1)", got, want);
}

/* The result's UVs: 0 the same as its positions, 1 u mirrored, 2 turned a quarter
 * (u, v) = (1 - y, x); the texture's texel (column, row) that map texel (X, Y) must hold. */
static void remap_uv(lm_mesh *res, int how)
{
    for (uint32_t w = 0; w < res->n_wedges; w++) {
        const float *p = res->pos[res->wedges[w].vertex];
        float *uv = res->wedges[w].uv;
        uv[0] = how == 0 ? p[0] : how == 1 ? 1.0f - p[0] : 1.0f - p[1];
        uv[1] = how == 2 ? p[0] : p[1];
    }
}

static void source_texel(int how, int X, int Y, int *col, int *row)
{
    *col = how == 0 ? X : how == 1 ? 15 - X : 15 - Y;
    *row = how == 2 ? X : Y;
}

/* Same, mirrored and turned UVs: every texel of the map is the texture's texel at that point. */
static void test_bake_color_texture(void **state)
{
    (void)state;
    for (int how = 0; how < 3; how++) {
        lm_mesh *orig = textured_quad(), *res = lmt_make_grid(2);
        remap_uv(res, how);
        assert_int_equal(lm_bake_uv_check(res, 16, NULL), LM_OK);
        lm_image *img;
        lm_bake_stats st;
        assert_int_equal(lm_bake_color(orig, res, 16, &img, &st), LM_OK);
        assert_int_equal(st.texels, 256);
        assert_int_equal(st.hits, 256);
        const lm_image *tex = orig->materials[0].texture;
        for (int Y = 0; Y < 16; Y++)
            for (int X = 0; X < 16; X++) {
                int col, row;
                source_texel(how, X, Y, &col, &row);
                const uint8_t *got = img->pixels + 4 * (Y * 16 + X),
                              *want = tex->pixels + 4 * (row * 16 + col);
                for (int ch = 0; ch < 3; ch++)
                    assert_near(got[ch], want[ch]);
                assert_int_equal(got[3], 255);
            }
        lm_image_destroy(img);
        lm_mesh_destroy(res);
        lm_mesh_destroy(orig);
    }
}

/* No texture: the factor times the vertex colours, (0.5 x, 0.25 y, 1) at (x, y). */
static void test_bake_color_factor_and_vertex_colours(void **state)
{
    (void)state;
    lm_mesh *orig = lmt_make_grid(2), *res = lmt_make_grid(2);
    orig->attrs |= LM_ATTR_COLOR;
    float dif[4] = {0.5f, 0.25f, 1.0f, 1.0f};
    memcpy(orig->materials[0].diffuse, dif, sizeof dif);
    for (uint32_t w = 0; w < orig->n_wedges; w++) {
        const float *p = orig->pos[orig->wedges[w].vertex];
        float c[4] = {p[0], p[1], 1.0f, 1.0f};
        memcpy(orig->wedges[w].color, c, sizeof c);
    }
    lm_image *img;
    assert_int_equal(lm_bake_color(orig, res, 16, &img, NULL), LM_OK);
    for (int Y = 0; Y < 16; Y++)
        for (int X = 0; X < 16; X++) {
            double x = (X + 0.5) / 16.0, y = 1.0 - (Y + 0.5) / 16.0;
            const uint8_t *got = img->pixels + 4 * (Y * 16 + X);
            assert_near(got[0], (int)floor(255.0 * 0.5 * x + 0.5));
            assert_near(got[1], (int)floor(255.0 * 0.25 * y + 0.5));
            assert_int_equal(got[2], 255);
        }
    lm_image_destroy(img);
    lm_mesh_destroy(res);
    lm_mesh_destroy(orig);
}

/* Both maps in one walk (what --bake normal,color does): each the bytes of its bake alone, the
 * gutters included (the chart covers the map's left half). */
static void test_bake_both_in_one_walk(void **state)
{
    (void)state;
    lm_mesh *orig = textured_quad(), *res = lmt_make_grid(2);
    for (uint32_t w = 0; w < orig->n_wedges; w++)
        orig->wedges[w].normal[0] = 0.5f;
    for (uint32_t w = 0; w < res->n_wedges; w++)
        res->wedges[w].uv[0] *= 0.5f;
    lm_image *n1, *c1, *n2, *c2;
    lm_bake_stats s1, s2;
    assert_int_equal(lm_bake_normal(orig, res, 32, NULL, &n1, NULL), LM_OK);
    assert_int_equal(lm_bake_color(orig, res, 32, &c1, &s1), LM_OK);
    assert_int_equal(lm_image_create(32, 32, &n2), LM_OK);
    assert_int_equal(lm_image_create(32, 32, &c2), LM_OK);
    lm_bake_sink sinks[2];
    lm_bake_normal_sink(n2, &sinks[0]);
    lm_bake_color_sink(c2, &sinks[1]);
    lm_image *imgs[2] = {n2, c2};
    assert_int_equal(lm_bake_walk(orig, res, 32, sinks, 2, imgs, 2, &s2), LM_OK);
    assert_memory_equal(n1->pixels, n2->pixels, 32 * 32 * 4);
    assert_memory_equal(c1->pixels, c2->pixels, 32 * 32 * 4);
    assert_int_equal(s1.texels, s2.texels);
    assert_int_equal(s1.hits, s2.hits);
    /* the gutter (right half) repeats the chart's last column */
    assert_memory_equal(c2->pixels + 4 * 31, c2->pixels + 4 * 15, 4);
    lm_image *imgs_all[4] = {n1, c1, n2, c2};
    for (int i = 0; i < 4; i++)
        lm_image_destroy(imgs_all[i]);
    lm_mesh_destroy(res);
    lm_mesh_destroy(orig);
}

/* Each wedge's tangent (what the GLB writer stores as TANGENT) against its triangle's own frame
 * made orthogonal to the wedge's normal (what the renderers light with): the same bits. */
static void assert_wedge_tangents_are_triangle_frames(const lm_mesh *a)
{
    float(*tan)[4];
    assert_int_equal(lm_mesh_tangents(a, &tan), LM_OK);
    for (uint32_t t = 0; t < a->n_tris; t++) {
        float p[3][3], uv[3][2], want[4];
        for (int k = 0; a->tri_alive[t] && k < 3; k++) {
            const lm_wedge *w = &a->wedges[a->tris[t].w[k]];
            memcpy(p[k], a->pos[w->vertex], sizeof p[k]);
            memcpy(uv[k], w->uv, sizeof uv[k]);
        }
        if (!a->tri_alive[t])
            continue;
        double ft[3], fb[3];
        lm_tri_tangent_frame(p, uv, ft, fb);
        for (int k = 0; k < 3; k++) {
            uint32_t w = a->tris[t].w[k];
            lm_tangent_orthogonal(a->wedges[w].normal, ft, fb, want);
            assert_memory_equal(want, tan[w], sizeof want);
        }
    }
    free(tan);
}

static void test_atlas(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2), *a;
    assert_int_equal(lm_atlas_per_triangle(m, 256, &a), LM_OK);
    assert_int_equal(a->live_tris, m->live_tris);
    assert_int_equal(lm_bake_uv_check(a, 256, NULL), LM_OK);
    for (uint32_t t = 0; t < a->n_tris; t++) /* the source's positions and normals, in order */
        for (int k = 0; k < 3; k++)
            for (int x = 0; x < 3; x++)
                assert_true(
                    a->pos[lm_tri_vertex(a, t, k)][x] == m->pos[lm_tri_vertex(m, t, k)][x] &&
                    a->wedges[a->tris[t].w[k]].normal[x] == m->wedges[m->tris[t].w[k]].normal[x]);
    assert_wedge_tangents_are_triangle_frames(a);
    lm_mesh_destroy(a);
    assert_int_equal(lm_atlas_per_triangle(m, 64, &a), LM_E_INVALID);
    assert_null(a);
    lm_mesh_destroy(m);
}

/* The atlas keyed by triangle id (maps in the loop, coordinator/job/bake_loop.h): triangle t's
 * chart in cell t mod cells², with lm_atlas_cell_uv's bits (the views' triangles are rewritten
 * with them), a dead triangle's cell left empty, lm_atlas_per_triangle's charts those bits too;
 * valid for a bake. */
static void test_atlas_by_id(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2), *a;
    m->tri_alive[3] = 0; /* a dead slot: the live triangles after it keep their ids' cells */
    m->live_tris--;
    uint32_t cells = lm_atlas_cells(m->n_tris + m->n_tris / 4 + 16);
    assert_int_equal(lm_atlas_by_id(m, 512, cells, &a), LM_OK);
    assert_int_equal(a->live_tris, m->live_tris);
    assert_int_equal(lm_bake_uv_check(a, 512, NULL), LM_OK);
    uint32_t i = 0;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        for (int k = 0; k < 3; k++) {
            float uv[2];
            lm_atlas_cell_uv(t % (cells * cells), cells, 512, k, uv);
            const float *w = a->wedges[a->tris[i].w[k]].uv;
            assert_true(w[0] == uv[0] && w[1] == uv[1]);
        }
        i++;
    }
    lm_mesh_destroy(a);
    assert_int_equal(lm_atlas_per_triangle(m, 512, &a), LM_OK);
    uint32_t c = lm_atlas_cells(m->live_tris);
    for (uint32_t t = 0; t < a->n_tris; t++)
        for (int k = 0; k < 3; k++) {
            float uv[2];
            lm_atlas_cell_uv(t, c, 512, k, uv);
            const float *w = a->wedges[a->tris[t].w[k]].uv;
            assert_true(w[0] == uv[0] && w[1] == uv[1]);
        }
    lm_mesh_destroy(a);
    assert_int_equal(lm_atlas_by_id(m, 64, cells, &a), LM_E_INVALID);
    assert_null(a);
    lm_mesh_destroy(m);
}

/* A baked atlas mesh written as GLB and read back: still one triangle per wedge (nothing
 * merged), so the tangents a reader derives (and the file's TANGENT, written from the same
 * function) are the renderer's per-triangle frames. */
static void test_atlas_glb_round_trip(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2), *a, *back;
    assert_int_equal(lm_atlas_per_triangle(m, 256, &a), LM_OK);
    lm_image *img;
    assert_int_equal(lm_bake_normal(m, a, 256, NULL, &img, NULL), LM_OK);
    assert_int_equal(lm_mesh_set_normal_map(a, 0, "n.png", img), LM_OK);
    char *dir = lmt_mkdtemp(), path[512];
    snprintf(path, sizeof path, "%s/atlas.glb", dir);
    assert_int_equal(lm_mesh_save(path, a), LM_OK);
    assert_int_equal(lm_mesh_load(path, NULL, &back), LM_OK);
    assert_int_equal(back->live_tris, a->live_tris);
    assert_int_equal(back->n_wedges, 3 * back->live_tris);
    assert_non_null(back->materials[0].normal_map);
    assert_wedge_tangents_are_triangle_frames(back);
    lm_mesh_destroy(back);
    lm_mesh_destroy(a);
    lm_mesh_destroy(m);
    lmt_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_line_hit_against_every_triangle),
        cmocka_unit_test(test_uv_check),
        cmocka_unit_test(test_bake_tilted_normals),
        cmocka_unit_test(test_bake_gutters),
        cmocka_unit_test(test_bake_color_texture),
        cmocka_unit_test(test_bake_color_factor_and_vertex_colours),
        cmocka_unit_test(test_bake_both_in_one_walk),
        cmocka_unit_test(test_atlas),
        cmocka_unit_test(test_atlas_by_id),
        cmocka_unit_test(test_atlas_glb_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
