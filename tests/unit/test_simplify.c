/* tests/unit/test_simplify.c — the initial simplifiers (QEM through meshoptimizer, Rossignac–Borrel
 * clustering) on real models (bunny, spider) and the procedural frog, and the frog itself. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "coordinator/frog/frog.h"
#include "coordinator/frog/frog_internal.h"
#include "coordinator/simplify/simplify_internal.h"

/* ---- helpers ----------------------------------------------------------------------------------
 */

static lm_mesh *load_or_skip(const char *path)
{
    if (!path) {
        print_message("test data missing (run scripts/install-deps.sh); skipping\n");
        skip();
    }
    lm_mesh *m = NULL;
    lm_status s = lm_mesh_load(path, NULL, &m);
    if (s)
        fail_msg("loading %s: %s", path, lm_last_error());
    return m;
}

static uint32_t live_wedges(const lm_mesh *m)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < m->n_wedges; i++)
        n += m->wedge_alive[i];
    return n;
}

/* Every output mesh: valid, compact (no dead or unused elements), adjacency built. */
static void check_output(const lm_mesh *m)
{
    assert_int_equal(lm_mesh_validate(m), LM_OK);
    assert_int_equal(m->live_verts, m->n_verts);
    assert_int_equal(m->live_tris, m->n_tris);
    uint8_t *used_v = calloc(m->n_verts + 1, 1), *used_w = calloc(m->n_wedges + 1, 1);
    for (uint32_t t = 0; t < m->n_tris; t++)
        for (int k = 0; k < 3; k++) {
            used_w[m->tris[t].w[k]] = 1;
            used_v[lm_tri_vertex(m, t, k)] = 1;
        }
    for (uint32_t v = 0; v < m->n_verts; v++) {
        assert_true(used_v[v]);
        uint32_t tris[64];
        assert_true(lm_mesh_vertex_tris(m, v, tris, 64) > 0); /* adjacency is there */
    }
    for (uint32_t w = 0; w < m->n_wedges; w++)
        assert_true(used_w[w]);
    free(used_v);
    free(used_w);
}

static void check_target(const lm_mesh *in, co_simplify_method method, uint32_t target)
{
    lm_mesh *out = NULL;
    lm_status s = co_simplify(in, method, target, &out);
    if (s)
        fail_msg("simplify to %u: %s", target, lm_last_error());
    print_message("%s: %u -> %u vertices (target %u), %u triangles\n",
                  method == CO_SIMPLIFY_QEM ? "qem" : "cluster", in->live_verts, out->live_verts,
                  target, out->live_tris);
    assert_true(fabs((double)out->live_verts - target) <= 0.05 * target);
    check_output(out);
    assert_int_equal(out->n_materials, in->n_materials);
    lm_mesh_destroy(out);
}

/* ---- QEM and clustering on the bunny --------------------------------------------------------- */

static void test_qem_bunny(void **state)
{
    (void)state;
    lm_mesh *m = load_or_skip(lmt_bunny_path());
    assert_true(m->live_verts > 30000);
    check_target(m, CO_SIMPLIFY_QEM, m->live_verts / 100);
    check_target(m, CO_SIMPLIFY_QEM, m->live_verts / 10);
    lm_mesh_destroy(m);
}

static void test_cluster_bunny(void **state)
{
    (void)state;
    lm_mesh *m = load_or_skip(lmt_bunny_path());
    check_target(m, CO_SIMPLIFY_CLUSTER, m->live_verts / 100);
    check_target(m, CO_SIMPLIFY_CLUSTER, m->live_verts / 10);
    lm_mesh_destroy(m);
}

/* ---- QEM keeps parts, seams and materials ------------------------------------------------------
 */

/* The spider: 18 closed or nearly closed parts stuck together. At half its vertices QEM keeps every
 * part as it is; at a quarter no part is lost (a thin part may split where meshoptimizer pinches
 * it: 0.18 does not check the link condition). Much lower, whole legs vanish, as the paper's
 * Figure 10b shows for memoryless simplification. */
static void test_qem_spider_components(void **state)
{
    (void)state;
    lm_mesh *m = load_or_skip(lmt_spider_path());
    uint32_t parts = lm_mesh_count_components(m);
    assert_true(parts > 1);
    for (uint32_t div = 2; div <= 4; div *= 2) {
        uint32_t target = m->live_verts / div;
        lm_mesh *out = NULL;
        lm_status s = co_simplify(m, CO_SIMPLIFY_QEM, target, &out);
        if (s)
            fail_msg("spider to %u: %s", target, lm_last_error());
        uint32_t got = lm_mesh_count_components(out);
        print_message("spider: %u parts, %u -> %u vertices, %u parts\n", parts, m->live_verts,
                      out->live_verts, got);
        if (div == 2)
            assert_int_equal(got, parts);
        else
            assert_true(got >= parts);
        check_output(out);
        lm_mesh_destroy(out);
    }
    lm_mesh_destroy(m);
}

/* No part disappears silently (issue 39): the spider at 300 vertices loses its 38-triangle eye
 * 'Duplicate05' to QEM and 'Auge' to clustering unless kept; both simplifiers keep every named part
 * (at its smallest) within the target's tolerance, and a mesh that lost one names it. */
static void test_spider_keeps_parts(void **state)
{
    (void)state;
    lm_mesh *m = load_or_skip(lmt_spider_path());
    uint32_t parts = lm_mesh_count_parts(m);
    assert_int_equal(parts, 19);
    char names[256];
    for (int method = CO_SIMPLIFY_QEM; method <= CO_SIMPLIFY_CLUSTER; method++) {
        lm_mesh *out = NULL;
        lm_status s = co_simplify(m, (co_simplify_method)method, 300, &out);
        if (s)
            fail_msg("spider to 300 (method %d): %s", method, lm_last_error());
        print_message("spider to 300 (method %d): %u vertices, %u parts\n", method, out->live_verts,
                      lm_mesh_count_parts(out));
        assert_int_equal(lm_mesh_count_parts(out), parts);
        assert_int_equal(co_simplify_lost_parts(m, out, names, sizeof names), 0);
        check_output(out);
        uint32_t body = lm_mesh_find_part(out, "HLeib01"); /* the eye moved away: it is named */
        assert_true(body != LM_NONE);
        for (uint32_t t = 0; t < out->n_tris; t++)
            if (out->tri_alive[t] && !strcmp(lm_mesh_part_name(out, t), "Duplicate05"))
                out->tris[t].part = body;
        assert_int_equal(co_simplify_lost_parts(m, out, names, sizeof names), 1);
        assert_string_equal(names, "'Duplicate05'");
        lm_mesh_destroy(out);
    }
    lm_mesh_destroy(m);
}

/* The chart a UV lies in (the frog's atlas: body left half, legs bottom right, eyes top right). */
static int chart_of(const float uv[2])
{
    return uv[0] < 0.5f   ? CO_FROG_CHART_BODY
           : uv[1] < 0.5f ? CO_FROG_CHART_LEGS
                          : CO_FROG_CHART_EYES;
}

static void test_qem_frog_seams(void **state)
{
    (void)state;
    lm_mesh *frog = NULL, *out = NULL;
    assert_int_equal(co_frog_generate(20000, 1, &frog), LM_OK);
    uint32_t target = frog->live_verts / 20;
    lm_status s = co_simplify(frog, CO_SIMPLIFY_QEM, target, &out);
    if (s)
        fail_msg("frog to %u: %s", target, lm_last_error());
    check_output(out);
    print_message("frog qem: %u verts, %u wedges, %u tris\n", out->live_verts, live_wedges(out),
                  out->live_tris);
    /* Seams kept: more wedges than vertices, and no triangle spans two texture charts. */
    assert_true(live_wedges(out) > out->live_verts);
    for (uint32_t t = 0; t < out->n_tris; t++) {
        int c = chart_of(out->wedges[out->tris[t].w[0]].uv);
        for (int k = 1; k < 3; k++)
            assert_int_equal(chart_of(out->wedges[out->tris[t].w[k]].uv), c);
    }
    assert_int_equal(lm_mesh_count_components(out), CO_FROG_PARTS);
    assert_non_null(out->materials[0].texture);
    assert_ptr_not_equal(out->materials[0].texture, frog->materials[0].texture); /* cloned */
    lm_mesh_destroy(out);
    lm_mesh_destroy(frog);
}

/* Two materials on one sphere: the boundary between them must survive simplification. */
static void test_qem_material_boundary(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(4), *out = NULL;
    assert_int_equal(lm_mesh_add_material(m, "second", NULL, NULL, NULL, NULL), LM_OK);
    uint32_t upper = 0;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        float z = 0;
        for (int k = 0; k < 3; k++)
            z += m->pos[lm_tri_vertex(m, t, k)][2];
        m->tris[t].material = z > 0 ? 1 : 0;
        upper += z > 0;
    }
    assert_int_equal(co_simplify(m, CO_SIMPLIFY_QEM, m->live_verts / 8, &out), LM_OK);
    check_output(out);
    uint32_t first[2] = {0, 0};
    for (uint32_t t = 0; t < out->n_tris; t++) {
        float z = 0;
        for (int k = 0; k < 3; k++)
            z += out->pos[lm_tri_vertex(out, t, k)][2];
        first[out->tris[t].material]++;
        /* each side keeps its material: no triangle of material 1 below the equator */
        assert_true(out->tris[t].material == 1 ? z > -1e-3f : z < 1e-3f);
    }
    assert_true(first[0] > 0 && first[1] > 0 && upper > 0);
    lm_mesh_destroy(out);
    lm_mesh_destroy(m);
}

/* ---- clustering removes double-sided faces -----------------------------------------------------
 */

/* A closed, very thin box (n x n grids 0.002 apart around z = 0.1, inside one layer of 0.2 cells
 * of a grid starting at z = -1) at x in [3, 4]. */
static void add_slab(lm_mesh *m, int n)
{
    uint32_t base = m->n_wedges;
    for (int side = 0; side < 2; side++)
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                float p[3] = {3 + (float)i / (n - 1), (float)j / (n - 1), side ? 0.101f : 0.099f};
                uint32_t v;
                assert_int_equal(lm_mesh_add_vertex(m, p, &v), LM_OK);
                lm_wedge w = {
                    .vertex = v, .normal = {0, 0, side ? 1.f : -1.f}, .color = {1, 1, 1, 1}};
                assert_int_equal(lm_mesh_add_wedge(m, &w, NULL), LM_OK);
            }
    for (int side = 0; side < 2; side++)
        for (int j = 0; j + 1 < n; j++)
            for (int i = 0; i + 1 < n; i++) {
                uint32_t a = base + (uint32_t)(side * n * n + j * n + i), b = a + 1;
                uint32_t c = a + (uint32_t)n, d = c + 1;
                uint32_t t1[3] = {a, b, d}, t2[3] = {a, d, c}, t3[3] = {a, d, b}, t4[3] = {a, c, d};
                assert_int_equal(lm_mesh_add_tri(m, side ? t1 : t3, 0, NULL), LM_OK);
                assert_int_equal(lm_mesh_add_tri(m, side ? t2 : t4, 0, NULL), LM_OK);
            }
    /* the four thin sides */
    for (int e = 0; e < 4; e++)
        for (int k = 0; k + 1 < n; k++) {
            int i0 = e == 0 ? k : e == 1 ? n - 1 : e == 2 ? n - 1 - k : 0;
            int j0 = e == 0 ? 0 : e == 1 ? k : e == 2 ? n - 1 : n - 1 - k;
            int i1 = e == 0 ? k + 1 : e == 1 ? n - 1 : e == 2 ? n - 2 - k : 0;
            int j1 = e == 0 ? 0 : e == 1 ? k + 1 : e == 2 ? n - 1 : n - 2 - k;
            uint32_t a = base + (uint32_t)(j0 * n + i0), b = base + (uint32_t)(j1 * n + i1);
            uint32_t c = a + (uint32_t)(n * n), d = b + (uint32_t)(n * n);
            uint32_t t1[3] = {a, b, d}, t2[3] = {a, d, c};
            assert_int_equal(lm_mesh_add_tri(m, t1, 0, NULL), LM_OK);
            assert_int_equal(lm_mesh_add_tri(m, t2, 0, NULL), LM_OK);
        }
}

static void test_cluster_double_sided(void **state)
{
    (void)state;
    lm_mesh *sphere = lmt_make_sphere(4), *both = lmt_make_sphere(4), *out = NULL;
    add_slab(both, 21);
    assert_int_equal(lm_mesh_validate(both), LM_OK);
    assert_int_equal(lm_mesh_build_adjacency(both), LM_OK);
    co_simplify_stats st;
    /* Control: the sphere alone, cells of 0.2, has nothing double-sided. */
    assert_int_equal(co_simplify_cluster_grid(sphere, 0.2, &st, &out), LM_OK);
    assert_int_equal(st.double_sided_removed, 0);
    uint32_t sphere_tris = out->live_tris;
    lm_mesh_destroy(out);
    /* With the slab: its top and bottom land in the same cells with opposite orientations, so
     * every one of its triangles is dropped (double-sided or degenerate) and only the sphere's
     * triangles remain. */
    assert_int_equal(co_simplify_cluster_grid(both, 0.2, &st, &out), LM_OK);
    print_message("double-sided removed: %u, duplicates %u, degenerate %u\n",
                  st.double_sided_removed, st.duplicates_removed, st.degenerate_removed);
    assert_true(st.double_sided_removed >= 2 * 25);
    assert_int_equal(st.double_sided_removed % 2, 0);
    check_output(out);
    for (uint32_t v = 0; v < out->n_verts; v++)
        assert_true(out->pos[v][0] < 2.0f); /* nothing of the slab is left */
    assert_int_equal(out->live_tris, sphere_tris);
    lm_mesh_destroy(out);
    lm_mesh_destroy(sphere);
    lm_mesh_destroy(both);
}

/* Clustering merges wedges per (cell, material): one material -> one wedge per vertex. */
static void test_cluster_frog_wedges(void **state)
{
    (void)state;
    lm_mesh *frog = NULL, *out = NULL;
    assert_int_equal(co_frog_generate(20000, 3, &frog), LM_OK);
    co_simplify_stats st;
    assert_int_equal(co_simplify_cluster(frog, 800, &st, &out), LM_OK);
    check_output(out);
    print_message("frog cluster: %u verts, %u tris, %u passes, cell %.4f, double-sided %u\n",
                  out->live_verts, out->live_tris, st.passes, st.cell_size,
                  st.double_sided_removed);
    assert_int_equal(live_wedges(out), out->live_verts);
    lm_mesh_destroy(out);
    lm_mesh_destroy(frog);
}

/* ---- unreachable targets ------------------------------------------------------------------------
 */

static void test_unreachable(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2), *out = NULL;
    /* The target is an upper bound: a model below it is the answer as it is. */
    assert_int_equal(co_simplify(m, CO_SIMPLIFY_QEM, m->live_verts * 2, &out), LM_OK);
    assert_non_null(out);
    assert_int_equal(out->live_verts, m->live_verts);
    assert_int_equal(out->live_tris, m->live_tris);
    lm_mesh_destroy(out);
    for (int method = 0; method < 2; method++) {
        assert_int_equal(co_simplify(m, (co_simplify_method)method, 2, &out), LM_E_RANGE);
        assert_non_null(out);
        check_output(out);
        lm_mesh_destroy(out);
    }
    assert_int_equal(co_simplify(m, CO_SIMPLIFY_QEM, m->live_verts, &out), LM_OK);
    lm_mesh_destroy(out);
    lm_mesh_destroy(m);
}

/* ---- the frog
 * ------------------------------------------------------------------------------------ */

static void check_frog(uint32_t tris)
{
    lm_mesh *m = NULL;
    assert_int_equal(co_frog_generate(tris, 7, &m), LM_OK);
    print_message("frog %u: %u tris, %u verts\n", tris, m->live_tris, m->live_verts);
    assert_true(fabs((double)m->live_tris - tris) <= 0.02 * tris);
    assert_int_equal(lm_mesh_validate(m), LM_OK);
    assert_int_equal(lm_mesh_count_components(m), CO_FROG_PARTS);
    /* closed parts: every vertex has a full fan, Euler characteristic 2 per sphere-like part */
    assert_int_equal(lm_mesh_euler_characteristic(m), 2 * CO_FROG_PARTS);
    assert_true(live_wedges(m) > m->live_verts); /* UV seams */
    assert_true((m->attrs & (LM_ATTR_UV | LM_ATTR_NORMAL)) == (LM_ATTR_UV | LM_ATTR_NORMAL));
    lm_mesh_destroy(m);
}

static void test_frog_sizes(void **state)
{
    (void)state;
    check_frog(2000);
    check_frog(5000);
    check_frog(200000);
    lm_mesh *m = NULL;
    assert_int_equal(co_frog_generate(10, 1, &m), LM_E_RANGE);
    assert_null(m);
}

/* Outward orientation: the signed volume of every part is positive. */
static void test_frog_orientation(void **state)
{
    (void)state;
    lm_mesh *m = NULL;
    assert_int_equal(co_frog_generate(5000, 1, &m), LM_OK);
    double vol = 0;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        const float *a = m->pos[lm_tri_vertex(m, t, 0)], *b = m->pos[lm_tri_vertex(m, t, 1)];
        const float *c = m->pos[lm_tri_vertex(m, t, 2)];
        vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                a[2] * (b[0] * c[1] - b[1] * c[0])) /
               6.0;
    }
    print_message("frog volume %.4f\n", vol);
    assert_true(vol > 0.3);
    lm_mesh_destroy(m);
}

static void test_frog_determinism(void **state)
{
    (void)state;
    lm_mesh *a = NULL, *b = NULL, *c = NULL;
    assert_int_equal(co_frog_generate(5000, 11, &a), LM_OK);
    assert_int_equal(co_frog_generate(5000, 11, &b), LM_OK);
    assert_int_equal(co_frog_generate(5000, 12, &c), LM_OK);
    assert_true(lm_mesh_hash(a) == lm_mesh_hash(b));
    assert_true(lm_mesh_hash(a) != lm_mesh_hash(c));
    const lm_image *ta = a->materials[0].texture, *tb = b->materials[0].texture;
    const lm_image *tc = c->materials[0].texture;
    size_t bytes = (size_t)ta->width * ta->height * 4;
    assert_memory_equal(ta->pixels, tb->pixels, bytes);
    assert_true(memcmp(ta->pixels, tc->pixels, bytes) != 0);
    lm_mesh_destroy(a);
    lm_mesh_destroy(b);
    lm_mesh_destroy(c);
}

static int has_colour(const lm_image *img, uint8_t r, uint8_t g, uint8_t b)
{
    for (size_t i = 0; i < (size_t)img->width * img->height; i++)
        if (img->pixels[4 * i] == r && img->pixels[4 * i + 1] == g && img->pixels[4 * i + 2] == b)
            return 1;
    return 0;
}

static void test_frog_texture(void **state)
{
    (void)state;
    lm_mesh *m = NULL;
    assert_int_equal(co_frog_generate(3000, 5, &m), LM_OK);
    assert_int_equal(m->n_materials, 1);
    const lm_image *tex = m->materials[0].texture;
    assert_non_null(tex);
    assert_int_equal(tex->width, CO_FROG_TEXTURE_SIZE);
    assert_int_equal(tex->height, CO_FROG_TEXTURE_SIZE);
    assert_string_equal(m->materials[0].texture_path, "frog_skin.png");
    assert_true(has_colour(tex, 8, 8, 10));     /* pupil */
    assert_true(has_colour(tex, 228, 186, 34)); /* iris */
    assert_true(has_colour(tex, 30, 62, 26));   /* spots */
    assert_true(has_colour(tex, 38, 74, 30));   /* leg stripes */
    /* Eye wedges map into the eye chart; the end pole (pupil) into the black area. */
    uint32_t pupil = 0;
    for (uint32_t w = 0; w < m->n_wedges; w++) {
        const float *uv = m->wedges[w].uv;
        assert_true(uv[0] > 0 && uv[0] < 1 && uv[1] > 0 && uv[1] < 1);
        if (uv[0] > 0.5f && uv[1] > 0.99f)
            pupil++;
    }
    assert_true(pupil > 0);
    lm_mesh_destroy(m);
}

/* The frog survives a GLB round trip: parts, triangles, UV seams and its texture. */
static void test_frog_roundtrip(void **state)
{
    (void)state;
    lm_mesh *m = NULL, *back = NULL;
    assert_int_equal(co_frog_generate(5000, 2, &m), LM_OK);
    char *dir = lmt_mkdtemp(), path[1100];
    snprintf(path, sizeof path, "%s/frog.glb", dir);
    if (lm_mesh_save(path, m))
        fail_msg("save %s: %s", path, lm_last_error());
    if (lm_mesh_load(path, NULL, &back))
        fail_msg("load %s: %s", path, lm_last_error());
    assert_int_equal(back->live_tris, m->live_tris);
    assert_int_equal(back->live_verts, m->live_verts);
    assert_int_equal(lm_mesh_count_components(back), CO_FROG_PARTS);
    assert_true(live_wedges(back) > back->live_verts);
    assert_true(back->n_materials >= 1);
    assert_non_null(back->materials[0].texture);
    assert_int_equal(back->materials[0].texture->width, CO_FROG_TEXTURE_SIZE);
    lm_mesh_destroy(back);
    lm_mesh_destroy(m);
    lmt_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frog_sizes),
        cmocka_unit_test(test_frog_orientation),
        cmocka_unit_test(test_frog_determinism),
        cmocka_unit_test(test_frog_texture),
        cmocka_unit_test(test_frog_roundtrip),
        cmocka_unit_test(test_qem_frog_seams),
        cmocka_unit_test(test_qem_material_boundary),
        cmocka_unit_test(test_cluster_double_sided),
        cmocka_unit_test(test_cluster_frog_wedges),
        cmocka_unit_test(test_unreachable),
        cmocka_unit_test(test_qem_bunny),
        cmocka_unit_test(test_cluster_bunny),
        cmocka_unit_test(test_qem_spider_components),
        cmocka_unit_test(test_spider_keeps_parts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
