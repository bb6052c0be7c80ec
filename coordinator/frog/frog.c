/* coordinator/frog/frog.c — geometry of the procedural frog (see frog.h): seven closed generalised
 * cylinders ("parts") swept along Catmull–Rom spines with elliptical cross-sections and rounded
 * end caps that close into poles. Rings are spaced evenly along the meridian (arc length of the
 * profile), so a sphere gets even latitudes and a leg even segments; the triangle budget of each
 * part is split between rings and segments in proportion to its length and girth. */
#include "coordinator/frog/frog.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh_topology.h"
#include "coordinator/frog/frog_internal.h"

#define MAX_CTRL 6
#define PROFILE_SAMPLES 4096
#define MIN_AROUND 8
#define MIN_RINGS 3

typedef struct ctrl {
    double p[3];
    double a, b; /* half-widths of the cross-section: sideways and up */
} ctrl;

typedef struct part {
    int n;
    ctrl c[MAX_CTRL];
    double cap0, cap1; /* fractions of the spine parameter rounded into end caps */
    int chart;
    double share; /* of the triangle budget */
    /* planned */
    double *prof; /* [PROFILE_SAMPLES + 1] meridian arc length at v = k / PROFILE_SAMPLES */
    uint32_t around, rings; /* vertices per ring, rings between the poles */
} part;

/* The seven parts, left-side legs and eyes (z > 0); the right ones are mirrored. */
static const part BODY = {.n = 5,
                          .c = {{{-0.95, 0.42, 0}, 0.50, 0.36},
                                {{-0.45, 0.48, 0}, 0.62, 0.42},
                                {{0.15, 0.55, 0}, 0.60, 0.40},
                                {{0.65, 0.60, 0}, 0.50, 0.31},
                                {{1.05, 0.60, 0}, 0.36, 0.20}},
                          .cap0 = 0.20,
                          .cap1 = 0.22,
                          .chart = CO_FROG_CHART_BODY,
                          .share = 0.40};
static const part HIND_LEG = {.n = 5,
                              .c = {{{-0.55, 0.35, 0.35}, 0.20, 0.20},
                                    {{-0.02, 0.30, 0.90}, 0.13, 0.13},
                                    {{-0.66, 0.11, 0.95}, 0.08, 0.08},
                                    {{-0.52, 0.045, 1.07}, 0.10, 0.04},
                                    {{-0.06, 0.03, 1.30}, 0.17, 0.025}},
                              .cap0 = 0.08,
                              .cap1 = 0.06,
                              .chart = CO_FROG_CHART_LEGS,
                              .share = 0.16};
static const part FRONT_LEG = {.n = 4,
                               .c = {{{0.45, 0.35, 0.25}, 0.11, 0.11},
                                     {{0.50, 0.22, 0.56}, 0.08, 0.08},
                                     {{0.70, 0.065, 0.61}, 0.055, 0.055},
                                     {{0.98, 0.025, 0.73}, 0.11, 0.022}},
                               .cap0 = 0.10,
                               .cap1 = 0.08,
                               .chart = CO_FROG_CHART_LEGS,
                               .share = 0.09};

/* An eye: a sphere of radius r around centre, its end pole (the pupil) looking along dir. */
static part eye_part(const double centre[3], double r, const double dir[3])
{
    part e = {.n = 2, .cap0 = 0.5, .cap1 = 0.5, .chart = CO_FROG_CHART_EYES, .share = 0.05};
    e.c[0].a = e.c[0].b = e.c[1].a = e.c[1].b = r;
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (int k = 0; k < 3; k++) {
        e.c[0].p[k] = centre[k] - r * dir[k] / len;
        e.c[1].p[k] = centre[k] + r * dir[k] / len;
    }
    return e;
}

static void jitter(part *p, co_frog_rng *r, int mirror)
{
    for (int i = 0; i < p->n; i++) {
        for (int k = 0; k < 3; k++)
            p->c[i].p[k] += co_frog_uniform(r, -0.015, 0.015);
        if (mirror)
            p->c[i].p[2] = -p->c[i].p[2];
        double g = co_frog_uniform(r, 0.95, 1.05);
        p->c[i].a *= g;
        p->c[i].b *= g;
    }
}

/* Body, hind legs, front legs, eyes — with the seed's small jitter. */
static void make_parts(uint64_t seed, part parts[CO_FROG_PARTS])
{
    co_frog_rng r = {seed};
    parts[0] = BODY;
    parts[1] = parts[2] = HIND_LEG;
    parts[3] = parts[4] = FRONT_LEG;
    double r_eye = co_frog_uniform(&r, 0.155, 0.17);
    for (int side = 0; side < 2; side++) {
        double z = side ? -1 : 1;
        double c[3] = {0.60, 0.93, 0.26 * z}, dir[3] = {0.45, 0.4, 0.8 * z};
        parts[5 + side] = eye_part(c, r_eye, dir);
    }
    jitter(&parts[0], &r, 0);
    for (int i = 1; i < 5; i++)
        jitter(&parts[i], &r, (i & 1) == 0);
}

/* ---- the swept surface ----------------------------------------------------------------------- */

static double catmull_rom(double p0, double p1, double p2, double p3, double u)
{
    return 0.5 * (2 * p1 + (p2 - p0) * u + (2 * p0 - 5 * p1 + 4 * p2 - p3) * u * u +
                  (3 * p1 - p0 - 3 * p2 + p3) * u * u * u);
}

/* Spine point and cross-section half-widths at v in [0, 1] (before the end caps). Phantom end
 * points are extrapolated, so a two-point spine is a straight, evenly paced segment. */
static ctrl spine(const part *p, double v)
{
    int segs = p->n - 1;
    double t = v * segs;
    int i = t < 0 ? 0 : (int)t >= segs ? segs - 1 : (int)t;
    double u = t - i, h = u * u * (3 - 2 * u);
    const ctrl *c1 = &p->c[i], *c2 = &p->c[i + 1];
    ctrl out = {{0}, c1->a + (c2->a - c1->a) * h, c1->b + (c2->b - c1->b) * h};
    for (int k = 0; k < 3; k++) {
        double p0 = i > 0 ? p->c[i - 1].p[k] : 2 * c1->p[k] - c2->p[k];
        double p3 = i + 2 < p->n ? p->c[i + 2].p[k] : 2 * c2->p[k] - c1->p[k];
        out.p[k] = catmull_rom(p0, c1->p[k], c2->p[k], p3, u);
    }
    return out;
}

/* Rounded end caps: the cross-section shrinks like a quarter ellipse to a point at each end. */
static double cap(const part *p, double v)
{
    double x = 1.0;
    if (v < p->cap0)
        x = v / p->cap0;
    else if (v > 1.0 - p->cap1)
        x = (1.0 - v) / p->cap1;
    x = x < 0 ? 0 : x;
    return sqrt(fmax(0.0, 1.0 - (1.0 - x) * (1.0 - x)));
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int k = 0; k < 3; k++)
        v[k] = l > 0 ? v[k] / l : 0;
}

/* Frame at v: side S = T x up, U = S x T (up-ish); c gets the capped centre and half-widths. */
static void frame(const part *p, double v, ctrl *c, double S[3], double U[3])
{
    double dv = 1e-4, v0 = fmax(0.0, v - dv), v1 = fmin(1.0, v + dv);
    ctrl a = spine(p, v0), b = spine(p, v1);
    double T[3] = {b.p[0] - a.p[0], b.p[1] - a.p[1], b.p[2] - a.p[2]};
    double up[3] = {0, 1, 0}, fx[3] = {1, 0, 0};
    normalize(T);
    cross(T, up, S);
    if (S[0] * S[0] + S[1] * S[1] + S[2] * S[2] < 1e-6)
        cross(T, fx, S);
    normalize(S);
    cross(S, T, U);
    *c = spine(p, v);
    double e = cap(p, v);
    c->a *= e;
    c->b *= e;
}

/* Point i of n around a ring with frame (c, S, U); i = 0 is the underside. */
static void ring_point(const ctrl *c, const double S[3], const double U[3], uint32_t i, uint32_t n,
                       float out[3])
{
    double th = -M_PI / 2 + 2 * M_PI * (double)i / n, cs = cos(th), sn = sin(th);
    for (int k = 0; k < 3; k++)
        out[k] = (float)(c->p[k] + c->a * cs * S[k] + c->b * sn * U[k]);
}

/* ---- planning: meridian arc length and the split of the budget ------------------------------- */

/* Fills p->prof; returns the mean girth (circumference) along the meridian. */
static double profile(part *p)
{
    double len = 0, girth = 0, prev_r = 0, prev[3];
    for (int k = 0; k <= PROFILE_SAMPLES; k++) {
        double v = (double)k / PROFILE_SAMPLES;
        ctrl c = spine(p, v);
        double r = 0.5 * (c.a + c.b) * cap(p, v);
        if (k > 0) {
            double d2 = (r - prev_r) * (r - prev_r);
            for (int i = 0; i < 3; i++)
                d2 += (c.p[i] - prev[i]) * (c.p[i] - prev[i]);
            double ds = sqrt(d2);
            len += ds;
            girth += 2 * M_PI * 0.5 * (r + prev_r) * ds;
        }
        p->prof[k] = len;
        prev_r = r;
        memcpy(prev, c.p, sizeof prev);
    }
    return len > 0 ? girth / len : 0;
}

/* The spine parameter where the meridian has run `frac` of its length. */
static double meridian_v(const part *p, double frac)
{
    double want = frac * p->prof[PROFILE_SAMPLES];
    uint32_t lo = 0, hi = PROFILE_SAMPLES;
    while (hi - lo > 1) {
        uint32_t mid = (lo + hi) / 2;
        if (p->prof[mid] < want)
            lo = mid;
        else
            hi = mid;
    }
    double span = p->prof[hi] - p->prof[lo], t = span > 0 ? (want - p->prof[lo]) / span : 0;
    return ((double)lo + t) / PROFILE_SAMPLES;
}

/* Vertices around and rings for `budget` triangles (2 * around * rings), cells about square. */
static void plan(part *p, double budget, double girth)
{
    double len = p->prof[PROFILE_SAMPLES];
    double around = sqrt(fmax(budget, 1.0) / 2 * girth / fmax(len, 1e-9));
    p->around = around < MIN_AROUND ? MIN_AROUND : (uint32_t)lround(around);
    double rings = budget / (2.0 * p->around);
    p->rings = rings < MIN_RINGS ? MIN_RINGS : (uint32_t)lround(rings);
}

/* Plan every part; the body (part 0) takes what the others leave so the total is on target. */
static void plan_all(part parts[CO_FROG_PARTS], uint32_t target)
{
    double girth[CO_FROG_PARTS], used = 0;
    for (int i = 0; i < CO_FROG_PARTS; i++)
        girth[i] = profile(&parts[i]);
    for (int i = 1; i < CO_FROG_PARTS; i++) {
        plan(&parts[i], parts[i].share * target, girth[i]);
        used += 2.0 * parts[i].around * parts[i].rings;
    }
    plan(&parts[0], parts[0].share * target, girth[0]);
    double rings = ((double)target - used) / (2.0 * parts[0].around);
    parts[0].rings = rings < MIN_RINGS ? MIN_RINGS : (uint32_t)lround(rings);
}

/* ---- emission ------------------------------------------------------------------------------ */

static lm_status add_wedge(lm_mesh *m, const part *p, uint32_t vertex, double s, double f)
{
    const float *c = co_frog_charts[p->chart];
    lm_wedge w = {.vertex = vertex, .normal = {0, 0, 1}, .color = {1, 1, 1, 1}};
    w.uv[0] = (float)(c[0] + (c[2] - c[0]) * s);
    w.uv[1] = (float)(c[1] + (c[3] - c[1]) * f);
    return lm_mesh_add_wedge(m, &w, NULL);
}

/* Poles and rings: vertex ids v0 + {0, 1 + (j-1)*n + i, 1 + R*n}; wedge ids w0 + {0 (start
 * pole), 1 + (j-1)*(n+1) + i (i = n repeats i = 0 with s = 1: the seam), 1 + R*(n+1) (end pole)}.
 * A pole has one wedge: with one per fan triangle, meshoptimizer sees every edge around the pole
 * as an attribute border and can never collapse the first ring, which caps simplification. */
static lm_status emit_points(lm_mesh *m, const part *p)
{
    uint32_t n = p->around, R = p->rings, v0 = m->n_verts;
    ctrl c = spine(p, 0);
    float q[3] = {(float)c.p[0], (float)c.p[1], (float)c.p[2]};
    lm_status s = lm_mesh_add_vertex(m, q, NULL);
    if (!s)
        s = add_wedge(m, p, v0, 0.5, 0.0);
    for (uint32_t j = 1; j <= R && !s; j++) {
        double f = (double)j / (R + 1), S[3], U[3];
        frame(p, meridian_v(p, f), &c, S, U);
        uint32_t first = m->n_verts;
        for (uint32_t i = 0; i < n && !s; i++) {
            ring_point(&c, S, U, i, n, q);
            s = lm_mesh_add_vertex(m, q, NULL);
        }
        for (uint32_t i = 0; i <= n && !s; i++)
            s = add_wedge(m, p, first + i % n, (double)i / n, f);
    }
    c = spine(p, 1);
    float e[3] = {(float)c.p[0], (float)c.p[1], (float)c.p[2]};
    uint32_t last = m->n_verts;
    if (!s)
        s = lm_mesh_add_vertex(m, e, NULL);
    if (!s)
        s = add_wedge(m, p, last, 0.5, 1.0);
    return s;
}

/* 1 when the ring order (i, i+1 around; j, j+1 along) faces inward and must be flipped. */
static int inward(const lm_mesh *m, const part *p, uint32_t v0)
{
    uint32_t n = p->around, j = p->rings / 2;
    const float *a = m->pos[v0 + 1 + (j - 1) * n], *b = m->pos[v0 + 1 + (j - 1) * n + 1];
    const float *c = m->pos[v0 + 1 + j * n + 1];
    double u[3], w[3], nn[3];
    for (int k = 0; k < 3; k++) {
        u[k] = (double)b[k] - a[k];
        w[k] = (double)c[k] - a[k];
    }
    cross(u, w, nn);
    ctrl centre = spine(p, meridian_v(p, (double)j / (p->rings + 1)));
    double d = 0;
    for (int k = 0; k < 3; k++)
        d += nn[k] * ((double)a[k] - centre.p[k]);
    return d < 0;
}

static lm_status tri(lm_mesh *m, uint32_t a, uint32_t b, uint32_t c, int flip)
{
    uint32_t w[3] = {a, flip ? c : b, flip ? b : c};
    return lm_mesh_add_tri(m, w, 0, NULL);
}

static lm_status emit_part(lm_mesh *m, const part *p)
{
    uint32_t n = p->around, R = p->rings, v0 = m->n_verts, w0 = m->n_wedges;
    lm_status s = emit_points(m, p);
    if (s)
        return s;
    int flip = inward(m, p, v0);
    uint32_t ring = w0 + 1, end = w0 + 1 + R * (n + 1); /* first wedge of ring 1, end pole */
    for (uint32_t i = 0; i < n && !s; i++)
        s = tri(m, w0, ring + i + 1, ring + i, flip);
    for (uint32_t j = 0; j + 1 < R && !s; j++) {
        uint32_t r0 = ring + j * (n + 1), r1 = r0 + n + 1;
        for (uint32_t i = 0; i < n && !s; i++) {
            s = tri(m, r0 + i, r0 + i + 1, r1 + i + 1, flip);
            if (!s)
                s = tri(m, r0 + i, r1 + i + 1, r1 + i, flip);
        }
    }
    uint32_t last = ring + (R - 1) * (n + 1);
    for (uint32_t i = 0; i < n && !s; i++)
        s = tri(m, last + i, last + i + 1, end, flip);
    return s;
}

/* Part i: its name, and its triangles (emitted from triangle t0 on) put in it. */
static lm_status name_part(lm_mesh *m, int i, uint32_t t0)
{
    static const char *const names[CO_FROG_PARTS] = {
        "body",     "hind_leg_left", "hind_leg_right", "front_leg_left", "front_leg_right",
        "eye_left", "eye_right"};
    uint32_t id;
    lm_status s = lm_mesh_add_part(m, names[i], &id);
    for (uint32_t t = t0; !s && t < m->n_tris; t++)
        m->tris[t].part = id;
    return s;
}

static lm_status add_skin(lm_mesh *m, uint64_t seed)
{
    lm_image *tex;
    lm_status s = co_frog_texture(seed, &tex);
    if (s)
        return s;
    static const float white[4] = {1, 1, 1, 1};
    s = lm_mesh_add_material(m, "frog_skin", white, "frog_skin.png", tex, NULL);
    if (s)
        lm_image_destroy(tex);
    return s;
}

lm_status co_frog_generate(uint32_t target_tris, uint64_t seed, lm_mesh **out)
{
    *out = NULL;
    if (target_tris < CO_FROG_MIN_TRIS || target_tris > CO_FROG_MAX_TRIS)
        return lm_fail(LM_E_RANGE, "frog triangle count %u is outside [%u, %u]", target_tris,
                       CO_FROG_MIN_TRIS, CO_FROG_MAX_TRIS);
    part parts[CO_FROG_PARTS];
    make_parts(seed, parts);
    double *prof = malloc((size_t)CO_FROG_PARTS * (PROFILE_SAMPLES + 1) * sizeof *prof);
    lm_mesh *m = NULL;
    lm_status s = prof ? lm_mesh_create(&m) : lm_fail(LM_E_NOMEM, "out of memory (frog)");
    for (int i = 0; i < CO_FROG_PARTS && prof; i++)
        parts[i].prof = prof + (size_t)i * (PROFILE_SAMPLES + 1);
    if (!s) {
        plan_all(parts, target_tris);
        m->attrs = LM_ATTR_NORMAL | LM_ATTR_UV;
        s = add_skin(m, seed);
    }
    for (int i = 0; i < CO_FROG_PARTS && !s; i++) {
        uint32_t t0 = m->n_tris;
        s = emit_part(m, &parts[i]);
        if (!s)
            s = name_part(m, i, t0);
    }
    free(prof);
    if (!s) {
        lm_mesh_compute_normals(m);
        s = lm_mesh_build_adjacency(m);
    }
    if (s) {
        lm_mesh_destroy(m);
        return s;
    }
    *out = m;
    return LM_OK;
}
