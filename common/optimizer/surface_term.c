/* common/optimizer/surface_term.c — the geometric term (surface_term.h): views that pass every
 * op on to the views they wrap and keep the current mesh's e(t) in a table (common/
 * surface_table.h), so that a patch's ΔE_geo costs distance queries only for triangles whose
 * corners moved; where the wrapped views hold the term too (workers), the ΔE_geo of evaluations
 * is priced here or there, whichever measures faster. */
#include "common/optimizer/surface_term.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/bvh.h"
#include "common/log.h"
#include "common/optimizer/optimizer_tuning.h"
#include "common/surface_table.h"

/* Where the evaluations' ΔE_geo is priced when the wrapped views hold the term too: here, while
 * they render (this process's work, overlapped with theirs), or by them (spread over their
 * groups of views, but after their rendering, in every round). Here costs nothing while the
 * workers take longer than the term, and holds every round up once they are quicker (many
 * workers, short rounds): so a batch priced here measures the term's time and how long the
 * workers' answers were still awaited after it, and the workers price it while that wait is under
 * a tenth of the term's time (averages over batches; while they do, every SV_PROBE_EVERY-th batch
 * is priced here to measure again). Where the workers busy every processor of this machine
 * (lm_views_info.overlap_costs: local workers as many as its cores), work here is never free: it
 * takes a processor from one of them, which that wait cannot show, so they always price it
 * (bunny 1% and frog, --workers 2 on 2 cores: ×1.04 evaluations/s). The answers are the same
 * bits either way. */
#define SV_PROBE_EVERY 32u
#define SV_AVERAGE 0.0625 /* weight of a batch in the averages */

typedef struct surface_views {
    lm_views base;
    lm_views *inner;
    const lm_mesh *surface;
    lm_bvh *bvh;
    lm_surface_table *table;   /* every triangle of the current mesh (share 0 of 1) */
    double k;                  /* e(t) = round(k · area · mean d²) */
    double weight;             /* the term's weight (create, set_weight) */
    double n_views, px, px256; /* k = weight · views · px² · px256² */
    double two_r;              /* the surface's bounding sphere's diameter (px, px256) */
    int held;                  /* the inner views hold the term (surface_term took it) */
    lm_surface_pricing pricing;
    int workers;                  /* with LM_SURFACE_AUTO: the inner views price it now */
    int cores_full;               /* their workers busy every processor here (overlap_costs):
                                     with LM_SURFACE_AUTO they always price it */
    uint32_t batch;               /* batches evaluated by the workers since the last here */
    double geo_s, wait_s;         /* averages a patch, of batches priced here: the term's time,
                                     and the wait for the workers' answers after it */
    uint64_t by_workers, by_here; /* patches priced each way */
    int64_t *scratch;             /* evaluate: each patch's change */
    uint32_t cap_scratch;
} surface_views;

static surface_views *as_sv(lm_views *v)
{
    return (surface_views *)v;
}

/* k for a weight (this order of products: the same bits as ever for a given weight). */
static double scale(const surface_views *s, double weight)
{
    return weight * s->n_views * s->px * s->px * s->px256 * s->px256;
}

/* The view parts of k from the wrapped views: their count and width (px, the pixels per unit of a
 * view S wide framing the surface's bounding sphere). */
static void view_parts(surface_views *s)
{
    lm_views_info info;
    s->inner->ops->info(s->inner, &info);
    s->n_views = (double)info.n_views;
    s->px = (double)info.width / s->two_r;
}

/* The bounding sphere's diameter of the surface (2 where it is a point). */
static double surface_diameter(const lm_mesh *surface)
{
    float c[3], r;
    lm_mesh_bounding_sphere(surface, c, &r);
    return r > 0 ? 2.0 * (double)r : 2.0;
}

/* LUMESH_SURFACE_PRICING=here|workers fixes where the term is priced (tests, benchmarks); unset
 * or anything else, whichever measures faster. */
static lm_surface_pricing pricing_from_env(void)
{
    const char *e = getenv("LUMESH_SURFACE_PRICING");
    if (e && !strcmp(e, "here"))
        return LM_SURFACE_HERE;
    if (e && !strcmp(e, "workers"))
        return LM_SURFACE_WORKERS;
    return LM_SURFACE_AUTO;
}

/* Hand the term to the inner views where they take it (their evaluate_surface then prices it);
 * otherwise it is priced here. */
static lm_status offload(surface_views *s)
{
    lm_status st = lm_views_surface_term(s->inner, s->surface, s->k);
    s->held = st == LM_OK && s->inner->ops->evaluate_surface;
    lm_views_info info;
    s->inner->ops->info(s->inner, &info);
    s->cores_full = info.overlap_costs;
    if (st == LM_E_UNSUPPORTED) {
        lm_clear_error();
        st = LM_OK;
    }
    return st;
}

static lm_status sv_set_mesh(lm_views *base, const lm_tri_data *tris, size_t n)
{
    surface_views *s = as_sv(base);
    lm_status st = s->inner->ops->set_mesh(s->inner, tris, n);
    return st == LM_OK ? lm_surface_table_set_mesh(s->table, tris, n) : st;
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
    surface_views *s;
    const lm_patch *patches;
    uint32_t n;
    double seconds; /* the time it took */
} batch_geo;

static double wall_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void geo_of_batch(void *ctx)
{
    batch_geo *b = ctx;
    double t0 = wall_s();
    for (uint32_t i = 0; i < b->n; i++)
        b->s->scratch[i] = lm_surface_table_delta(b->s->table, &b->patches[i]);
    b->seconds = wall_s() - t0;
}

/* The batch with ΔE_geo priced here, while the inner views render it where they can; where they
 * hold the term too, the averages that decide where it is priced are updated. */
static lm_status evaluate_here(surface_views *s, const lm_patch *patches, uint32_t n,
                               int64_t *delta)
{
    lm_status st = scratch_reserve(s, n);
    batch_geo b = {s, patches, n, 0};
    double t0 = wall_s();
    if (st == LM_OK)
        st = lm_views_evaluate_overlapped(s->inner, patches, n, delta, geo_of_batch, &b);
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        delta[i] += s->scratch[i];
    if (st == LM_OK && s->held && n) {
        double wait = wall_s() - t0 - b.seconds, geo = b.seconds;
        s->geo_s += SV_AVERAGE * (geo / n - s->geo_s);
        s->wait_s += SV_AVERAGE * ((wait > 0 ? wait : 0) / n - s->wait_s);
        s->workers = s->wait_s < 0.1 * s->geo_s;
        s->batch = 0;
    }
    return st;
}

static lm_status sv_evaluate(lm_views *base, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    surface_views *s = as_sv(base);
    int workers =
        s->held && (s->pricing == LM_SURFACE_WORKERS ||
                    (s->pricing == LM_SURFACE_AUTO &&
                     (s->cores_full || (s->workers && ++s->batch % SV_PROBE_EVERY != 0))));
    *(workers ? &s->by_workers : &s->by_here) += s->held ? n : 0;
    return workers ? s->inner->ops->evaluate_surface(s->inner, patches, n, delta)
                   : evaluate_here(s, patches, n, delta);
}

static lm_status sv_commit(lm_views *base, const lm_patch *patch)
{
    surface_views *s = as_sv(base);
    lm_status st = s->inner->ops->commit(s->inner, patch);
    return st == LM_OK ? lm_surface_table_commit(s->table, patch) : st;
}

static lm_status sv_energy(lm_views *base, int64_t *total, int64_t *per_view)
{
    surface_views *s = as_sv(base);
    int64_t t = 0;
    lm_status st = s->inner->ops->energy(s->inner, &t, per_view);
    if (st == LM_OK && total)
        *total = t + lm_surface_table_total(s->table);
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
    if (s->held)
        lm_debug("geometric term: %.1f us a patch, answers awaited %.1f us after it; %.0f%% of "
                 "patches priced by the workers",
                 1e6 * s->geo_s, 1e6 * s->wait_s, 100.0 * lm_surface_views_worker_share(base));
    lm_surface_table_destroy(s->table);
    lm_bvh_destroy(s->bvh);
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

lm_status lm_surface_views_create(lm_views *inner, const lm_mesh *surface, double weight,
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
    s->surface = surface;
    s->two_r = surface_diameter(surface);
    view_parts(s);
    s->px256 = 256.0 / s->two_r;
    s->weight = weight;
    s->k = scale(s, weight);
    s->workers = 0; /* until a batch priced here has measured the way */
    s->pricing = pricing_from_env();
    lm_status st = lm_bvh_create(surface, &s->bvh);
    if (st == LM_OK)
        st = lm_surface_table_create(s->bvh, s->k, 0, 1, &s->table);
    if (st == LM_OK)
        st = offload(s);
    if (st != LM_OK) {
        sv_destroy(&s->base);
        return st;
    }
    *out = &s->base;
    return LM_OK;
}

lm_status lm_surface_views_set_inner(lm_views *v, lm_views *inner)
{
    surface_views *s = as_sv(v);
    s->inner = inner;
    view_parts(s);
    double k = scale(s, s->weight);
    if (k != s->k) { /* other views' count or size: the term keeps its share of the image energy */
        s->k = k;
        lm_surface_table_set_k(s->table, k);
    }
    return offload(s);
}

double lm_surface_views_scale(const lm_views *v)
{
    return ((const surface_views *)v)->k;
}

int lm_surface_views_offloaded(const lm_views *v)
{
    return ((const surface_views *)v)->held;
}

void lm_surface_views_set_pricing(lm_views *v, lm_surface_pricing p)
{
    as_sv(v)->pricing = p;
}

double lm_surface_views_worker_share(const lm_views *v)
{
    const surface_views *s = (const surface_views *)v;
    uint64_t all = s->by_workers + s->by_here;
    return all ? (double)s->by_workers / (double)all : 0.0;
}

int64_t lm_surface_views_energy(const lm_views *v)
{
    return lm_surface_table_total(((const surface_views *)v)->table);
}

int64_t lm_surface_views_tri(const lm_views *v, const float p[3][3])
{
    return lm_surface_table_tri(((const surface_views *)v)->table, p);
}

double lm_surface_views_unit_energy(const lm_views *v)
{
    const surface_views *s = (const surface_views *)v;
    return lm_surface_table_unit_energy(s->table, scale(s, 1.0));
}

lm_status lm_surface_views_weight_for_share(lm_views *v, double share, double *weight)
{
    surface_views *s = as_sv(v);
    int64_t image = 0;
    *weight = 1.0;
    lm_status st = s->inner->ops->energy(s->inner, &image, NULL);
    if (st != LM_OK)
        return st;
    double unit = lm_surface_views_unit_energy(v);
    if (image > 0 && unit > 0) {
        double w = share * (double)image / unit;
        *weight = w < LM_SURFACE_MAX_WEIGHT ? w : LM_SURFACE_MAX_WEIGHT;
    }
    return LM_OK;
}

lm_status lm_surface_views_set_weight(lm_views *v, double weight)
{
    surface_views *s = as_sv(v);
    s->weight = weight;
    s->k = scale(s, weight);
    lm_surface_table_set_k(s->table, s->k);
    return s->held ? offload(s) : LM_OK;
}
