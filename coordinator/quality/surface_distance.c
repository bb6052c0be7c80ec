/* coordinator/quality/surface_distance.c — surface sampling (the cumulative area of the live
 * triangles, one stratified draw per sample, uniform barycentric coordinates) and the two
 * one-sided distance sums through a closest-point hierarchy over each surface. */
#include "coordinator/quality/surface_distance.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"

#define CO_DISTANCE_SEED 0x9e3779b97f4a7c15ull

static double next_unit(uint64_t *s) /* xorshift64*, in [0, 1) */
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ull) >> 11) * (1.0 / 9007199254740992.0);
}

static double tri_area(const lm_mesh *m, uint32_t t)
{
    const float *a = m->pos[lm_tri_vertex(m, t, 0)], *b = m->pos[lm_tri_vertex(m, t, 1)];
    const float *c = m->pos[lm_tri_vertex(m, t, 2)];
    double u[3], v[3];
    for (int k = 0; k < 3; k++)
        u[k] = (double)b[k] - a[k], v[k] = (double)c[k] - a[k];
    double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2],
           z = u[0] * v[1] - u[1] * v[0];
    return 0.5 * sqrt(x * x + y * y + z * z);
}

/* Point at (r1, r2) on triangle t, uniformly distributed for uniform r1, r2. */
static void point_on(const lm_mesh *m, uint32_t t, double r1, double r2, double *p)
{
    double s = sqrt(r1), wa = 1 - s, wb = s * (1 - r2), wc = s * r2;
    const float *a = m->pos[lm_tri_vertex(m, t, 0)], *b = m->pos[lm_tri_vertex(m, t, 1)];
    const float *c = m->pos[lm_tri_vertex(m, t, 2)];
    for (int k = 0; k < 3; k++)
        p[k] = wa * a[k] + wb * b[k] + wc * c[k];
}

/* Live triangle ids and their cumulative areas (cum[i] = area of tris 0..i). */
static lm_status area_table(const lm_mesh *m, uint32_t **ids, double **cum, uint32_t *n)
{
    *ids = malloc(((size_t)m->live_tris + 1) * sizeof **ids);
    *cum = malloc(((size_t)m->live_tris + 1) * sizeof **cum);
    if (!*ids || !*cum)
        return lm_fail(LM_E_NOMEM, "out of memory sampling a surface");
    double total = 0;
    uint32_t k = 0;
    for (uint32_t t = 0; t < m->n_tris; t++)
        if (m->tri_alive[t]) {
            total += tri_area(m, t);
            (*ids)[k] = t;
            (*cum)[k++] = total;
        }
    *n = k;
    return k && total > 0 ? LM_OK : lm_fail(LM_E_INVALID, "the surface has no area to sample");
}

/* First index whose cumulative area exceeds x. */
static uint32_t find_area(const double *cum, uint32_t n, double x)
{
    uint32_t lo = 0, hi = n - 1;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (cum[mid] > x)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

lm_status co_surface_sample(const lm_mesh *m, uint32_t n, uint64_t seed, double **out)
{
    *out = NULL;
    uint32_t *ids = NULL, n_tris = 0;
    double *cum = NULL, *pts = malloc(((size_t)n + 1) * 3 * sizeof *pts);
    lm_status s = pts ? area_table(m, &ids, &cum, &n_tris) : lm_fail(LM_E_NOMEM, "out of memory");
    uint64_t rng = seed ? seed : 1;
    for (uint32_t i = 0; !s && i < n; i++) {
        double x = ((double)i + next_unit(&rng)) / n * cum[n_tris - 1];
        uint32_t t = ids[find_area(cum, n_tris, x)];
        double r1 = next_unit(&rng), r2 = next_unit(&rng);
        point_on(m, t, r1, r2, pts + 3 * (size_t)i);
    }
    free(ids);
    free(cum);
    if (s) {
        free(pts);
        return s;
    }
    *out = pts;
    return LM_OK;
}

typedef struct one_side {
    double sum, sum_sq, max;
} one_side;

/* Distances from n points of one surface to the other (its hierarchy). */
static void measure_side(const lm_bvh *other, const double *pts, uint32_t n, one_side *r)
{
    *r = (one_side){0, 0, 0};
    for (uint32_t i = 0; i < n; i++) {
        double d2 = lm_bvh_closest_sq(other, pts + 3 * (size_t)i), d = sqrt(d2);
        r->sum += d;
        r->sum_sq += d2;
        r->max = d > r->max ? d : r->max;
    }
}

static double diagonal_of(const lm_mesh *m)
{
    float lo[3], hi[3];
    lm_mesh_bounds(m, lo, hi);
    double d2 = 0;
    for (int k = 0; k < 3; k++)
        d2 += ((double)hi[k] - lo[k]) * ((double)hi[k] - lo[k]);
    return sqrt(d2);
}

lm_status co_surface_distance_measure(const lm_mesh *original, const lm_mesh *model,
                                      uint32_t samples, co_surface_distance *out)
{
    uint32_t n = samples ? samples : CO_DISTANCE_SAMPLES;
    memset(out, 0, sizeof *out); /* padding too: results compare as bytes */
    lm_bvh *bo = NULL, *bm = NULL;
    double *po = NULL, *pm = NULL;
    lm_status s = lm_bvh_create(original, &bo);
    if (!s)
        s = lm_bvh_create(model, &bm);
    if (!s)
        s = co_surface_sample(original, n, CO_DISTANCE_SEED, &po);
    if (!s)
        s = co_surface_sample(model, n, CO_DISTANCE_SEED + 1, &pm);
    if (!s) {
        one_side a, b;
        measure_side(bm, po, n, &a);
        measure_side(bo, pm, n, &b);
        out->mean = (a.sum + b.sum) / (2.0 * n);
        out->mean_from_original = a.sum / n;
        out->mean_to_original = b.sum / n;
        out->rms = sqrt((a.sum_sq + b.sum_sq) / (2.0 * n));
        out->max = a.max > b.max ? a.max : b.max;
        out->diagonal = diagonal_of(original);
        out->samples = n;
    }
    free(po);
    free(pm);
    lm_bvh_destroy(bo);
    lm_bvh_destroy(bm);
    return s;
}
