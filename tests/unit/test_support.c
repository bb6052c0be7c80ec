/* tests/unit/test_support.c — shared test helpers: data paths, temp dirs, small generated meshes.
 */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/mesh_topology.h"

#ifndef LUMESH_TEST_DATA
#define LUMESH_TEST_DATA "tests/data"
#endif

static const char *data_root(void)
{
    const char *env = getenv("LUMESH_TEST_DATA");
    return env && *env ? env : LUMESH_TEST_DATA;
}

const char *lmt_data_path(const char *rel)
{
    static _Thread_local char buf[8][1024];
    static _Thread_local int next;
    char *b = buf[next++ % 8];
    snprintf(b, sizeof buf[0], "%s/%s", data_root(), rel);
    return b;
}

static const char *existing(const char *rel)
{
    const char *p = lmt_data_path(rel);
    return access(p, R_OK) == 0 ? p : NULL;
}

const char *lmt_bunny_path(void)
{
    return existing("cache/meshes/bunny00.off");
}

const char *lmt_spider_path(void)
{
    return existing("cache/root/usr/share/assimp/models/OBJ/spider.obj");
}

char *lmt_mkdtemp(void)
{
    char *d = strdup("/tmp/lumesh-test-XXXXXX");
    assert_non_null(d);
    assert_non_null(mkdtemp(d));
    return d;
}

void lmt_rmdir(char *dir)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
    free(dir);
}

/* ---- generated meshes ---------------------------------------------------------------------- */

static uint32_t add_vertex_wedge(lm_mesh *m, float x, float y, float z, float u, float v)
{
    float p[3] = {x, y, z};
    uint32_t vid, wid;
    assert_int_equal(lm_mesh_add_vertex(m, p, &vid), LM_OK);
    lm_wedge w = {.vertex = vid, .normal = {x, y, z}, .uv = {u, v}, .color = {1, 1, 1, 1}};
    assert_int_equal(lm_mesh_add_wedge(m, &w, &wid), LM_OK);
    return wid;
}

/* Midpoint of edge (a, b) projected to the unit sphere, cached in a small hash on (min,max). */
typedef struct edge_cache {
    uint64_t *keys;
    uint32_t *vals;
    size_t cap;
} edge_cache;

static uint32_t midpoint(lm_mesh *m, edge_cache *c, uint32_t a, uint32_t b)
{
    uint64_t key = a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
    size_t h = (size_t)(key * 0x9E3779B97F4A7C15ull) % c->cap;
    while (c->keys[h] != UINT64_MAX) {
        if (c->keys[h] == key)
            return c->vals[h];
        h = (h + 1) % c->cap;
    }
    const float *pa = m->pos[m->wedges[a].vertex], *pb = m->pos[m->wedges[b].vertex];
    float p[3] = {pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2]};
    float len = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; k++)
        p[k] /= len;
    float u = 0.5f + atan2f(p[1], p[0]) / (2 * (float)M_PI), v = 0.5f + asinf(p[2]) / (float)M_PI;
    uint32_t w = add_vertex_wedge(m, p[0], p[1], p[2], u, v);
    c->keys[h] = key;
    c->vals[h] = w;
    return w;
}

lm_mesh *lmt_make_sphere(int subdivisions)
{
    lm_mesh *m;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "default", NULL, NULL, NULL, NULL), LM_OK);
    m->attrs = LM_ATTR_NORMAL | LM_ATTR_UV;
    static const float oct[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                    {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    static const uint32_t faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                         {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int i = 0; i < 6; i++)
        add_vertex_wedge(m, oct[i][0], oct[i][1], oct[i][2], 0.5f + 0.1f * (float)i, 0.5f);
    size_t nf = 8;
    uint32_t *f = malloc(nf * 3 * sizeof *f);
    memcpy(f, faces, sizeof faces);
    for (int s = 0; s < subdivisions; s++) {
        edge_cache c = {.cap = nf * 4 + 64};
        c.keys = malloc(c.cap * sizeof *c.keys);
        c.vals = malloc(c.cap * sizeof *c.vals);
        memset(c.keys, 0xff, c.cap * sizeof *c.keys);
        uint32_t *g = malloc(nf * 4 * 3 * sizeof *g);
        for (size_t i = 0; i < nf; i++) {
            uint32_t a = f[3 * i], b = f[3 * i + 1], d = f[3 * i + 2];
            uint32_t ab = midpoint(m, &c, a, b), bd = midpoint(m, &c, b, d),
                     da = midpoint(m, &c, d, a);
            uint32_t q[12] = {a, ab, da, ab, b, bd, da, bd, d, ab, bd, da};
            memcpy(g + 12 * i, q, sizeof q);
        }
        free(f);
        free(c.keys);
        free(c.vals);
        f = g;
        nf *= 4;
    }
    for (size_t i = 0; i < nf; i++)
        assert_int_equal(lm_mesh_add_tri(m, f + 3 * i, 0, NULL), LM_OK);
    free(f);
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    return m;
}

lm_mesh *lmt_make_grid(int n)
{
    lm_mesh *m;
    assert_true(n >= 2);
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "default", NULL, NULL, NULL, NULL), LM_OK);
    m->attrs = LM_ATTR_NORMAL | LM_ATTR_UV;
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            float u = (float)x / (float)(n - 1), v = (float)y / (float)(n - 1);
            uint32_t w = add_vertex_wedge(m, u, v, 0, u, v);
            m->wedges[w].normal[0] = m->wedges[w].normal[1] = 0;
            m->wedges[w].normal[2] = 1;
        }
    for (int y = 0; y + 1 < n; y++)
        for (int x = 0; x + 1 < n; x++) {
            uint32_t a = (uint32_t)(y * n + x), b = a + 1, c = a + (uint32_t)n, d = c + 1;
            uint32_t t1[3] = {a, b, d}, t2[3] = {a, d, c};
            assert_int_equal(lm_mesh_add_tri(m, t1, 0, NULL), LM_OK);
            assert_int_equal(lm_mesh_add_tri(m, t2, 0, NULL), LM_OK);
        }
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    return m;
}

double lmt_urand(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return (double)(*s >> 11) / 9007199254740992.0;
}
