/* tests/bench/bench_bvh.c — speed of closest-point queries (lm_bvh_closest_sq) as the optimizer's
 * geometric term asks them: the original's hierarchy, queried at the three edge midpoints and the
 * centroid of every triangle of its QEM simplification to 1%, each also moved a little (as a
 * vertex being tried elsewhere moves them). Prints queries per second, microseconds a query, the
 * hierarchy's build time and a checksum of the distances (the same on every build: a change to the
 * traversal must leave it alone).
 *
 * usage: bench_bvh [MODEL (default tests/data/cache/meshes/bunny00.off)] [ROUNDS (default 20)] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "common/bvh.h"
#include "common/io/mesh_io.h"
#include "common/optimizer/rng.h"
#include "coordinator/simplify/simplify.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The points of coarse triangle t (edge midpoints, centroid) into q[4][3]. */
static void tri_points(const lm_mesh *m, uint32_t t, double q[4][3])
{
    double c[3][3];
    for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++)
            c[v][k] = m->pos[lm_tri_vertex(m, t, v)][k];
    for (int e = 0; e < 3; e++)
        for (int k = 0; k < 3; k++)
            q[e][k] = 0.5 * (c[e][k] + c[(e + 1) % 3][k]);
    for (int k = 0; k < 3; k++)
        q[3][k] = (c[0][k] + c[1][k] + c[2][k]) / 3.0;
}

/* Every live triangle's points, then each moved by up to `jitter` along every axis. */
static double *make_queries(const lm_mesh *m, double jitter, size_t *n)
{
    double *q = malloc((size_t)m->n_tris * 8 * 3 * sizeof *q);
    lm_rng rng;
    lm_rng_seed(&rng, 1);
    *n = 0;
    for (uint32_t t = 0; q && t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        double p[4][3];
        tri_points(m, t, p);
        for (int i = 0; i < 4; i++)
            for (int moved = 0; moved < 2; moved++, (*n)++)
                for (int k = 0; k < 3; k++) {
                    double r = lm_rng_unit(&rng) - 0.5;
                    q[3 * *n + (size_t)k] = p[i][k] + (moved ? 2 * r * jitter : 0);
                }
    }
    return q;
}

static double diagonal(const lm_mesh *m)
{
    float lo[3], hi[3];
    double d = 0;
    lm_mesh_bounds(m, lo, hi);
    for (int k = 0; k < 3; k++)
        d += ((double)hi[k] - lo[k]) * ((double)hi[k] - lo[k]);
    return d > 0 ? sqrt(d) : 1;
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "tests/data/cache/meshes/bunny00.off";
    int rounds = argc > 2 ? atoi(argv[2]) : 20;
    lm_mesh *orig = NULL, *coarse = NULL;
    lm_bvh *b = NULL;
    if (lm_mesh_load(path, NULL, &orig) != LM_OK) {
        fprintf(stderr, "bench_bvh: %s\n", lm_last_error());
        return 1;
    }
    uint32_t target = orig->live_verts / 100 > 100 ? orig->live_verts / 100 : 100;
    if (co_simplify(orig, CO_SIMPLIFY_QEM, target, &coarse) != LM_OK) {
        fprintf(stderr, "bench_bvh: %s\n", lm_last_error());
        return 1;
    }
    double t0 = now();
    if (lm_bvh_create(orig, &b) != LM_OK) {
        fprintf(stderr, "bench_bvh: %s\n", lm_last_error());
        return 1;
    }
    double build_s = now() - t0;
    size_t n = 0;
    double *q = make_queries(coarse, 0.002 * diagonal(orig), &n);
    if (!q)
        return 1;
    double sum = 0;
    t0 = now();
    for (int r = 0; r < rounds; r++)
        for (size_t i = 0; i < n; i++)
            sum += lm_bvh_closest_sq(b, q + 3 * i);
    double s = now() - t0, per = (double)n * rounds;
    printf("bench bvh: %s, %u triangles (built in %.1f ms), %zu query points from %u coarse "
           "triangles, %d rounds: %.0f queries/s, %.3f us a query, checksum %.17g\n",
           path, orig->live_tris, 1e3 * build_s, n, coarse->live_tris, rounds, per / s,
           1e6 * s / per, sum / rounds);
    free(q);
    lm_bvh_destroy(b);
    lm_mesh_destroy(coarse);
    lm_mesh_destroy(orig);
    return 0;
}
