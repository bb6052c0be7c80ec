/* coordinator/geometric/sample.c — the data points of Hoppe's E_dist: points on the original's
 * surface, each triangle chosen with probability proportional to its area and the point uniform
 * on it (the square-root map), drawn from the seed: the same seed gives the same points. */
#include <math.h>
#include <stdlib.h>

#include "coordinator/geometric/geo_internal.h"

static double tri_area(const lm_mesh *m, uint32_t t)
{
    double n[3];
    lm_mesh_face_normal(m, t, n);
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* First index i with cdf[i] > u (cdf ascending, cdf[n-1] > u). */
static uint32_t pick(const double *cdf, uint32_t n, double u)
{
    uint32_t lo = 0, hi = n - 1;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (cdf[mid] > u)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

lm_status co_geo_sample(const lm_mesh *original, uint32_t n, uint64_t seed, co_geo_point *out)
{
    uint32_t nt = original->live_tris;
    double *cdf = malloc((size_t)nt * sizeof *cdf);
    uint32_t *id = malloc((size_t)nt * sizeof *id);
    if (!cdf || !id) {
        free(cdf);
        free(id);
        return lm_fail(LM_E_NOMEM, "out of memory for the sample points");
    }
    double acc = 0;
    uint32_t k = 0;
    for (uint32_t t = 0; t < original->n_tris; t++)
        if (original->tri_alive[t]) {
            acc += tri_area(original, t);
            cdf[k] = acc;
            id[k++] = t;
        }
    lm_rng r;
    lm_rng_seed(&r, seed ^ 0x9e0a5a11e5ULL);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t t = id[pick(cdf, nt, lm_rng_unit(&r) * acc)];
        double r1 = sqrt(lm_rng_unit(&r)), r2 = lm_rng_unit(&r);
        double w[3] = {1 - r1, r1 * (1 - r2), r1 * r2};
        for (int c = 0; c < 3; c++)
            out[i].x[c] = 0;
        for (int v = 0; v < 3; v++) {
            const float *p = original->pos[lm_tri_vertex(original, t, v)];
            for (int c = 0; c < 3; c++)
                out[i].x[c] += w[v] * p[c];
        }
        out[i].tri = out[i].next = LM_NONE;
        out[i].d2 = 0;
    }
    free(cdf);
    free(id);
    return LM_OK;
}
