/* coordinator/optimizer/surface_term.c — the geometric term (surface_term.h): views that pass every
 * op on to the views they wrap and keep, per triangle id of the current mesh, its corner positions
 * and e(t), so that a patch's ΔE_geo costs distance queries only for triangles whose corners
 * moved. */
#include "coordinator/optimizer/surface_term.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "coordinator/optimizer/distance_memo.h"
#include "coordinator/optimizer/optimizer_tuning.h"

typedef struct tri_entry {
    float p[3][3];
    int64_t e;
    int alive;
} tri_entry;

typedef struct surface_views {
    lm_views base;
    lm_views *inner;
    lm_bvh *bvh;
    co_distance_memo *memo;    /* filled through const pointers too: it never changes a result */
    double k;                  /* e(t) = round(k · area · mean d²) */
    double n_views, px, px256; /* k = weight · views · px² · px256² */
    tri_entry *tri;
    uint32_t cap;
    int64_t total;
    int64_t *scratch; /* evaluate: each patch's change; commit: the added triangles' e(t) */
    uint32_t cap_scratch;
} surface_views;

static surface_views *as_sv(lm_views *v)
{
    return (surface_views *)v;
}

static double tri_area(const double p[3][3])
{
    double u[3], w[3];
    for (int i = 0; i < 3; i++) {
        u[i] = p[1][i] - p[0][i];
        w[i] = p[2][i] - p[0][i];
    }
    double c0 = u[1] * w[2] - u[2] * w[1];
    double c1 = u[2] * w[0] - u[0] * w[2];
    double c2 = u[0] * w[1] - u[1] * w[0];
    return 0.5 * sqrt(c0 * c0 + c1 * c1 + c2 * c2);
}

/* k for a weight (this order of products: the same bits as ever for a given weight). */
static double scale(const surface_views *s, double weight)
{
    return weight * s->n_views * s->px * s->px * s->px256 * s->px256;
}

/* area(t) and the mean squared distance of the edge midpoints and the centroid. */
static void tri_parts(const surface_views *s, const float pf[3][3], double *area, double *mean)
{
    double p[3][3], q[4][3], sum = 0;
    for (int v = 0; v < 3; v++)
        for (int i = 0; i < 3; i++)
            p[v][i] = pf[v][i];
    for (int i = 0; i < 3; i++) {
        q[0][i] = 0.5 * (p[0][i] + p[1][i]);
        q[1][i] = 0.5 * (p[1][i] + p[2][i]);
        q[2][i] = 0.5 * (p[2][i] + p[0][i]);
        q[3][i] = (p[0][i] + p[1][i] + p[2][i]) / 3.0;
    }
    for (int j = 0; j < 4; j++)
        sum += co_distance_memo_sq(s->memo, q[j]);
    *area = tri_area(p);
    *mean = sum / 4.0;
}

/* e(t): k · area · mean d², rounded. */
static int64_t tri_energy(const surface_views *s, const float pf[3][3])
{
    double area, mean;
    tri_parts(s, pf, &area, &mean);
    double e = s->k * area * mean;
    return e < 9e18 ? (int64_t)llround(e) : INT64_C(9000000000000000000);
}

static void corners_of(const lm_tri_data *t, float p[3][3])
{
    for (int v = 0; v < 3; v++)
        memcpy(p[v], t->c[v].pos, sizeof p[v]);
}

/* e(t) of new data for id t->id: the stored one when its corners did not move. */
static int64_t added_energy(const surface_views *s, const lm_tri_data *t)
{
    float p[3][3];
    corners_of(t, p);
    if (t->id < s->cap && s->tri[t->id].alive && !memcmp(s->tri[t->id].p, p, sizeof p))
        return s->tri[t->id].e;
    return tri_energy(s, (const float(*)[3])p);
}

static lm_status reserve(surface_views *s, uint32_t id)
{
    if (id < s->cap)
        return LM_OK;
    uint32_t cap = s->cap ? s->cap : 1024;
    while (cap <= id)
        cap *= 2;
    tri_entry *t = realloc(s->tri, (size_t)cap * sizeof *t);
    if (!t)
        return lm_fail(LM_E_NOMEM, "out of memory for the geometric term of %u triangles", cap);
    memset(t + s->cap, 0, (size_t)(cap - s->cap) * sizeof *t);
    s->tri = t;
    s->cap = cap;
    return LM_OK;
}

static lm_status put(surface_views *s, const lm_tri_data *t, int64_t e)
{
    lm_status st = reserve(s, t->id);
    if (st != LM_OK)
        return st;
    tri_entry *x = &s->tri[t->id];
    corners_of(t, x->p);
    x->e = e;
    x->alive = 1;
    s->total += e;
    return LM_OK;
}

static void drop(surface_views *s, uint32_t id)
{
    if (id < s->cap && s->tri[id].alive) {
        s->total -= s->tri[id].e;
        s->tri[id].alive = 0;
    }
}

static int64_t patch_delta(const surface_views *s, const lm_patch *p)
{
    int64_t d = 0;
    for (uint32_t i = 0; i < p->n_added; i++)
        d += added_energy(s, &p->added[i]);
    for (uint32_t i = 0; i < p->n_removed; i++) {
        uint32_t id = p->removed[i];
        if (id < s->cap && s->tri[id].alive)
            d -= s->tri[id].e;
    }
    return d;
}

/* ---- the ops ---------------------------------------------------------------------------------
 */

static lm_status sv_set_mesh(lm_views *base, const lm_tri_data *tris, size_t n)
{
    surface_views *s = as_sv(base);
    lm_status st = s->inner->ops->set_mesh(s->inner, tris, n);
    if (st != LM_OK)
        return st;
    for (uint32_t i = 0; i < s->cap; i++)
        s->tri[i].alive = 0;
    s->total = 0;
    for (size_t i = 0; i < n && st == LM_OK; i++) {
        float p[3][3];
        corners_of(&tris[i], p);
        st = put(s, &tris[i], tri_energy(s, (const float(*)[3])p));
    }
    return st;
}

static lm_status sv_set_materials(lm_views *base, const lm_material *m, uint32_t n)
{
    surface_views *s = as_sv(base);
    return s->inner->ops->set_materials(s->inner, m, n);
}

static lm_status scratch_reserve(surface_views *s, uint32_t n)
{
    if (n <= s->cap_scratch)
        return LM_OK;
    int64_t *x = realloc(s->scratch, (size_t)n * sizeof *x);
    if (!x)
        return lm_fail(LM_E_NOMEM, "out of memory for the geometric term of %u moves", n);
    s->scratch = x;
    s->cap_scratch = n;
    return LM_OK;
}

/* The geometric term's changes of a batch (into scratch), worked out while the inner views
 * render it where they can (workers in other processes). */
typedef struct batch_geo {
    const surface_views *s;
    const lm_patch *patches;
    uint32_t n;
} batch_geo;

static void geo_of_batch(void *ctx)
{
    const batch_geo *b = ctx;
    for (uint32_t i = 0; i < b->n; i++)
        b->s->scratch[i] = patch_delta(b->s, &b->patches[i]);
}

static lm_status sv_evaluate(lm_views *base, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    surface_views *s = as_sv(base);
    lm_status st = scratch_reserve(s, n);
    batch_geo b = {s, patches, n};
    if (st == LM_OK)
        st = lm_views_evaluate_overlapped(s->inner, patches, n, delta, geo_of_batch, &b);
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        delta[i] += s->scratch[i];
    return st;
}

static lm_status sv_commit(lm_views *base, const lm_patch *patch)
{
    surface_views *s = as_sv(base);
    lm_status st = s->inner->ops->commit(s->inner, patch);
    if (st != LM_OK)
        return st;
    st = scratch_reserve(s, patch->n_added);
    if (st != LM_OK)
        return st;
    for (uint32_t i = 0; i < patch->n_added; i++)
        s->scratch[i] = added_energy(s, &patch->added[i]);
    for (uint32_t i = 0; i < patch->n_removed; i++)
        drop(s, patch->removed[i]);
    for (uint32_t i = 0; i < patch->n_added && st == LM_OK; i++) {
        drop(s, patch->added[i].id);
        st = put(s, &patch->added[i], s->scratch[i]);
    }
    return st;
}

static lm_status sv_energy(lm_views *base, int64_t *total, int64_t *per_view)
{
    surface_views *s = as_sv(base);
    int64_t t = 0;
    lm_status st = s->inner->ops->energy(s->inner, &t, per_view);
    if (st == LM_OK && total)
        *total = t + s->total;
    return st;
}

static lm_status sv_potentials(lm_views *base, const float (*p)[3], size_t n, int64_t *out)
{
    surface_views *s = as_sv(base);
    return s->inner->ops->potentials(s->inner, p, n, out);
}

static lm_status sv_read_image(lm_views *base, lm_image_kind k, uint32_t view, uint8_t *out)
{
    surface_views *s = as_sv(base);
    return s->inner->ops->read_image(s->inner, k, view, out);
}

static void sv_info(lm_views *base, lm_views_info *out)
{
    surface_views *s = as_sv(base);
    s->inner->ops->info(s->inner, out);
}

static void sv_destroy(lm_views *base)
{
    surface_views *s = as_sv(base);
    co_distance_memo_destroy(s->memo);
    lm_bvh_destroy(s->bvh);
    free(s->tri);
    free(s->scratch);
    free(s);
}

static const lm_views_ops surface_ops = {
    .set_mesh = sv_set_mesh,
    .set_materials = sv_set_materials,
    .evaluate = sv_evaluate,
    .commit = sv_commit,
    .energy = sv_energy,
    .potentials = sv_potentials,
    .read_image = sv_read_image,
    .info = sv_info,
    .destroy = sv_destroy,
};

lm_status co_surface_views_create(lm_views *inner, const lm_mesh *surface, double weight,
                                  lm_views **out)
{
    *out = NULL;
    if (!inner || !surface || !(weight > 0) || !isfinite(weight))
        return lm_fail(LM_E_INVALID, "geometric term: views, a surface and a positive weight");
    surface_views *s = calloc(1, sizeof *s);
    if (!s)
        return lm_fail(LM_E_NOMEM, "out of memory for the geometric term");
    s->base.ops = &surface_ops;
    s->inner = inner;
    lm_status st = lm_bvh_create(surface, &s->bvh);
    if (st == LM_OK)
        st = co_distance_memo_create(s->bvh, CO_SURFACE_MEMO_LOG2, &s->memo);
    if (st != LM_OK) {
        lm_bvh_destroy(s->bvh);
        free(s);
        return st;
    }
    lm_views_info info;
    inner->ops->info(inner, &info);
    float c[3], r;
    lm_mesh_bounding_sphere(surface, c, &r);
    double two_r = r > 0 ? 2.0 * (double)r : 2.0;
    s->n_views = (double)info.n_views;
    s->px = (double)info.width / two_r;
    s->px256 = 256.0 / two_r;
    s->k = scale(s, weight);
    *out = &s->base;
    return LM_OK;
}

void co_surface_views_set_inner(lm_views *v, lm_views *inner)
{
    as_sv(v)->inner = inner;
}

int64_t co_surface_views_energy(const lm_views *v)
{
    return ((const surface_views *)v)->total;
}

int64_t co_surface_views_tri(const lm_views *v, const float p[3][3])
{
    return tri_energy((const surface_views *)v, p);
}

double co_surface_views_unit_energy(const lm_views *v)
{
    const surface_views *s = (const surface_views *)v;
    double sum = 0, k = scale(s, 1.0), area, mean;
    for (uint32_t i = 0; i < s->cap; i++) {
        if (!s->tri[i].alive)
            continue;
        tri_parts(s, (const float(*)[3])s->tri[i].p, &area, &mean);
        sum += k * area * mean;
    }
    return sum;
}

lm_status co_surface_views_weight_for_share(lm_views *v, double share, double *weight)
{
    surface_views *s = as_sv(v);
    int64_t image = 0;
    *weight = 1.0;
    lm_status st = s->inner->ops->energy(s->inner, &image, NULL);
    if (st != LM_OK)
        return st;
    double unit = co_surface_views_unit_energy(v);
    if (image > 0 && unit > 0) {
        double w = share * (double)image / unit;
        *weight = w < CO_SURFACE_MAX_WEIGHT ? w : CO_SURFACE_MAX_WEIGHT;
    }
    return LM_OK;
}

void co_surface_views_set_weight(lm_views *v, double weight)
{
    surface_views *s = as_sv(v);
    s->k = scale(s, weight);
    s->total = 0;
    for (uint32_t i = 0; i < s->cap; i++) {
        if (!s->tri[i].alive)
            continue;
        s->tri[i].e = tri_energy(s, (const float(*)[3])s->tri[i].p);
        s->total += s->tri[i].e;
    }
}
