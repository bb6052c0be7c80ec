/* coordinator/simplify/simplify_adaptive.c — the shape-adaptive simplification loop (Park, Lee &
 * Lee 2003) and its --target-verts search. Every vertex b is a candidate to leave by a half-edge
 * collapse b -> a into the neighbour a of least optimality Omega(ab) < 0 (the edge shorter than
 * its optimal length: adapt_edge_length.h); an indexed heap orders the vertices by that Omega,
 * the least optimal first. A corner (adapt_features.h) never leaves; a vertex on a feature line
 * leaves only along a feature edge. A collapse is kept when it folds no triangle, leaves no
 * vertex above the paper's valence limit, and keeps the tolerance (the explicit check that
 * replaces the paper's "reject what lowers optimality": see SIMPLIFY.md, "Shape-adaptive"): every
 * original vertex removed so far stays within e of the triangles around the vertex that holds it,
 * and the changed triangles' edge midpoints and centroids stay within e of the original. Otherwise
 * the journal undoes it and the next neighbour is tried. The survivor keeps its position (an
 * original vertex), so the curvature of every edge comes from the original's normals. Same input,
 * same output: every decision is ordered by (Omega, id). */
#include "coordinator/simplify/adaptive.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "common/indexed_heap.h"
#include "common/mesh_topology.h"
#include "coordinator/simplify/adapt_curvature.h"
#include "coordinator/simplify/adapt_edge_length.h"
#include "coordinator/simplify/adapt_features.h"
#include "coordinator/simplify/simplify_internal.h"

#define RING_CAP 256
#define LOCAL_CAP 64
#define PRIO_SCALE 1099511627776.0 /* 2^40: Omega / diagonal as a heap key */

/* What every pass shares: the original with adjacency, its normals, classes, BVH, diagonal. */
typedef struct adapt_base {
    lm_mesh *mesh;
    double (*pts)[3]; /* the tolerance's points of the original: its vertices (by id), then its
                         triangles' centroids and its edges' midpoints */
    uint32_t *owner;  /* [n_pts]: the vertex that holds each point first (itself for a vertex) */
    uint8_t *sharp;   /* [n_pts]: 1 for a point on a feature (held to CO_ADAPT_FEATURE_SHARE) */
    uint32_t n_pts;
    double (*nrm)[3];
    uint8_t *cls;
    lm_bvh *bvh;
    double diag;
    int soft; /* features held by the tighter tolerance only: corners and lines may move */
} adapt_base;

typedef struct owned {
    uint32_t *ids, n, cap;
} owned;

typedef struct adapt {
    const adapt_base *base;
    lm_mesh *m;
    lm_journal *j;
    owned *own;
    lm_iheap heap;
    double e, e2, f2, cos_max; /* f2: the squared tolerance of feature points */
    uint32_t collapses, refused;
    uint32_t ring[RING_CAP], ring_b[RING_CAP], ring_a[RING_CAP], fan[RING_CAP];
    uint32_t before_ids[RING_CAP], n_before;
    double before[RING_CAP][3];
    double corners[RING_CAP][3][3];
    uint32_t local_ids[LOCAL_CAP];
    double local[LOCAL_CAP][3][3];
} adapt;

static void posd(const lm_mesh *m, uint32_t v, double p[3])
{
    p[0] = m->pos[v][0];
    p[1] = m->pos[v][1];
    p[2] = m->pos[v][2];
}

static double omega(const adapt *s, uint32_t b, uint32_t a)
{
    double pa[3], pb[3];
    posd(s->m, a, pa);
    posd(s->m, b, pb);
    double d[3] = {pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double kappa = co_adapt_edge_curvature(pb, s->base->nrm[b], pa, s->base->nrm[a]);
    return co_adapt_optimality(len, kappa, s->e, s->base->diag);
}

static int eligible(const adapt *s, uint32_t b, uint32_t a)
{
    uint8_t c = s->base->cls[b];
    if (s->base->soft)
        return 1;
    if (c == CO_ADAPT_CORNER)
        return 0;
    return c == CO_ADAPT_SMOOTH || co_adapt_is_feature_edge(s->m, b, a, s->cos_max);
}

static int64_t prio_of(const adapt *s, double w)
{
    return (int64_t)llround(w / s->base->diag * PRIO_SCALE);
}

/* The heap key of b: its least Omega < 0 over eligible neighbours; out of the heap if none. */
static void refresh(adapt *s, uint32_t b)
{
    int found = 0;
    double best = 0;
    if (s->m->vert_alive[b]) {
        uint32_t n = lm_mesh_vertex_neighbors(s->m, b, s->ring, RING_CAP);
        for (uint32_t i = 0; i < n && i < RING_CAP; i++) {
            double w = omega(s, b, s->ring[i]);
            if (w < 0 && (!found || w < best) && eligible(s, b, s->ring[i])) {
                best = w;
                found = 1;
            }
        }
    }
    if (found)
        lm_iheap_set(&s->heap, b, prio_of(s, best), b);
    else
        lm_iheap_remove(&s->heap, b);
}

/* No triangle around b turned over (or degenerated) by the collapse. */
static int fold_ok(adapt *s)
{
    for (uint32_t i = 0; i < s->n_before; i++) {
        uint32_t t = s->before_ids[i];
        if (!s->m->tri_alive[t])
            continue;
        double n[3], *o = s->before[i];
        co_adapt_tri_cross(s->m, t, n);
        double dot = n[0] * o[0] + n[1] * o[1] + n[2] * o[2];
        double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double on = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
        if (!(dot > 0.2 * nn * on))
            return 0;
    }
    return 1;
}

/* The triangles around v as corner positions in s->corners; returns how many. */
static uint32_t gather_fan(adapt *s, uint32_t v)
{
    uint32_t n = lm_mesh_vertex_tris(s->m, v, s->fan, RING_CAP);
    n = n < RING_CAP ? n : RING_CAP;
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            posd(s->m, s->m->wedges[s->m->tris[s->fan[i]].w[k]].vertex, s->corners[i][k]);
    return n;
}

/* 1 when original point p is within e of one of the n gathered triangles. */
static int near_fan(const adapt *s, uint32_t n, uint32_t p)
{
    const double *q = s->base->pts[p];
    double r2 = s->base->sharp[p] ? s->f2 : s->e2;
    for (uint32_t i = 0; i < n; i++)
        if (lm_point_triangle_sq(q, s->corners[i][0], s->corners[i][1], s->corners[i][2]) <= r2)
            return 1;
    return 0;
}

/* Every original point v holds (and `extra`, unless LM_NONE) within e of v's triangles. */
static int owned_within(adapt *s, uint32_t v, const owned *o, uint32_t extra)
{
    if (!o->n && extra == LM_NONE)
        return 1;
    uint32_t n = gather_fan(s, v);
    if (extra != LM_NONE && !near_fan(s, n, extra))
        return 0;
    for (uint32_t i = 0; i < o->n; i++)
        if (!near_fan(s, n, o->ids[i]))
            return 0;
    return 1;
}

/* Steps a side of triangle c's sample grid: CO_ADAPT_SAMPLE_STEPS, more on a triangle whose
 * longest edge is above CO_ADAPT_SAMPLE_STEPS x CO_ADAPT_SAMPLE_SPACING x e, at most 16. */
static int sample_steps(const double c[3][3], double e)
{
    double longest = 0;
    for (int k = 0; k < 3; k++) {
        const double *p = c[k], *q = c[(k + 1) % 3];
        double d = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                        (p[2] - q[2]) * (p[2] - q[2]));
        longest = d > longest ? d : longest;
    }
    double steps = ceil(longest / (CO_ADAPT_SAMPLE_SPACING * e));
    return steps < CO_ADAPT_SAMPLE_STEPS ? CO_ADAPT_SAMPLE_STEPS : steps > 16 ? 16 : (int)steps;
}

/* The original's triangles around the corners of triangle t (vertices keep their ids), as
 * corner positions in s->local: the first place to look for a sample's original surface. */
static uint32_t gather_local(adapt *s, uint32_t t)
{
    const lm_mesh *o = s->base->mesh;
    uint32_t n = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t v = s->m->wedges[s->m->tris[t].w[k]].vertex;
        uint32_t c = lm_mesh_vertex_tris(o, v, s->local_ids + n, LOCAL_CAP - n);
        n += c < LOCAL_CAP - n ? c : LOCAL_CAP - n;
    }
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            posd(o, o->wedges[o->tris[s->local_ids[i]].w[k]].vertex, s->local[i][k]);
    return n;
}

static int near_local(const adapt *s, uint32_t n, const double p[3])
{
    for (uint32_t i = 0; i < n; i++)
        if (lm_point_triangle_sq(p, s->local[i][0], s->local[i][1], s->local[i][2]) <= s->e2)
            return 1;
    return 0;
}

/* The changed triangles (those b had, alive) stay near the original: the points of a
 * barycentric grid (sample_steps; corners left out: original vertices) within e. */
static int samples_within(adapt *s)
{
    for (uint32_t i = 0; i < s->n_before; i++) {
        uint32_t t = s->before_ids[i];
        if (!s->m->tri_alive[t])
            continue;
        double c[3][3];
        for (int k = 0; k < 3; k++)
            posd(s->m, s->m->wedges[s->m->tris[t].w[k]].vertex, c[k]);
        int n = sample_steps(c, s->e);
        uint32_t nl = gather_local(s, t);
        for (int u = 0; u <= n; u++)
            for (int v = 0; u + v <= n; v++) {
                int w = n - u - v;
                if (u == n || v == n || w == n)
                    continue;
                double p[3];
                for (int x = 0; x < 3; x++)
                    p[x] = ((double)u * c[0][x] + (double)v * c[1][x] + (double)w * c[2][x]) / n;
                if (!near_local(s, nl, p) && !lm_bvh_within(s->base->bvh, p, s->e2))
                    return 0;
            }
    }
    return 1;
}

/* Every check of a collapse b -> a already applied (a's and b's rings before in ring_a[0..na)
 * and ring_b[0..nb)). */
static int collapse_ok(adapt *s, uint32_t b, uint32_t a, uint32_t na, uint32_t nb)
{
    if (!fold_ok(s))
        return 0;
    uint32_t n = lm_mesh_vertex_neighbors(s->m, a, s->ring, RING_CAP);
    if (n > RING_CAP || (n > CO_ADAPT_MAX_VALENCE && n > na))
        return 0;
    if (!owned_within(s, a, &s->own[b], b) || !owned_within(s, a, &s->own[a], LM_NONE))
        return 0;
    for (uint32_t i = 0; i < nb; i++)
        if (s->ring_b[i] != a && !owned_within(s, s->ring_b[i], &s->own[s->ring_b[i]], LM_NONE))
            return 0;
    return samples_within(s);
}

/* Collapse b -> a (a keeps its position) if every check passes; 1 when applied. */
static int try_collapse(adapt *s, uint32_t b, uint32_t a)
{
    size_t mark = lm_journal_mark(s->j);
    s->n_before = lm_mesh_vertex_tris(s->m, b, s->before_ids, RING_CAP);
    uint32_t na = lm_mesh_vertex_neighbors(s->m, a, s->ring_a, RING_CAP);
    uint32_t nb = lm_mesh_vertex_neighbors(s->m, b, s->ring_b, RING_CAP);
    if (s->n_before > RING_CAP || na > RING_CAP || nb > RING_CAP)
        return 0;
    for (uint32_t i = 0; i < s->n_before; i++)
        co_adapt_tri_cross(s->m, s->before_ids[i], s->before[i]);
    if (lm_mesh_collapse_edge(s->m, a, b, s->m->pos[a], s->j) != LM_OK)
        return 0;
    if (collapse_ok(s, b, a, na, nb))
        return 1;
    lm_journal_rollback(s->m, s->j, mark);
    return 0;
}

typedef struct cand {
    double w;
    uint32_t a;
} cand;

/* Apply b's best collapse that passes (in (Omega, id) order); 1 with *a and *w when one did. */
static int best_passing(adapt *s, uint32_t b, uint32_t *a, double *w)
{
    cand c[RING_CAP];
    uint32_t n = lm_mesh_vertex_neighbors(s->m, b, s->ring, RING_CAP), k = 0;
    for (uint32_t i = 0; i < n && i < RING_CAP; i++) {
        double x = omega(s, b, s->ring[i]);
        if (x < 0 && eligible(s, b, s->ring[i])) {
            uint32_t p = k++;
            for (; p > 0 && (c[p - 1].w > x || (c[p - 1].w == x && c[p - 1].a > s->ring[i])); p--)
                c[p] = c[p - 1];
            c[p] = (cand){x, s->ring[i]};
        }
    }
    for (uint32_t i = 0; i < k; i++) {
        if (try_collapse(s, b, c[i].a)) {
            *a = c[i].a;
            *w = c[i].w;
            return 1;
        }
        s->refused++;
    }
    return 0;
}

static lm_status own_add(owned *o, uint32_t v)
{
    if (o->n == o->cap) {
        uint32_t cap = o->cap ? 2 * o->cap : 4;
        uint32_t *g = realloc(o->ids, (size_t)cap * sizeof *g);
        if (!g)
            return lm_fail(LM_E_NOMEM, "out of memory simplifying");
        o->ids = g;
        o->cap = cap;
    }
    o->ids[o->n++] = v;
    return LM_OK;
}

/* Keep the applied collapse b -> a: a holds b and what b held; keys around a refreshed. */
static lm_status commit(adapt *s, uint32_t b, uint32_t a)
{
    lm_status st = own_add(&s->own[a], b);
    for (uint32_t i = 0; i < s->own[b].n && !st; i++)
        st = own_add(&s->own[a], s->own[b].ids[i]);
    free(s->own[b].ids);
    s->own[b] = (owned){0};
    lm_journal_clear(s->j);
    s->collapses++;
    lm_iheap_remove(&s->heap, b);
    refresh(s, a);
    uint32_t n = lm_mesh_vertex_neighbors(s->m, a, s->ring_a, RING_CAP);
    for (uint32_t i = 0; i < n && i < RING_CAP; i++)
        refresh(s, s->ring_a[i]);
    return st;
}

static lm_status loop(adapt *s, uint32_t stop)
{
    lm_status st = LM_OK;
    while (!st && lm_iheap_count(&s->heap) && (!stop || s->m->live_verts > stop)) {
        uint32_t b = lm_iheap_top(&s->heap), a = 0;
        int64_t key = s->heap.key[b].prio;
        lm_iheap_remove(&s->heap, b);
        double w = 0;
        size_t mark = lm_journal_mark(s->j);
        if (!s->m->vert_alive[b] || !best_passing(s, b, &a, &w))
            continue;
        int64_t p = prio_of(s, w);
        uint32_t next = lm_iheap_top(&s->heap);
        if (p == key || next == LM_IHEAP_OUT || p <= s->heap.key[next].prio) {
            st = commit(s, b, a);
        } else { /* not the least optimal any more: back in at its true key */
            lm_journal_rollback(s->m, s->j, mark);
            lm_iheap_set(&s->heap, b, p, b);
        }
    }
    return st;
}

/* The live triangles of m as a compact mesh, every part of the original kept. */
static lm_status output(const adapt_base *base, const lm_mesh *m, lm_mesh **out)
{
    lm_status s = co_simplify_copy_live(m, out);
    uint32_t kept = 0;
    if (!s)
        s = co_simplify_keep_parts(base->mesh, *out, &kept);
    return s;
}

/* One pass at tolerance e_frac (of the diagonal), stopping at `stop` vertices (0: none). */
static lm_status pass(const adapt_base *base, double e_frac, uint32_t stop, co_adapt_stats *st,
                      lm_mesh **out)
{
    adapt *s = calloc(1, sizeof *s);
    if (!s)
        return lm_fail(LM_E_NOMEM, "out of memory simplifying");
    *out = NULL;
    s->base = base;
    s->e = e_frac * base->diag;
    s->e2 = (CO_ADAPT_CHECK_SHARE * s->e) * (CO_ADAPT_CHECK_SHARE * s->e);
    s->f2 = (CO_ADAPT_FEATURE_SHARE * s->e) * (CO_ADAPT_FEATURE_SHARE * s->e);
    s->cos_max = cos(CO_ADAPT_FEATURE_DEG * 3.14159265358979323846 / 180.0);
    lm_iheap_init(&s->heap);
    lm_status r = lm_mesh_clone(base->mesh, &s->m);
    if (!r)
        r = lm_mesh_build_adjacency(s->m);
    if (!r)
        r = lm_journal_create(&s->j);
    if (!r) {
        s->own = calloc((size_t)s->m->n_verts + 1, sizeof *s->own);
        if (!s->own || !lm_iheap_reserve(&s->heap, s->m->n_verts))
            r = lm_fail(LM_E_NOMEM, "out of memory simplifying");
    }
    for (uint32_t p = base->mesh->n_verts; !r && p < base->n_pts; p++)
        r = own_add(&s->own[base->owner[p]], p);
    for (uint32_t v = 0; !r && v < s->m->n_verts; v++)
        refresh(s, v);
    if (!r)
        r = loop(s, stop);
    if (!r)
        r = output(base, s->m, out);
    if (st) {
        st->tolerance = e_frac;
        st->runs++;
        st->collapses = s->collapses;
        st->refused = s->refused;
    }
    for (uint32_t v = 0; s->own && v < s->m->n_verts; v++)
        free(s->own[v].ids);
    free(s->own);
    lm_iheap_free(&s->heap);
    lm_journal_destroy(s->j);
    lm_mesh_destroy(s->m);
    free(s);
    return r;
}

static void base_free(adapt_base *b)
{
    lm_bvh_destroy(b->bvh);
    free(b->pts);
    free(b->owner);
    free(b->sharp);
    free(b->nrm);
    free(b->cls);
    lm_mesh_destroy(b->mesh);
}

static void add_point(adapt_base *b, uint32_t owner, const uint32_t *v, int n, int sharp)
{
    b->sharp[b->n_pts] = (uint8_t)sharp;
    double *p = b->pts[b->n_pts];
    for (int k = 0; k < 3; k++) {
        double sum = 0;
        for (int i = 0; i < n; i++)
            sum += b->mesh->pos[v[i]][k];
        p[k] = sum / n;
    }
    b->owner[b->n_pts++] = owner;
}

/* The tolerance's points: vertices, then centroids (held by their least vertex), then edge
 * midpoints (held by the edge's first vertex). */
static lm_status base_points(adapt_base *b)
{
    const lm_mesh *m = b->mesh;
    uint32_t(*e)[2] = NULL;
    size_t ne = 0;
    lm_status s = lm_mesh_list_edges(m, &e, &ne);
    if (s)
        return s;
    size_t n = (size_t)m->n_verts + m->n_tris + ne;
    b->pts = malloc((n + 1) * sizeof *b->pts);
    b->owner = malloc((n + 1) * sizeof *b->owner);
    b->sharp = malloc(n + 1);
    if (!b->pts || !b->owner || !b->sharp || n > UINT32_MAX) {
        free(e);
        return lm_fail(LM_E_NOMEM, "out of memory simplifying");
    }
    for (uint32_t v = 0; v < m->n_verts; v++)
        add_point(b, v, &v, 1, b->cls[v] != CO_ADAPT_SMOOTH);
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        uint32_t c[3];
        for (int k = 0; k < 3; k++)
            c[k] = m->wedges[m->tris[t].w[k]].vertex;
        uint32_t lo = c[0] < c[1] ? c[0] : c[1];
        add_point(b, lo < c[2] ? lo : c[2], c, 3, 0);
    }
    double cos_max = cos(CO_ADAPT_FEATURE_DEG * 3.14159265358979323846 / 180.0);
    for (size_t i = 0; i < ne; i++)
        add_point(b, e[i][0], e[i], 2, co_adapt_is_feature_edge(m, e[i][0], e[i][1], cos_max));
    free(e);
    return LM_OK;
}

static lm_status base_make(const lm_mesh *in, adapt_base *b)
{
    memset(b, 0, sizeof *b);
    lm_status s = lm_mesh_clone(in, &b->mesh);
    if (!s)
        s = lm_mesh_build_adjacency(b->mesh);
    if (s)
        return s;
    b->nrm = malloc(((size_t)in->n_verts + 1) * sizeof *b->nrm);
    b->cls = malloc((size_t)in->n_verts + 1);
    if (!b->nrm || !b->cls)
        return lm_fail(LM_E_NOMEM, "out of memory simplifying");
    co_adapt_vertex_normals(b->mesh, b->nrm);
    s = co_adapt_vertex_classes(b->mesh, cos(CO_ADAPT_FEATURE_DEG * 3.14159265358979323846 / 180.0),
                                b->cls);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < in->n_verts; v++)
        for (int k = 0; k < 3 && in->vert_alive[v]; k++) {
            lo[k] = in->pos[v][k] < lo[k] ? in->pos[v][k] : lo[k];
            hi[k] = in->pos[v][k] > hi[k] ? in->pos[v][k] : hi[k];
        }
    double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    b->diag = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!s && !(b->diag > 0))
        s = lm_fail(LM_E_INVALID, "the model has no extent (every vertex at one point)");
    if (!s)
        s = lm_bvh_create(b->mesh, &b->bvh);
    return s ? s : base_points(b);
}

/* Vertices left by a pass at tolerance e (no stop). */
static lm_status count_at(const adapt_base *b, double e, co_adapt_stats *st, uint32_t *n)
{
    lm_mesh *m = NULL;
    lm_status s = pass(b, e, 0, st, &m);
    *n = m ? m->live_verts : 0;
    lm_mesh_destroy(m);
    return s;
}

/* The --target-verts search: the least tolerance (within the bisection) that reaches target. */
static lm_status search(adapt_base *b, uint32_t target, co_adapt_stats *st, lm_mesh **out)
{
    double lo = 0, hi = CO_ADAPT_SEARCH_START;
    uint32_t n = 0, most = 0;
    lm_status s = count_at(b, hi, st, &n);
    if (!s && n > target) /* can the features' rules reach the target at all? */
        s = count_at(b, CO_ADAPT_SEARCH_MAX, st, &most);
    if (!s && n > target && most > target) { /* no: features held by the tolerance alone */
        b->soft = 1;
        if (st)
            st->soft_features = 1;
        s = count_at(b, hi, st, &n);
    }
    while (!s && n > target && hi < CO_ADAPT_SEARCH_MAX) { /* too many: a larger tolerance */
        lo = hi;
        hi = 2 * hi < CO_ADAPT_SEARCH_MAX ? 2 * hi : CO_ADAPT_SEARCH_MAX;
        s = count_at(b, hi, st, &n);
    }
    if (!s && n > target) {
        s = pass(b, hi, target, st, out);
        if (!s)
            s = lm_fail(LM_E_RANGE,
                        "no legal collapse is left at %u vertices (closed parts and "
                        "folds stop the adaptive method)",
                        (*out)->live_verts);
        return s;
    }
    while (!s && lo == 0 && hi > CO_ADAPT_SEARCH_MIN) { /* reached: find where it stops doing so */
        s = count_at(b, hi / 2, st, &n);
        if (n > target)
            lo = hi / 2;
        else
            hi /= 2;
    }
    for (int i = 0; !s && lo > 0 && i < CO_ADAPT_SEARCH_STEPS; i++) {
        double mid = sqrt(lo * hi);
        s = count_at(b, mid, st, &n);
        if (n > target)
            lo = mid;
        else
            hi = mid;
    }
    return s ? s : pass(b, hi, target, st, out);
}

lm_status co_simplify_adaptive(const lm_mesh *in, double tolerance, uint32_t target_verts,
                               co_adapt_stats *stats, lm_mesh **out)
{
    *out = NULL;
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (!(tolerance >= 0) || (tolerance == 0 && target_verts < 4))
        return lm_fail(LM_E_INVALID, "co_simplify_adaptive: a tolerance > 0 or a target of at "
                                     "least 4 vertices is needed");
    adapt_base b;
    lm_status s = base_make(in, &b);
    if (!s)
        s = tolerance > 0 ? pass(&b, tolerance, 0, stats, out)
                          : search(&b, target_verts, stats, out);
    base_free(&b);
    if (s && s != LM_E_RANGE) {
        lm_mesh_destroy(*out);
        *out = NULL;
    }
    return s;
}
