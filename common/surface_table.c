/* common/surface_table.c — the geometric term's table (surface_table.h): per triangle id of the
 * share, its corner positions and e(t); distances from the surface's hierarchy through a memo. */
#include "common/surface_table.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/distance_memo.h"
#include "common/grow.h"

typedef struct tri_entry {
    float p[3][3];
    int64_t e;
    int alive;
} tri_entry;

struct lm_surface_table {
    lm_distance_memo *memo;
    double k;
    uint32_t share, shares;
    tri_entry *tri; /* by id (ids of other shares stay dead) */
    uint32_t cap;
    int64_t total;
    int64_t *scratch; /* commit: the added triangles' e(t) */
    uint32_t cap_scratch;
};

static int mine(const lm_surface_table *t, uint32_t id)
{
    return id % t->shares == t->share;
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

/* area(t) and the mean squared distance of the edge midpoints and the centroid. */
static void tri_parts(lm_surface_table *t, const float pf[3][3], double *area, double *mean)
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
        sum += lm_distance_memo_sq(t->memo, q[j]);
    *area = tri_area(p);
    *mean = sum / 4.0;
}

int64_t lm_surface_table_tri(lm_surface_table *t, const float p[3][3])
{
    double area, mean;
    tri_parts(t, p, &area, &mean);
    double e = t->k * area * mean;
    return e < 9e18 ? (int64_t)llround(e) : INT64_C(9000000000000000000);
}

static void corners_of(const lm_tri_data *d, float p[3][3])
{
    for (int v = 0; v < 3; v++)
        memcpy(p[v], d->c[v].pos, sizeof p[v]);
}

/* e(t) of new data for its id: the stored one when its corners did not move. */
static int64_t added_energy(lm_surface_table *t, const lm_tri_data *d)
{
    float p[3][3];
    corners_of(d, p);
    if (d->id < t->cap && t->tri[d->id].alive && !memcmp(t->tri[d->id].p, p, sizeof p))
        return t->tri[d->id].e;
    return lm_surface_table_tri(t, (const float(*)[3])p);
}

static lm_status reserve(lm_surface_table *t, uint32_t id)
{
    if (id < t->cap)
        return LM_OK;
    size_t cap = lm_grow_cap(t->cap, (size_t)id + 1, 1024, UINT32_MAX);
    if (!LM_RESIZE(&t->tri, cap))
        return lm_fail(LM_E_NOMEM, "out of memory for the geometric term of %u triangles",
                       (uint32_t)cap);
    memset(t->tri + t->cap, 0, (cap - t->cap) * sizeof *t->tri);
    t->cap = (uint32_t)cap;
    return LM_OK;
}

static lm_status put(lm_surface_table *t, const lm_tri_data *d, int64_t e)
{
    lm_status st = reserve(t, d->id);
    if (st != LM_OK)
        return st;
    tri_entry *x = &t->tri[d->id];
    corners_of(d, x->p);
    x->e = e;
    x->alive = 1;
    t->total += e;
    return LM_OK;
}

static void drop(lm_surface_table *t, uint32_t id)
{
    if (id < t->cap && t->tri[id].alive) {
        t->total -= t->tri[id].e;
        t->tri[id].alive = 0;
    }
}

lm_status lm_surface_table_create(const lm_bvh *surface, double k, uint32_t share, uint32_t shares,
                                  lm_surface_table **out)
{
    *out = NULL;
    if (!surface || !(k > 0) || !isfinite(k) || shares == 0 || share >= shares)
        return lm_fail(LM_E_INVALID,
                       "geometric term: a surface, a positive scale and share %u "
                       "of %u",
                       share, shares);
    lm_surface_table *t = calloc(1, sizeof *t);
    if (!t)
        return lm_fail(LM_E_NOMEM, "out of memory for the geometric term");
    lm_status st = lm_distance_memo_create(surface, LM_SURFACE_MEMO_LOG2, &t->memo);
    if (st != LM_OK) {
        free(t);
        return st;
    }
    t->k = k;
    t->share = share;
    t->shares = shares;
    *out = t;
    return LM_OK;
}

void lm_surface_table_destroy(lm_surface_table *t)
{
    if (!t)
        return;
    lm_distance_memo_destroy(t->memo);
    free(t->tri);
    free(t->scratch);
    free(t);
}

lm_status lm_surface_table_set_mesh(lm_surface_table *t, const lm_tri_data *tris, size_t n)
{
    for (uint32_t i = 0; i < t->cap; i++)
        t->tri[i].alive = 0;
    t->total = 0;
    lm_status st = LM_OK;
    for (size_t i = 0; i < n && st == LM_OK; i++) {
        if (!mine(t, tris[i].id))
            continue;
        float p[3][3];
        corners_of(&tris[i], p);
        st = put(t, &tris[i], lm_surface_table_tri(t, (const float(*)[3])p));
    }
    return st;
}

static lm_status scratch_reserve(lm_surface_table *t, uint32_t n)
{
    if (n <= t->cap_scratch)
        return LM_OK;
    int64_t *x = realloc(t->scratch, (size_t)n * sizeof *x);
    if (!x)
        return lm_fail(LM_E_NOMEM, "out of memory for the geometric term of %u triangles", n);
    t->scratch = x;
    t->cap_scratch = n;
    return LM_OK;
}

lm_status lm_surface_table_commit(lm_surface_table *t, const lm_patch *p)
{
    lm_status st = scratch_reserve(t, p->n_added);
    if (st != LM_OK)
        return st;
    for (uint32_t i = 0; i < p->n_added; i++)
        t->scratch[i] = mine(t, p->added[i].id) ? added_energy(t, &p->added[i]) : 0;
    for (uint32_t i = 0; i < p->n_removed; i++)
        drop(t, p->removed[i]);
    for (uint32_t i = 0; i < p->n_added && st == LM_OK; i++) {
        if (!mine(t, p->added[i].id))
            continue;
        drop(t, p->added[i].id);
        st = put(t, &p->added[i], t->scratch[i]);
    }
    return st;
}

int64_t lm_surface_table_delta(lm_surface_table *t, const lm_patch *p)
{
    int64_t d = 0;
    for (uint32_t i = 0; i < p->n_added; i++)
        if (mine(t, p->added[i].id))
            d += added_energy(t, &p->added[i]);
    for (uint32_t i = 0; i < p->n_removed; i++) {
        uint32_t id = p->removed[i];
        if (id < t->cap && t->tri[id].alive)
            d -= t->tri[id].e;
    }
    return d;
}

int64_t lm_surface_table_total(const lm_surface_table *t)
{
    return t->total;
}

void lm_surface_table_set_k(lm_surface_table *t, double k)
{
    t->k = k;
    t->total = 0;
    for (uint32_t i = 0; i < t->cap; i++) {
        if (!t->tri[i].alive)
            continue;
        t->tri[i].e = lm_surface_table_tri(t, (const float(*)[3])t->tri[i].p);
        t->total += t->tri[i].e;
    }
}

double lm_surface_table_unit_energy(lm_surface_table *t, double k1)
{
    double sum = 0, area, mean;
    for (uint32_t i = 0; i < t->cap; i++) {
        if (!t->tri[i].alive)
            continue;
        tri_parts(t, (const float(*)[3])t->tri[i].p, &area, &mean);
        sum += k1 * area * mean;
    }
    return sum;
}
