/* tests/unit/test_parts.c — part names and grouping from input to every output: the frog's seven
 * named parts and the spider's 19 groups survive OBJ, PLY and GLB round trips (same names, same
 * triangles per part), assimp's made-up names are not taken as part names, an FBX read in a child
 * process keeps its node names, QEM and clustering keep parts, an edge swap never joins two parts
 * and a split keeps its triangle's part. */
#include "test_support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "coordinator/frog/frog.h"
#include "coordinator/simplify/simplify.h"

#define MAX_PARTS 64

/* Triangles per part name, sorted by name (parts with no triangle are not listed). */
typedef struct part_census {
    uint32_t n;
    char name[MAX_PARTS][LM_PART_NAME_MAX];
    uint32_t tris[MAX_PARTS];
} part_census;

static int by_name(const void *a, const void *b)
{
    return strcmp(a, b);
}

static void census(const lm_mesh *m, part_census *c)
{
    memset(c, 0, sizeof *c);
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        const char *name = lm_mesh_part_name(m, t);
        uint32_t i = 0;
        while (i < c->n && strcmp(c->name[i], name))
            i++;
        if (i == c->n) {
            assert_true(c->n < MAX_PARTS);
            snprintf(c->name[c->n++], LM_PART_NAME_MAX, "%s", name);
        }
        c->tris[i]++;
    }
    /* sort names, carrying counts along (n is small) */
    for (uint32_t i = 0; i < c->n; i++)
        for (uint32_t j = i + 1; j < c->n; j++)
            if (by_name(c->name[j], c->name[i]) < 0) {
                char tmp[LM_PART_NAME_MAX];
                memcpy(tmp, c->name[i], sizeof tmp);
                memcpy(c->name[i], c->name[j], sizeof tmp);
                memcpy(c->name[j], tmp, sizeof tmp);
                uint32_t x = c->tris[i];
                c->tris[i] = c->tris[j];
                c->tris[j] = x;
            }
}

static void assert_same_parts(const part_census *a, const part_census *b, const char *what)
{
    if (a->n != b->n)
        fail_msg("%s: %u parts, expected %u", what, b->n, a->n);
    for (uint32_t i = 0; i < a->n; i++) {
        if (strcmp(a->name[i], b->name[i]) || a->tris[i] != b->tris[i])
            fail_msg("%s: part '%s' (%u triangles), expected '%s' (%u)", what, b->name[i],
                     b->tris[i], a->name[i], a->tris[i]);
    }
}

/* Save m as each format, load it back: the same parts with the same triangles. */
static void round_trips(const lm_mesh *m, const char *stem)
{
    static const char *const exts[] = {"obj", "ply", "glb"};
    part_census before, after;
    census(m, &before);
    char *dir = lmt_mkdtemp();
    for (int i = 0; i < 3; i++) {
        char path[1200], what[64];
        snprintf(path, sizeof path, "%s/%s.%s", dir, stem, exts[i]);
        snprintf(what, sizeof what, "%s through %s", stem, exts[i]);
        assert_int_equal(lm_mesh_save(path, m), LM_OK);
        lm_mesh *back = NULL;
        if (lm_mesh_load(path, NULL, &back) != LM_OK)
            fail_msg("%s: %s", what, lm_last_error());
        census(back, &after);
        assert_same_parts(&before, &after, what);
        lm_mesh_destroy(back);
    }
    lmt_rmdir(dir);
}

static void test_frog_parts(void **state)
{
    (void)state;
    lm_mesh *m = NULL;
    assert_int_equal(co_frog_generate(3000, 2, &m), LM_OK);
    part_census c;
    census(m, &c);
    assert_int_equal(c.n, CO_FROG_PARTS);
    static const char *const names[] = {"body",           "eye_left",        "eye_right",
                                        "front_leg_left", "front_leg_right", "hind_leg_left",
                                        "hind_leg_right"};
    for (uint32_t i = 0; i < c.n; i++)
        assert_string_equal(c.name[i], names[i]);
    /* each part is one of the seven closed components */
    assert_int_equal(lm_mesh_count_components(m), CO_FROG_PARTS);
    round_trips(m, "frog");
    lm_mesh_destroy(m);
}

static void test_spider_parts(void **state)
{
    (void)state;
    const char *path = lmt_spider_path();
    if (!path)
        skip();
    lm_mesh *m = NULL;
    assert_int_equal(lm_mesh_load(path, NULL, &m), LM_OK);
    part_census c;
    census(m, &c);
    /* the 19 "g" groups of spider.obj, by their names */
    assert_int_equal(c.n, 19);
    static const char *const some[] = {"HLeib01", "OK", "Bein1Li", "Kopf2", "Auge", "Duplicate05"};
    for (size_t k = 0; k < sizeof some / sizeof some[0]; k++) {
        uint32_t i = 0;
        while (i < c.n && strcmp(c.name[i], some[k]))
            i++;
        if (i == c.n)
            fail_msg("spider: no part '%s'", some[k]);
    }
    round_trips(m, "spider");
    lm_mesh_destroy(m);
}

/* A file with nothing to name its parts: one unnamed part, and no made-up name ("<OFFRoot>",
 * "defaultobject", "nodes[0]") taken for one. */
static void test_unnamed(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    static const char *const files[][2] = {
        {"t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
    };
    for (int i = 0; i < 2; i++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/%s", dir, files[i][0]);
        FILE *fp = fopen(path, "w");
        assert_non_null(fp);
        fputs(files[i][1], fp);
        fclose(fp);
        lm_mesh *m = NULL;
        assert_int_equal(lm_mesh_load(path, NULL, &m), LM_OK);
        assert_string_equal(lm_mesh_part_name(m, 0), "");
        snprintf(path, sizeof path, "%s/u%d.glb", dir, i);
        assert_int_equal(lm_mesh_save(path, m), LM_OK);
        lm_mesh_destroy(m);
        assert_int_equal(lm_mesh_load(path, NULL, &m), LM_OK); /* the glb's node has no name */
        assert_string_equal(lm_mesh_part_name(m, 0), "");
        lm_mesh_destroy(m);
    }
    lmt_rmdir(dir);
}

/* A PLY's part runs are used only when they cover its faces in order; others (a foreign file, a
 * hostile count) leave the model one unnamed part. */
static void test_ply_runs(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    static const char *const second[] = {"1 1 second", "1 18446744073709551615 second",
                                         "2 1 second"};
    for (int i = 0; i < 3; i++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/r%d.ply", dir, i);
        FILE *fp = fopen(path, "w");
        assert_non_null(fp);
        fprintf(fp,
                "ply\nformat ascii 1.0\ncomment lumesh part 0 1 first\ncomment lumesh part %s\n"
                "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
                "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n",
                second[i]);
        fclose(fp);
        lm_mesh *m = NULL;
        assert_int_equal(lm_mesh_load(path, NULL, &m), LM_OK);
        assert_string_equal(lm_mesh_part_name(m, 0), i == 0 ? "first" : "");
        assert_string_equal(lm_mesh_part_name(m, 1), i == 0 ? "second" : "");
        lm_mesh_destroy(m);
    }
    lmt_rmdir(dir);
}

/* FBX is read in a child process that hands the model back as GLB: node names survive, and two
 * nodes of one name (the cube "Куб1" under both parents) are one part. */
static void test_fbx_names(void **state)
{
    (void)state;
    const char *path = lmt_data_path("cache/root/usr/share/assimp/models/FBX/cubes_with_names.fbx");
    lm_mesh *m = NULL;
    if (lm_mesh_load(path, NULL, &m) != LM_OK)
        skip();
    part_census c;
    census(m, &c);
    assert_int_equal(c.n, 3);
    assert_string_equal(c.name[0], "Cube2");
    assert_string_equal(c.name[1], "Cube3");
    assert_string_equal(c.name[2], "Куб1");
    lm_mesh_destroy(m);
}

/* Both simplifiers keep every triangle in a part of the input (QEM keeps all seven). */
static void test_simplified_parts(void **state)
{
    (void)state;
    lm_mesh *frog = NULL, *out = NULL;
    assert_int_equal(co_frog_generate(6000, 3, &frog), LM_OK);
    part_census in, c;
    census(frog, &in);
    for (int method = 0; method < 2; method++) {
        lm_status s = co_simplify(frog, (co_simplify_method)method, 400, &out);
        assert_true(s == LM_OK || s == LM_E_RANGE);
        census(out, &c);
        for (uint32_t i = 0; i < c.n; i++) {
            uint32_t j = 0;
            while (j < in.n && strcmp(in.name[j], c.name[i]))
                j++;
            if (j == in.n)
                fail_msg("method %d: part '%s' is not the frog's", method, c.name[i]);
        }
        if (method == CO_SIMPLIFY_QEM)
            assert_int_equal(c.n, CO_FROG_PARTS);
        else
            assert_true(c.n >= 2);
        lm_mesh_destroy(out);
    }
    lm_mesh_destroy(frog);
}

/* Two triangles on one edge with shared corners, parts p0 and p1: the quad (0,0)-(1,0)-(1,1)-(0,1)
 * split along (0,0)-(1,1). */
static lm_mesh *two_part_quad(uint32_t p1)
{
    lm_mesh *m = NULL;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    static const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (int i = 0; i < 4; i++) {
        lm_wedge w = {.vertex = (uint32_t)i, .normal = {0, 0, 1}, .color = {1, 1, 1, 1}};
        assert_int_equal(lm_mesh_add_vertex(m, p[i], NULL), LM_OK);
        assert_int_equal(lm_mesh_add_wedge(m, &w, NULL), LM_OK);
    }
    uint32_t a, b, t0, t1;
    assert_int_equal(lm_mesh_add_part(m, "left", &a), LM_OK);
    assert_int_equal(lm_mesh_add_part(m, "right", &b), LM_OK);
    assert_int_equal(lm_mesh_find_part(m, "right"), b);
    assert_int_equal(lm_mesh_find_part(m, "nowhere"), LM_NONE);
    assert_int_equal(lm_mesh_add_tri(m, (uint32_t[3]){0, 1, 2}, 0, &t0), LM_OK);
    assert_int_equal(lm_mesh_add_tri(m, (uint32_t[3]){0, 2, 3}, 0, &t1), LM_OK);
    m->tris[t0].part = a;
    m->tris[t1].part = p1 ? b : a;
    assert_int_equal(lm_mesh_validate(m), LM_OK);
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    return m;
}

static void test_topology_keeps_parts(void **state)
{
    (void)state;
    lm_mesh *m = two_part_quad(1);
    assert_int_equal(lm_mesh_swap_edge(m, 0, 2, NULL), LM_E_ILLEGAL);
    assert_non_null(strstr(lm_last_error(), "different parts"));
    uint32_t v;
    assert_int_equal(lm_mesh_split_edge(m, 0, 2, &v, NULL), LM_OK);
    part_census c;
    census(m, &c);
    assert_int_equal(c.n, 2);
    assert_int_equal(c.tris[0], 2); /* "left": its triangle and the new half */
    assert_int_equal(c.tris[1], 2);
    lm_mesh_destroy(m);
    m = two_part_quad(0);
    assert_int_equal(lm_mesh_swap_edge(m, 0, 2, NULL), LM_OK);
    lm_mesh_destroy(m);
    /* a triangle naming a part the mesh does not have is refused */
    m = two_part_quad(0);
    m->tris[0].part = 7;
    assert_int_equal(lm_mesh_validate(m), LM_E_RANGE);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frog_parts),
        cmocka_unit_test(test_spider_parts),
        cmocka_unit_test(test_unnamed),
        cmocka_unit_test(test_ply_runs),
        cmocka_unit_test(test_fbx_names),
        cmocka_unit_test(test_simplified_parts),
        cmocka_unit_test(test_topology_keeps_parts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
