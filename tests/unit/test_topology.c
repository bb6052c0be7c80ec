/* tests/unit/test_topology.c — adjacency queries, legal edge operations (collapse / split / swap),
 * wedges across seams, wedge merging and exact undo through the journal. */
#include "test_support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh_topology.h"

/* ---- helpers ----------------------------------------------------------------------------------
 */

static uint64_t rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* One wedge per vertex (uv = xy), material 0; adjacency built. */
static lm_mesh *build_mesh(const float (*pos)[3], uint32_t nv, const uint32_t (*tri)[3],
                           uint32_t nt)
{
    lm_mesh *m;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "m0", NULL, NULL, NULL, NULL), LM_OK);
    for (uint32_t i = 0; i < nv; i++) {
        uint32_t v, w;
        assert_int_equal(lm_mesh_add_vertex(m, pos[i], &v), LM_OK);
        lm_wedge x = {
            .vertex = v, .normal = {0, 0, 1}, .uv = {pos[i][0], pos[i][1]}, .color = {1, 1, 1, 1}};
        assert_int_equal(lm_mesh_add_wedge(m, &x, &w), LM_OK);
        assert_int_equal(w, v);
    }
    for (uint32_t i = 0; i < nt; i++)
        assert_int_equal(lm_mesh_add_tri(m, tri[i], 0, NULL), LM_OK);
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    return m;
}

static lm_mesh *make_tetra(void)
{
    static const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    static const uint32_t t[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    return build_mesh(p, 4, t, 4);
}

/* Triangular bipyramid: base x=0, y=1, z=2, apexes n=3 (up), s=4 (down). */
static lm_mesh *make_bipyramid(void)
{
    static const float p[5][3] = {
        {1, 0, 0}, {-0.5f, 0.87f, 0}, {-0.5f, -0.87f, 0}, {0, 0, 1}, {0, 0, -1}};
    static const uint32_t t[6][3] = {{3, 0, 1}, {3, 1, 2}, {3, 2, 0},
                                     {4, 1, 0}, {4, 2, 1}, {4, 0, 2}};
    return build_mesh(p, 5, t, 6);
}

/* Copy of another mesh's alive content appended to dst (wedges, triangles), then adjacency. */
static void append_mesh(lm_mesh *dst, const lm_mesh *src, float dx)
{
    uint32_t v0 = dst->n_verts, w0 = dst->n_wedges;
    for (uint32_t v = 0; v < src->n_verts; v++) {
        float p[3] = {src->pos[v][0] + dx, src->pos[v][1], src->pos[v][2]};
        assert_int_equal(lm_mesh_add_vertex(dst, p, NULL), LM_OK);
    }
    for (uint32_t w = 0; w < src->n_wedges; w++) {
        lm_wedge x = src->wedges[w];
        x.vertex += v0;
        assert_int_equal(lm_mesh_add_wedge(dst, &x, NULL), LM_OK);
    }
    for (uint32_t t = 0; t < src->n_tris; t++) {
        uint32_t w[3] = {src->tris[t].w[0] + w0, src->tris[t].w[1] + w0, src->tris[t].w[2] + w0};
        assert_int_equal(lm_mesh_add_tri(dst, w, 0, NULL), LM_OK);
    }
    assert_int_equal(lm_mesh_build_adjacency(dst), LM_OK);
}

typedef struct counts {
    long v, e, f;
} counts;

static counts count_elems(const lm_mesh *m)
{
    uint32_t(*e)[2];
    size_t ne;
    assert_int_equal(lm_mesh_list_edges(m, &e, &ne), LM_OK);
    free(e);
    counts c = {0, (long)ne, 0};
    for (uint32_t v = 0; v < m->n_verts; v++)
        c.v += m->vert_alive[v];
    for (uint32_t t = 0; t < m->n_tris; t++)
        c.f += m->tri_alive[t];
    assert_int_equal(c.v, m->live_verts);
    assert_int_equal(c.f, m->live_tris);
    return c;
}

/* Every vertex's adjacency list, flattened (for exact before/after comparisons). */
typedef struct adj_snap {
    uint32_t nv;
    uint32_t *start; /* [nv + 1] */
    uint32_t *ids;
} adj_snap;

static adj_snap snap_adjacency(const lm_mesh *m)
{
    adj_snap s = {.nv = m->n_verts};
    s.start = malloc(((size_t)s.nv + 1) * sizeof *s.start);
    size_t total = 0;
    for (uint32_t v = 0; v < s.nv; v++)
        total += lm_mesh_vertex_tris(m, v, NULL, 0);
    s.ids = malloc((total + 1) * sizeof *s.ids);
    uint32_t at = 0;
    for (uint32_t v = 0; v < s.nv; v++) {
        s.start[v] = at;
        at += lm_mesh_vertex_tris(m, v, s.ids + at, (uint32_t)(total - at));
    }
    s.start[s.nv] = at;
    return s;
}

static int snap_equal(const adj_snap *a, const adj_snap *b)
{
    return a->nv == b->nv && memcmp(a->start, b->start, ((size_t)a->nv + 1) * 4) == 0 &&
           memcmp(a->ids, b->ids, (size_t)a->start[a->nv] * 4) == 0;
}

static void snap_free(adj_snap *s)
{
    free(s->start);
    free(s->ids);
}

/* The incrementally maintained adjacency equals one rebuilt from scratch (lm_mesh_clone
 * rebuilds), every list is ascending, and the mesh validates. */
static void check_consistent(const lm_mesh *m)
{
    lm_mesh *c;
    assert_int_equal(lm_mesh_clone(m, &c), LM_OK);
    adj_snap a = snap_adjacency(m), b = snap_adjacency(c);
    assert_true(snap_equal(&a, &b));
    for (uint32_t v = 0; v < a.nv; v++)
        for (uint32_t i = a.start[v] + 1; i < a.start[v + 1]; i++)
            assert_true(a.ids[i - 1] < a.ids[i]);
    snap_free(&a);
    snap_free(&b);
    lm_mesh_destroy(c);
    assert_int_equal(lm_mesh_validate(m), LM_OK);
}

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

/* Each directed edge is used by at most one triangle (consistent orientation, no duplicates). */
static void check_oriented(const lm_mesh *m)
{
    uint64_t *k = malloc(((size_t)m->n_tris * 3 + 1) * sizeof *k);
    size_t n = 0;
    for (uint32_t t = 0; t < m->n_tris; t++)
        for (int c = 0; c < 3 && m->tri_alive[t]; c++)
            k[n++] = (uint64_t)lm_tri_vertex(m, t, c) << 32 | lm_tri_vertex(m, t, (c + 1) % 3);
    qsort(k, n, sizeof *k, cmp_u64);
    for (size_t i = 1; i < n; i++)
        assert_true(k[i] != k[i - 1]);
    free(k);
}

/* Content hash plus the live counters (which lm_mesh_hash does not cover). */
static uint64_t state_hash(const lm_mesh *m)
{
    return lm_mesh_hash(m) ^ ((uint64_t)m->live_verts << 40) ^ ((uint64_t)m->live_tris << 8);
}

/* A random edge (a, b) of an alive triangle. */
static void random_edge(const lm_mesh *m, uint64_t *rng, uint32_t *a, uint32_t *b)
{
    uint32_t t;
    do
        t = (uint32_t)(rng_next(rng) % m->n_tris);
    while (!m->tri_alive[t]);
    int k = (int)(rng_next(rng) % 3);
    *a = lm_tri_vertex(m, t, k);
    *b = lm_tri_vertex(m, t, (k + 1) % 3);
}

/* One random operation; returns its status (LM_OK or LM_E_ILLEGAL). op_out: 0 swap, 1 split,
 * 2 collapse. */
static lm_status random_op(lm_mesh *m, uint64_t *rng, lm_journal *j, int *op_out)
{
    uint32_t a, b;
    random_edge(m, rng, &a, &b);
    int op = (int)(rng_next(rng) % 3);
    if (op_out)
        *op_out = op;
    lm_status s;
    if (op == 0) {
        s = lm_mesh_swap_edge(m, a, b, j);
    } else if (op == 1) {
        s = lm_mesh_split_edge(m, a, b, NULL, j);
    } else {
        float p[3];
        for (int k = 0; k < 3; k++)
            p[k] = 0.5f * (m->pos[a][k] + m->pos[b][k]);
        s = lm_mesh_collapse_edge(m, a, b, p, j);
    }
    assert_true(s == LM_OK || s == LM_E_ILLEGAL);
    return s;
}

/* Distinct wedges used around vertex v. */
static uint32_t wedges_at(const lm_mesh *m, uint32_t v)
{
    uint32_t t[64], w[64], n = lm_mesh_vertex_tris(m, v, t, 64), nw = 0;
    assert_true(n <= 64);
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t x = m->tris[t[i]].w[k];
            if (m->wedges[x].vertex != v)
                continue;
            int dup = 0;
            for (uint32_t q = 0; q < nw; q++)
                dup |= w[q] == x;
            if (!dup)
                w[nw++] = x;
        }
    return nw;
}

/* ---- tests ---------------------------------------------------------------------------------- */

static void test_queries(void **state)
{
    (void)state;
    lm_mesh *g = lmt_make_grid(3); /* 0 1 2 / 3 4 5 / 6 7 8, diagonals 0-4, 1-5, 3-7, 4-8 */
    uint32_t nb[16], t[16];
    assert_int_equal(lm_mesh_vertex_neighbors(g, 4, nb, 16), 6);
    static const uint32_t expect4[6] = {0, 1, 3, 5, 7, 8};
    assert_memory_equal(nb, expect4, sizeof expect4);
    assert_int_equal(lm_mesh_vertex_tris(g, 4, t, 16), 6);
    assert_int_equal(lm_mesh_vertex_tris(g, 0, t, 16), 2);
    assert_true(lm_mesh_vertex_is_boundary(g, 0));
    assert_false(lm_mesh_vertex_is_boundary(g, 4));
    assert_true(lm_mesh_edge_exists(g, 0, 4));
    assert_false(lm_mesh_edge_exists(g, 2, 4));
    assert_false(lm_mesh_edge_exists(g, 0, 8));
    assert_true(lm_mesh_edge_is_boundary(g, 0, 1));
    assert_false(lm_mesh_edge_is_boundary(g, 1, 4));
    assert_true(lm_mesh_edge_is_manifold(g, 1, 4));
    assert_int_equal(lm_mesh_edge_tris(g, 4, 1, t, 16), 2);
    assert_false(lm_mesh_edge_is_attr_seam(g, 1, 4));
    uint32_t(*e)[2];
    size_t ne;
    assert_int_equal(lm_mesh_list_edges(g, &e, &ne), LM_OK);
    assert_int_equal(ne, 16); /* 12 axis edges + 4 diagonals */
    for (size_t i = 0; i < ne; i++) {
        assert_true(e[i][0] < e[i][1]);
        if (i)
            assert_true(e[i - 1][0] < e[i][0] || (e[i - 1][0] == e[i][0] && e[i - 1][1] < e[i][1]));
        assert_true(lm_mesh_edge_exists(g, e[i][0], e[i][1]));
    }
    free(e);
    assert_int_equal(lm_mesh_euler_characteristic(g), 1);
    lm_mesh_destroy(g);

    lm_mesh *s = lmt_make_sphere(3);
    assert_int_equal(lm_mesh_euler_characteristic(s), 2);
    counts c = count_elems(s);
    assert_int_equal(c.e * 2, c.f * 3);
    check_consistent(s);
    lm_mesh_destroy(s);
}

static void test_tetra_collapse_refused(void **state)
{
    (void)state;
    lm_mesh *m = make_tetra();
    uint64_t h = state_hash(m);
    lm_journal *j;
    assert_int_equal(lm_journal_create(&j), LM_OK);
    for (uint32_t a = 0; a < 4; a++)
        for (uint32_t b = 0; b < 4; b++) {
            if (a == b)
                continue;
            float p[3] = {0.25f, 0.25f, 0.25f};
            assert_int_equal(lm_mesh_collapse_edge(m, a, b, p, j), LM_E_ILLEGAL);
            assert_int_equal(lm_mesh_swap_edge(m, a, b, j), LM_E_ILLEGAL);
        }
    assert_int_equal(lm_journal_mark(j), 0);
    assert_int_equal(state_hash(m), h);
    /* A split is legal; collapsing the new vertex back into the tetrahedron is too (5 -> 4). */
    uint32_t mv;
    assert_int_equal(lm_mesh_split_edge(m, 0, 1, &mv, j), LM_OK);
    assert_int_equal(mv, 4);
    counts c = count_elems(m);
    assert_int_equal(c.v, 5);
    assert_int_equal(c.e, 9);
    assert_int_equal(c.f, 6);
    check_consistent(m);
    check_oriented(m);
    assert_int_equal(lm_mesh_collapse_edge(m, 0, mv, m->pos[0], j), LM_OK);
    c = count_elems(m);
    assert_int_equal(c.v, 4);
    assert_int_equal(c.f, 4);
    check_consistent(m);
    lm_journal_rollback(m, j, 0);
    assert_int_equal(state_hash(m), h);
    assert_int_equal(lm_mesh_collapse_edge(m, 9, 1, NULL, j), LM_E_RANGE);
    lm_journal_destroy(j);
    lm_mesh_destroy(m);
}

static void test_pinched_link_condition(void **state)
{
    (void)state;
    lm_mesh *m = make_bipyramid();
    uint64_t h = state_hash(m);
    /* Base edge 0-1: common neighbours 2, 3, 4 but only 3 and 4 are opposite -> pinch. */
    assert_int_equal(lm_mesh_collapse_edge(m, 0, 1, NULL, NULL), LM_E_ILLEGAL);
    assert_non_null(strstr(lm_last_error(), "link condition"));
    assert_int_equal(lm_mesh_collapse_edge(m, 2, 1, NULL, NULL), LM_E_ILLEGAL);
    assert_int_equal(state_hash(m), h);
    /* Apex edge 3-0: common neighbours 1, 2 = the opposite vertices; result is a tetrahedron. */
    counts c0 = count_elems(m);
    assert_int_equal(lm_mesh_collapse_edge(m, 3, 0, NULL, NULL), LM_OK);
    counts c1 = count_elems(m);
    assert_int_equal(c1.v, c0.v - 1);
    assert_int_equal(c1.e, c0.e - 3);
    assert_int_equal(c1.f, c0.f - 2);
    assert_int_equal(lm_mesh_euler_characteristic(m), 2);
    check_consistent(m);
    check_oriented(m);
    /* Now a tetrahedron: nothing collapses any more. */
    assert_int_equal(lm_mesh_collapse_edge(m, 3, 1, NULL, NULL), LM_E_ILLEGAL);
    lm_mesh_destroy(m);
}

static void test_boundary_rules(void **state)
{
    (void)state;
    lm_mesh *g = lmt_make_grid(3);
    uint64_t h = state_hash(g);
    /* 1 and 5 are boundary vertices, the diagonal 1-5 is interior. The link condition holds. */
    assert_true(lm_mesh_vertex_is_boundary(g, 1) && lm_mesh_vertex_is_boundary(g, 5));
    assert_int_equal(lm_mesh_edge_tris(g, 1, 5, NULL, 0), 2);
    assert_int_equal(lm_mesh_collapse_edge(g, 1, 5, NULL, NULL), LM_E_ILLEGAL);
    assert_non_null(strstr(lm_last_error(), "boundary"));
    assert_int_equal(lm_mesh_collapse_edge(g, 5, 1, NULL, NULL), LM_E_ILLEGAL);
    assert_int_equal(state_hash(g), h);
    /* Boundary edge 0-1: V-1, E-2, F-1. */
    counts c0 = count_elems(g);
    assert_int_equal(lm_mesh_collapse_edge(g, 1, 0, NULL, NULL), LM_OK);
    counts c1 = count_elems(g);
    assert_int_equal(c1.v, c0.v - 1);
    assert_int_equal(c1.e, c0.e - 2);
    assert_int_equal(c1.f, c0.f - 1);
    assert_int_equal(lm_mesh_euler_characteristic(g), 1);
    check_consistent(g);
    /* Interior-to-boundary edge 4-3 is legal: V-1, E-3, F-2. */
    assert_int_equal(lm_mesh_collapse_edge(g, 3, 4, g->pos[3], NULL), LM_OK);
    counts c2 = count_elems(g);
    assert_int_equal(c2.v, c1.v - 1);
    assert_int_equal(c2.e, c1.e - 3);
    assert_int_equal(c2.f, c1.f - 2);
    check_consistent(g);
    check_oriented(g);
    /* Swap of a boundary edge is refused. */
    assert_int_equal(lm_mesh_swap_edge(g, 7, 8, NULL), LM_E_ILLEGAL);
    lm_mesh_destroy(g);

    /* A lone triangle and a quad: collapses would leave fewer than 4 vertices. */
    static const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    static const uint32_t t[2][3] = {{0, 1, 2}, {0, 2, 3}};
    lm_mesh *q = build_mesh(p, 4, t, 2);
    assert_int_equal(lm_mesh_collapse_edge(q, 0, 1, NULL, NULL), LM_E_ILLEGAL);
    assert_int_equal(lm_mesh_collapse_edge(q, 0, 2, NULL, NULL), LM_E_ILLEGAL);
    assert_int_equal(lm_mesh_swap_edge(q, 0, 2, NULL), LM_OK); /* diagonal 1-3 now */
    assert_true(lm_mesh_edge_exists(q, 1, 3));
    assert_false(lm_mesh_edge_exists(q, 0, 2));
    check_oriented(q);
    check_consistent(q);
    lm_mesh_destroy(q);
}

static void test_collapse_interior_counts(void **state)
{
    (void)state;
    lm_mesh *s = lmt_make_sphere(2);
    uint64_t rng = 7;
    int done = 0;
    for (int i = 0; i < 40; i++) {
        uint32_t a, b;
        random_edge(s, &rng, &a, &b);
        counts c0 = count_elems(s);
        uint32_t ncomp = lm_mesh_count_components(s);
        float p[3] = {0.1f * (float)i, 0.5f, -0.25f};
        if (lm_mesh_collapse_edge(s, a, b, p, NULL) != LM_OK)
            continue;
        done++;
        assert_memory_equal(s->pos[a], p, sizeof p);
        counts c1 = count_elems(s);
        assert_int_equal(c1.v, c0.v - 1);
        assert_int_equal(c1.e, c0.e - 3);
        assert_int_equal(c1.f, c0.f - 2);
        assert_false(s->vert_alive[b]);
        assert_int_equal(lm_mesh_vertex_tris(s, b, NULL, 0), 0);
        assert_int_equal(lm_mesh_euler_characteristic(s), 2);
        assert_int_equal(lm_mesh_count_components(s), ncomp);
    }
    assert_true(done > 20);
    check_consistent(s);
    check_oriented(s);
    lm_mesh_destroy(s);
}

static void test_split_swap_keep_euler(void **state)
{
    (void)state;
    lm_mesh *meshes[2] = {lmt_make_sphere(2), lmt_make_grid(6)};
    for (int mi = 0; mi < 2; mi++) {
        lm_mesh *m = meshes[mi];
        long chi = lm_mesh_euler_characteristic(m);
        uint64_t rng = 11 + (uint64_t)mi;
        int swaps = 0, splits = 0;
        for (int i = 0; i < 400; i++) {
            uint32_t a, b;
            random_edge(m, &rng, &a, &b);
            counts c0 = count_elems(m);
            int boundary = lm_mesh_edge_is_boundary(m, a, b);
            if (i % 2) {
                uint32_t mv;
                assert_int_equal(lm_mesh_split_edge(m, a, b, &mv, NULL), LM_OK);
                counts c1 = count_elems(m);
                assert_int_equal(c1.v, c0.v + 1);
                assert_int_equal(c1.e, c0.e + (boundary ? 2 : 3));
                assert_int_equal(c1.f, c0.f + (boundary ? 1 : 2));
                assert_true(lm_mesh_edge_exists(m, a, mv) && lm_mesh_edge_exists(m, mv, b));
                assert_false(lm_mesh_edge_exists(m, a, b));
                splits++;
            } else if (lm_mesh_swap_edge(m, a, b, NULL) == LM_OK) {
                counts c1 = count_elems(m);
                assert_memory_equal(&c0, &c1, sizeof c0);
                assert_false(lm_mesh_edge_exists(m, a, b));
                swaps++;
            }
            assert_int_equal(lm_mesh_euler_characteristic(m), chi);
        }
        assert_true(swaps > 50 && splits == 200);
        check_consistent(m);
        check_oriented(m);
        lm_mesh_destroy(m);
    }
}

/* Random op sequences, each rolled back: hash and adjacency lists come back exactly. */
static void undo_sequences(lm_mesh *m, uint64_t seed, int sequences)
{
    lm_journal *j;
    assert_int_equal(lm_journal_create(&j), LM_OK);
    uint64_t h0 = state_hash(m);
    adj_snap s0 = snap_adjacency(m);
    uint64_t rng = seed;
    int ok = 0, ops[3] = {0};
    for (int q = 0; q < sequences; q++) {
        size_t mark = lm_journal_mark(j);
        int len = 1 + (int)(rng_next(&rng) % 8);
        uint64_t hmid = 0;
        size_t mid = 0;
        for (int i = 0; i < len; i++) {
            if (i == len / 2) {
                mid = lm_journal_mark(j);
                hmid = state_hash(m);
            }
            int op;
            if (random_op(m, &rng, j, &op) == LM_OK) {
                ok++;
                ops[op]++;
            }
        }
        if (q % 97 == 0) {
            check_consistent(m);
            check_oriented(m);
        }
        lm_journal_rollback(m, j, mid); /* nested mark first */
        assert_int_equal(state_hash(m), hmid);
        lm_journal_rollback(m, j, mark);
        assert_int_equal(state_hash(m), h0);
        if (q % 10 == 0 || q == sequences - 1) {
            adj_snap s1 = snap_adjacency(m);
            assert_true(snap_equal(&s0, &s1));
            snap_free(&s1);
        }
    }
    assert_true(ops[0] > sequences / 10 && ops[1] > sequences / 10 && ops[2] > sequences / 10);
    (void)ok;
    snap_free(&s0);
    lm_journal_destroy(j);
}

static void test_undo_random_sphere(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(3);
    undo_sequences(m, 1234, 3000);
    lm_mesh_destroy(m);
}

static void test_undo_random_grid(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_grid(12);
    undo_sequences(m, 99, 3000);
    lm_mesh_destroy(m);
}

/* Many committed operations on three components: components and Euler characteristic stay,
 * adjacency stays exact, orientation stays consistent; then the whole history is undone. */
static void test_components_preserved(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_sphere(2), *s2 = lmt_make_sphere(1), *g = lmt_make_grid(7);
    append_mesh(m, s2, 3.0f);
    append_mesh(m, g, -3.0f);
    lm_mesh_destroy(s2);
    lm_mesh_destroy(g);
    assert_int_equal(lm_mesh_count_components(m), 3);
    long chi = lm_mesh_euler_characteristic(m); /* 2 + 2 + 1 */
    assert_int_equal(chi, 5);
    uint64_t h0 = state_hash(m);
    lm_journal *j;
    assert_int_equal(lm_journal_create(&j), LM_OK);
    uint64_t rng = 5;
    int ok = 0;
    for (int i = 0; i < 4000; i++) {
        if (random_op(m, &rng, j, NULL) != LM_OK)
            continue;
        ok++;
        if (ok % 50 == 0) {
            assert_int_equal(lm_mesh_count_components(m), 3);
            assert_int_equal(lm_mesh_euler_characteristic(m), chi);
        }
        if (ok % 400 == 0) {
            check_consistent(m);
            check_oriented(m);
        }
    }
    assert_true(ok > 1000);
    assert_int_equal(lm_mesh_count_components(m), 3);
    check_consistent(m);
    lm_journal_rollback(m, j, 0);
    assert_int_equal(state_hash(m), h0);
    check_consistent(m);
    lm_journal_destroy(j);
    lm_mesh_destroy(m);
}

/* A 4x4 grid whose column x = 1 is a UV seam: vertices there have a left and a right wedge. */
static lm_mesh *make_seam_grid(void)
{
    lm_mesh *m = lmt_make_grid(4);
    uint32_t right[4];
    for (uint32_t y = 0; y < 4; y++) {
        lm_wedge w = m->wedges[y * 4 + 1];
        w.uv[0] += 10.0f;
        assert_int_equal(lm_mesh_add_wedge(m, &w, &right[y]), LM_OK);
    }
    for (uint32_t t = 0; t < m->n_tris; t++) {
        float cx = 0;
        for (int k = 0; k < 3; k++)
            cx += m->pos[lm_tri_vertex(m, t, k)][0];
        if (cx / 3 < 1.0f / 3.0f)
            continue; /* left of the seam column */
        for (int k = 0; k < 3; k++) {
            uint32_t v = lm_tri_vertex(m, t, k);
            if (v % 4 == 1)
                m->tris[t].w[k] = right[v / 4];
        }
    }
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    return m;
}

static void test_seams(void **state)
{
    (void)state;
    lm_mesh *m = make_seam_grid();
    assert_int_equal(lm_mesh_validate(m), LM_OK);
    assert_true(lm_mesh_edge_is_attr_seam(m, 5, 9));
    assert_false(lm_mesh_edge_is_attr_seam(m, 5, 6));
    assert_int_equal(wedges_at(m, 5), 2);
    /* Diagonal 5-10 is not a seam (5's right wedge on both sides); 1-5 and 4-5 are. */
    uint64_t h = state_hash(m);
    assert_int_equal(lm_mesh_swap_edge(m, 5, 9, NULL), LM_E_ILLEGAL);
    assert_non_null(strstr(lm_last_error(), "seam"));
    assert_int_equal(state_hash(m), h);

    lm_journal *j;
    assert_int_equal(lm_journal_create(&j), LM_OK);
    /* Split on the seam: two wedges for the midpoint; off the seam: one. */
    uint32_t mv;
    assert_int_equal(lm_mesh_split_edge(m, 5, 9, &mv, j), LM_OK);
    assert_int_equal(wedges_at(m, mv), 2);
    assert_true(lm_mesh_edge_is_attr_seam(m, 5, mv) && lm_mesh_edge_is_attr_seam(m, mv, 9));
    check_consistent(m);
    lm_journal_rollback(m, j, 0);
    assert_int_equal(state_hash(m), h);
    assert_int_equal(lm_mesh_split_edge(m, 5, 6, &mv, j), LM_OK);
    assert_int_equal(wedges_at(m, mv), 1);
    lm_journal_rollback(m, j, 0);

    /* Collapse along the seam 9 -> 5: 5 keeps two wedges (means of the merged pairs). */
    lm_wedge l5 = m->wedges[5], l9 = m->wedges[9];
    assert_int_equal(lm_mesh_collapse_edge(m, 5, 9, NULL, j), LM_OK);
    assert_int_equal(wedges_at(m, 5), 2);
    assert_true(lm_mesh_edge_is_attr_seam(m, 5, 13) && lm_mesh_edge_is_attr_seam(m, 1, 5));
    assert_true(m->wedges[5].uv[1] == 0.5f * (l5.uv[1] + l9.uv[1]));
    assert_false(m->wedge_alive[9]);
    for (uint32_t w = 0; w < m->n_wedges; w++)
        if (m->wedge_alive[w])
            assert_int_not_equal(m->wedges[w].vertex, 9);
    check_consistent(m);
    check_oriented(m);
    lm_journal_rollback(m, j, 0);
    assert_int_equal(state_hash(m), h);

    /* Collapse of seam vertex 5 into off-seam vertex 6: the seam moves to 6 (two wedges). */
    assert_int_equal(lm_mesh_collapse_edge(m, 6, 5, NULL, j), LM_OK);
    assert_int_equal(wedges_at(m, 6), 2);
    check_consistent(m);
    lm_journal_rollback(m, j, 0);
    /* Different materials also block a swap. */
    assert_int_equal(lm_mesh_add_material(m, "m1", NULL, NULL, NULL, NULL), LM_OK);
    uint32_t t[2];
    assert_int_equal(lm_mesh_edge_tris(m, 6, 11, t, 2), 2);
    assert_int_equal(lm_mesh_swap_edge(m, 6, 11, j), LM_OK);
    lm_journal_rollback(m, j, 0);
    m->tris[t[0]].material = 1;
    assert_int_equal(lm_mesh_swap_edge(m, 6, 11, j), LM_E_ILLEGAL);
    assert_non_null(strstr(lm_last_error(), "material"));
    lm_journal_destroy(j);
    lm_mesh_destroy(m);
}

static void test_merge_wedges(void **state)
{
    (void)state;
    /* Unindexed grid: every corner its own wedge; normals differ per triangle. */
    lm_mesh *g = lmt_make_grid(5), *m;
    assert_int_equal(lm_mesh_create(&m), LM_OK);
    assert_int_equal(lm_mesh_add_material(m, "m0", NULL, NULL, NULL, NULL), LM_OK);
    for (uint32_t v = 0; v < g->n_verts; v++)
        assert_int_equal(lm_mesh_add_vertex(m, g->pos[v], NULL), LM_OK);
    for (uint32_t t = 0; t < g->n_tris; t++) {
        uint32_t w[3];
        for (int k = 0; k < 3; k++) {
            lm_wedge x = g->wedges[g->tris[t].w[k]];
            x.normal[0] = (float)t;
            if (x.vertex == 12 && k == 0)
                x.uv[0] += 1.0f; /* one real seam corner on vertex 12 */
            assert_int_equal(lm_mesh_add_wedge(m, &x, &w[k]), LM_OK);
        }
        assert_int_equal(lm_mesh_add_tri(m, w, 0, NULL), LM_OK);
    }
    assert_int_equal(lm_mesh_build_adjacency(m), LM_OK);
    uint32_t corners = m->n_wedges;
    assert_int_equal(lm_mesh_merge_wedges(m, LM_ATTR_UV | LM_ATTR_COLOR | LM_ATTR_NORMAL), 0);
    uint32_t merged = lm_mesh_merge_wedges(m, LM_ATTR_UV | LM_ATTR_COLOR);
    uint32_t seam_corners = 0;
    for (uint32_t t = 0; t < g->n_tris; t++)
        seam_corners += lm_tri_vertex(g, t, 0) == 12;
    assert_true(seam_corners > 0);
    uint32_t expect_live = g->n_verts + 1; /* vertex 12 keeps a second wedge */
    assert_int_equal(merged, corners - expect_live);
    uint32_t live = 0;
    for (uint32_t w = 0; w < m->n_wedges; w++)
        live += m->wedge_alive[w];
    assert_int_equal(live, expect_live);
    for (uint32_t v = 0; v < m->n_verts; v++)
        assert_int_equal(wedges_at(m, v), v == 12 ? 2 : 1);
    assert_int_equal(lm_mesh_validate(m), LM_OK);
    check_consistent(m);
    assert_int_equal(lm_mesh_merge_wedges(m, LM_ATTR_UV | LM_ATTR_COLOR), 0);
    /* With only the seam left, swaps off the seam now work. */
    assert_int_equal(lm_mesh_swap_edge(m, 0, 6, NULL), LM_OK);
    lm_mesh_destroy(m);
    lm_mesh_destroy(g);
}

/* A tetrahedron with an extra triangle hanging on vertex 0 (a pinched vertex): collapsing 1 into 0
 * passes the link condition and keeps 5 vertices, but face (1,2,3) would become (0,2,3), a
 * duplicate of the face (0,3,2) that is already there. */
static void test_duplicate_refused(void **state)
{
    (void)state;
    static const float p[6][3] = {{0, 0, 0}, {1, 0, 0},  {0, 1, 0},
                                  {0, 0, 1}, {-1, 0, 0}, {-1, -1, 0}};
    static const uint32_t t[5][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}, {0, 4, 5}};
    lm_mesh *m = build_mesh(p, 6, t, 5);
    uint64_t h = state_hash(m);
    assert_int_equal(lm_mesh_collapse_edge(m, 0, 1, NULL, NULL), LM_E_ILLEGAL);
    assert_non_null(strstr(lm_last_error(), "duplicate"));
    assert_int_equal(state_hash(m), h);
    lm_mesh_destroy(m);
}

/* A triangle hanging on two far corners of a grid: collapsing its base would leave its third
 * vertex without triangles. */
static void test_orphan_refused(void **state)
{
    (void)state;
    lm_mesh *m = lmt_make_grid(4);
    float e[3] = {2, 2, 1};
    uint32_t v, w, tri[3] = {0, 15, 0};
    assert_int_equal(lm_mesh_add_vertex(m, e, &v), LM_OK);
    lm_wedge x = {.vertex = v, .color = {1, 1, 1, 1}};
    assert_int_equal(lm_mesh_add_wedge(m, &x, &w), LM_OK);
    tri[2] = w;
    assert_int_equal(lm_mesh_add_tri(m, tri, 0, NULL), LM_OK);
    check_consistent(m);
    uint64_t h = state_hash(m);
    assert_int_equal(lm_mesh_collapse_edge(m, 0, 15, NULL, NULL), LM_E_ILLEGAL);
    assert_non_null(strstr(lm_last_error(), "without triangles"));
    assert_int_equal(state_hash(m), h);
    lm_mesh_destroy(m);
}

/* Two triangles on an edge running the same way (inconsistent orientation): no swap. */
static void test_swap_orientation(void **state)
{
    (void)state;
    static const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0}};
    static const uint32_t bad[2][3] = {{0, 1, 2}, {0, 1, 3}}, good[2][3] = {{0, 1, 2}, {1, 0, 3}};
    lm_mesh *m = build_mesh(p, 4, bad, 2);
    assert_int_equal(lm_mesh_swap_edge(m, 0, 1, NULL), LM_E_ILLEGAL);
    assert_non_null(strstr(lm_last_error(), "orient"));
    lm_mesh_destroy(m);
    m = build_mesh(p, 4, good, 2);
    assert_int_equal(lm_mesh_swap_edge(m, 1, 0, NULL), LM_OK);
    check_oriented(m);
    /* Both new triangles face +z like the old ones. */
    for (uint32_t t = 0; t < 2; t++) {
        const float *a = m->pos[lm_tri_vertex(m, t, 0)], *b = m->pos[lm_tri_vertex(m, t, 1)],
                    *c = m->pos[lm_tri_vertex(m, t, 2)];
        float z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert_true(z > 0);
    }
    lm_mesh_destroy(m);
}

static void test_absurd_valence(void **state)
{
    (void)state;
    /* A fan of 1100 triangles around vertex 0 (a flat disk). */
    enum { N = 1100 };
    float(*p)[3] = malloc((N + 1) * sizeof *p);
    uint32_t(*t)[3] = malloc(N * sizeof *t);
    p[0][0] = p[0][1] = p[0][2] = 0;
    for (uint32_t i = 0; i < N; i++) {
        p[i + 1][0] = cosf(6.2831853f * (float)i / N);
        p[i + 1][1] = sinf(6.2831853f * (float)i / N);
        p[i + 1][2] = 0;
        t[i][0] = 0;
        t[i][1] = i + 1;
        t[i][2] = (i + 1) % N + 1;
    }
    lm_mesh *m = build_mesh((const float(*)[3])p, N + 1, (const uint32_t(*)[3])t, N);
    assert_int_equal(lm_mesh_collapse_edge(m, 0, 1, NULL, NULL), LM_E_RANGE);
    assert_int_equal(lm_mesh_vertex_neighbors(m, 0, NULL, 0), N);
    assert_false(lm_mesh_vertex_is_boundary(m, 0));
    assert_true(lm_mesh_vertex_is_boundary(m, 1));
    free(p);
    free(t);
    lm_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_queries),
        cmocka_unit_test(test_tetra_collapse_refused),
        cmocka_unit_test(test_pinched_link_condition),
        cmocka_unit_test(test_boundary_rules),
        cmocka_unit_test(test_collapse_interior_counts),
        cmocka_unit_test(test_split_swap_keep_euler),
        cmocka_unit_test(test_undo_random_sphere),
        cmocka_unit_test(test_undo_random_grid),
        cmocka_unit_test(test_components_preserved),
        cmocka_unit_test(test_seams),
        cmocka_unit_test(test_merge_wedges),
        cmocka_unit_test(test_duplicate_refused),
        cmocka_unit_test(test_orphan_refused),
        cmocka_unit_test(test_swap_orientation),
        cmocka_unit_test(test_absurd_valence),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
