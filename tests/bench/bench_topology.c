/* tests/bench/bench_topology.c — speed of the edge operations and their undo on a closed torus
 * mesh (every edge interior, valence 6): "try then roll back" (what the optimizer does when it
 * evaluates a move) and committed random operations.
 *
 * usage: bench_topology [N (torus is N x N vertices, default 256)] [OPS (default 200000)] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "common/mesh_topology.h"

static uint64_t rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static lm_mesh *make_torus(uint32_t n)
{
    lm_mesh *m;
    if (lm_mesh_create(&m) || lm_mesh_add_material(m, "m", NULL, NULL, NULL, NULL))
        return NULL;
    for (uint32_t y = 0; y < n; y++)
        for (uint32_t x = 0; x < n; x++) {
            float u = 6.2831853f * (float)x / (float)n, v = 6.2831853f * (float)y / (float)n;
            float p[3] = {(2 + cosf(v)) * cosf(u), (2 + cosf(v)) * sinf(u), sinf(v)};
            uint32_t id;
            lm_wedge w = {.normal = {0, 0, 1}, .uv = {u, v}, .color = {1, 1, 1, 1}};
            if (lm_mesh_add_vertex(m, p, &id))
                return NULL;
            w.vertex = id;
            if (lm_mesh_add_wedge(m, &w, NULL))
                return NULL;
        }
    for (uint32_t y = 0; y < n; y++)
        for (uint32_t x = 0; x < n; x++) {
            uint32_t a = y * n + x, b = y * n + (x + 1) % n, c = ((y + 1) % n) * n + x,
                     d = ((y + 1) % n) * n + (x + 1) % n;
            uint32_t t1[3] = {a, b, d}, t2[3] = {a, d, c};
            if (lm_mesh_add_tri(m, t1, 0, NULL) || lm_mesh_add_tri(m, t2, 0, NULL))
                return NULL;
        }
    return lm_mesh_build_adjacency(m) ? NULL : m;
}

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

static lm_status do_op(lm_mesh *m, int op, uint32_t a, uint32_t b, lm_journal *j)
{
    if (op == 0)
        return lm_mesh_swap_edge(m, a, b, j);
    if (op == 1)
        return lm_mesh_split_edge(m, a, b, NULL, j);
    float p[3];
    for (int k = 0; k < 3; k++)
        p[k] = 0.5f * (m->pos[a][k] + m->pos[b][k]);
    return lm_mesh_collapse_edge(m, a, b, p, j);
}

int main(int argc, char **argv)
{
    uint32_t n = argc > 1 ? (uint32_t)atoi(argv[1]) : 256;
    long ops = argc > 2 ? atol(argv[2]) : 200000;
    lm_mesh *m = make_torus(n < 4 ? 4 : n);
    lm_journal *j;
    if (!m || lm_journal_create(&j)) {
        fprintf(stderr, "bench_topology: setup failed: %s\n", lm_last_error());
        return 2;
    }
    printf("torus %u x %u: %u vertices, %u triangles\n", n, n, m->live_verts, m->live_tris);
    static const char *names[3] = {"swap", "split", "collapse"};
    uint64_t h0 = lm_mesh_hash(m);
    for (int op = 0; op < 3; op++) {
        uint64_t rng = 42;
        long ok = 0;
        double t0 = now();
        for (long i = 0; i < ops; i++) {
            uint32_t a, b;
            random_edge(m, &rng, &a, &b);
            size_t mark = lm_journal_mark(j);
            ok += do_op(m, op, a, b, j) == LM_OK;
            lm_journal_rollback(m, j, mark);
        }
        double dt = now() - t0;
        printf("%-8s + rollback: %8.0f per second (%.3f us each, %ld of %ld legal)\n", names[op],
               (double)ops / dt, 1e6 * dt / (double)ops, ok, ops);
    }
    if (lm_mesh_hash(m) != h0) {
        fprintf(stderr, "bench_topology: rollback did not restore the mesh\n");
        return 2;
    }
    uint64_t rng = 7;
    long ok = 0;
    double t0 = now();
    for (long i = 0; i < ops; i++) {
        uint32_t a, b;
        random_edge(m, &rng, &a, &b);
        ok += do_op(m, (int)(rng_next(&rng) % 3), a, b, j) == LM_OK;
        if (lm_journal_mark(j) > 100000)
            lm_journal_clear(j);
    }
    double dt = now() - t0;
    printf("committed random mix: %8.0f per second (%ld of %ld legal), now %u vertices\n",
           (double)ops / dt, ok, ops, m->live_verts);
    lm_journal_destroy(j);
    lm_mesh_destroy(m);
    return 0;
}
