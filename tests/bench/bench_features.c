/* tests/bench/bench_features.c — how well a simplified mesh keeps the original's sharp features
 * (issue 37 part 4's measure). Feature edges are those of coordinator/simplify/adapt_features.h
 * (dihedral angle above ANGLE degrees, plus boundaries, seams and material or part borders), on
 * both meshes. Points are sampled along the original's feature edges (one every diagonal / 2000,
 * at least one an edge); each one's distance to the nearest feature edge of RESULT is measured.
 * Prints one JSON line: the feature edges of both, the samples, the mean and max of those
 * distances as fractions of the original's bounding-box diagonal, and the share of samples within
 * 0.001, 0.002 and 0.005 of the diagonal of a feature edge of RESULT; and for the original's
 * corners (vertices with 1 or 3 and more feature edges), the share that RESULT has as a vertex
 * (within 1e-6 of the diagonal) and their mean distance to RESULT's nearest vertex.
 *
 * usage: bench_features ORIGINAL RESULT [ANGLE (default 30)] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "coordinator/simplify/adapt_features.h"

typedef struct seg {
    double a[3], b[3];
} seg;

/* The feature edges of m as segments (caller frees). */
static seg *features(const lm_mesh *m, double cos_max, size_t *n)
{
    uint32_t(*e)[2] = NULL;
    size_t ne = 0;
    *n = 0;
    if (lm_mesh_list_edges(m, &e, &ne))
        return NULL;
    seg *s = malloc((ne + 1) * sizeof *s);
    for (size_t i = 0; s && i < ne; i++) {
        if (!co_adapt_is_feature_edge(m, e[i][0], e[i][1], cos_max))
            continue;
        for (int k = 0; k < 3; k++) {
            s[*n].a[k] = m->pos[e[i][0]][k];
            s[*n].b[k] = m->pos[e[i][1]][k];
        }
        (*n)++;
    }
    free(e);
    return s;
}

static double seg_dist_sq(const double p[3], const seg *s)
{
    double d[3], w[3], dd = 0, t = 0;
    for (int k = 0; k < 3; k++) {
        d[k] = s->b[k] - s->a[k];
        w[k] = p[k] - s->a[k];
        dd += d[k] * d[k];
        t += d[k] * w[k];
    }
    t = dd > 0 ? t / dd : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    double r = 0;
    for (int k = 0; k < 3; k++) {
        double x = w[k] - t * d[k];
        r += x * x;
    }
    return r;
}

/* Over the corners of o: the share with a vertex of r within 1e-6 x diag, the mean distance to
 * r's nearest vertex (/ diag); returns the corners' count. */
static uint32_t corners(const lm_mesh *o, const lm_mesh *r, double cos_max, double diag,
                        double *kept, double *mean)
{
    uint8_t *cls = malloc(o->n_verts + 1);
    uint32_t n = 0, k = 0;
    double sum = 0;
    if (cls && !co_adapt_vertex_classes(o, cos_max, cls))
        for (uint32_t v = 0; v < o->n_verts; v++) {
            if (!o->vert_alive[v] || cls[v] != CO_ADAPT_CORNER)
                continue;
            double best = INFINITY;
            for (uint32_t u = 0; u < r->n_verts; u++) {
                double d = 0;
                for (int x = 0; x < 3; x++)
                    d += ((double)o->pos[v][x] - r->pos[u][x]) *
                         ((double)o->pos[v][x] - r->pos[u][x]);
                best = fmin(best, d);
            }
            best = sqrt(best) / diag;
            k += best <= 1e-6;
            sum += best;
            n++;
        }
    free(cls);
    *kept = n ? (double)k / n : 1;
    *mean = n ? sum / n : 0;
    return n;
}

static double diagonal(const lm_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < m->n_verts; v++)
        for (int k = 0; k < 3 && m->vert_alive[v]; k++) {
            lo[k] = fmin(lo[k], m->pos[v][k]);
            hi[k] = fmax(hi[k], m->pos[v][k]);
        }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_features ORIGINAL RESULT [ANGLE (default 30)]\n");
        return 1;
    }
    double angle = argc > 3 ? atof(argv[3]) : 30.0;
    double cos_max = cos(angle * 3.14159265358979323846 / 180.0);
    lm_mesh *o = NULL, *r = NULL;
    if (lm_mesh_load(argv[1], NULL, &o) || lm_mesh_load(argv[2], NULL, &r)) {
        fprintf(stderr, "bench_features: cannot load %s\n", o ? argv[2] : argv[1]);
        return 1;
    }
    size_t no = 0, nr = 0;
    seg *fo = features(o, cos_max, &no), *fr = features(r, cos_max, &nr);
    double diag = diagonal(o), step = diag / 2000, sum = 0, mx = 0;
    size_t samples = 0, within[3] = {0, 0, 0};
    const double tol[3] = {0.001, 0.002, 0.005};
    for (size_t i = 0; fo && fr && i < no; i++) {
        double len = sqrt((fo[i].b[0] - fo[i].a[0]) * (fo[i].b[0] - fo[i].a[0]) +
                          (fo[i].b[1] - fo[i].a[1]) * (fo[i].b[1] - fo[i].a[1]) +
                          (fo[i].b[2] - fo[i].a[2]) * (fo[i].b[2] - fo[i].a[2]));
        int k = (int)ceil(len / step);
        k = k < 1 ? 1 : k;
        for (int j = 0; j < k; j++) {
            double t = (j + 0.5) / k, p[3], best = INFINITY;
            for (int x = 0; x < 3; x++)
                p[x] = fo[i].a[x] + t * (fo[i].b[x] - fo[i].a[x]);
            for (size_t q = 0; q < nr; q++)
                best = fmin(best, seg_dist_sq(p, &fr[q]));
            double d = sqrt(best) / diag;
            sum += d;
            mx = fmax(mx, d);
            for (int w = 0; w < 3; w++)
                within[w] += d <= tol[w];
            samples++;
        }
    }
    double n = samples ? (double)samples : 1, kept = 0, cmean = 0;
    uint32_t nc = corners(o, r, cos_max, diag, &kept, &cmean);
    printf("{\"original_feature_edges\": %zu, \"result_feature_edges\": %zu, \"samples\": %zu, "
           "\"mean\": %.6g, \"max\": %.6g, \"within_0.001\": %.4f, \"within_0.002\": %.4f, "
           "\"within_0.005\": %.4f, \"corners\": %u, \"corners_kept\": %.4f, "
           "\"corner_mean\": %.6g}\n",
           no, nr, samples, sum / n, mx, within[0] / n, within[1] / n, within[2] / n, nc, kept,
           cmean);
    free(fo);
    free(fr);
    lm_mesh_destroy(o);
    lm_mesh_destroy(r);
    return 0;
}
