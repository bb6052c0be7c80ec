/* coordinator/simplify/placement.c — the collapse placements: endpoints, midpoint, and the
 * minimum of the memoryless quadric (solved in double; a singular system or a point far from the
 * edge falls back to the best point of the segment). */
#include "coordinator/simplify/placement.h"

#include <math.h>
#include <string.h>

#include "common/mesh_topology.h"

#define CO_PLACE_MAX_TRIS 512    /* triangles around an edge the quadric looks at */
#define CO_PLACE_BORDER_WEIGHT 1 /* weight of a border's perpendicular plane (x edge length²) */
#define CO_PLACE_REACH 1.0       /* the quadric's point may lie this many edge lengths away */

typedef struct quadric {
    double a[6]; /* xx xy xz yy yz zz */
    double b[3];
    double c;
} quadric;

static void q_add_plane(quadric *q, const double n[3], double d, double w)
{
    q->a[0] += w * n[0] * n[0], q->a[1] += w * n[0] * n[1], q->a[2] += w * n[0] * n[2];
    q->a[3] += w * n[1] * n[1], q->a[4] += w * n[1] * n[2], q->a[5] += w * n[2] * n[2];
    for (int k = 0; k < 3; k++)
        q->b[k] += w * d * n[k];
    q->c += w * d * d;
}

static double q_eval(const quadric *q, const double p[3])
{
    const double *a = q->a;
    double v = a[0] * p[0] * p[0] + a[3] * p[1] * p[1] + a[5] * p[2] * p[2] +
               2 * (a[1] * p[0] * p[1] + a[2] * p[0] * p[2] + a[4] * p[1] * p[2]);
    return v + 2 * (q->b[0] * p[0] + q->b[1] * p[1] + q->b[2] * p[2]) + q->c;
}

static void sub3(const float *x, const float *y, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (double)x[k] - y[k];
}

static void cross3(const double u[3], const double w[3], double out[3])
{
    out[0] = u[1] * w[2] - u[2] * w[1];
    out[1] = u[2] * w[0] - u[0] * w[2];
    out[2] = u[0] * w[1] - u[1] * w[0];
}

/* The plane of triangle t (area weighted), and a perpendicular plane on each border edge. */
static void q_add_tri(quadric *q, const lm_mesh *m, uint32_t t)
{
    uint32_t v[3];
    for (int k = 0; k < 3; k++)
        v[k] = lm_tri_vertex(m, t, k);
    double u[3], w[3], n[3];
    sub3(m->pos[v[1]], m->pos[v[0]], u);
    sub3(m->pos[v[2]], m->pos[v[0]], w);
    cross3(u, w, n);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0))
        return;
    for (int k = 0; k < 3; k++)
        n[k] /= len;
    const float *p0 = m->pos[v[0]];
    q_add_plane(q, n, -(n[0] * p0[0] + n[1] * p0[1] + n[2] * p0[2]), 0.5 * len);
    for (int k = 0; k < 3; k++) {
        uint32_t x = v[k], y = v[(k + 1) % 3];
        if (!lm_mesh_edge_is_boundary(m, x, y))
            continue;
        double e[3], pn[3];
        sub3(m->pos[y], m->pos[x], e);
        cross3(e, n, pn);
        double pl = sqrt(pn[0] * pn[0] + pn[1] * pn[1] + pn[2] * pn[2]);
        if (!(pl > 0))
            continue;
        for (int d = 0; d < 3; d++)
            pn[d] /= pl;
        const float *px = m->pos[x];
        q_add_plane(q, pn, -(pn[0] * px[0] + pn[1] * px[1] + pn[2] * px[2]),
                    CO_PLACE_BORDER_WEIGHT * pl * pl);
    }
}

static void edge_quadric(const lm_mesh *m, uint32_t a, uint32_t b, quadric *q)
{
    memset(q, 0, sizeof *q);
    uint32_t ta[CO_PLACE_MAX_TRIS], tb[CO_PLACE_MAX_TRIS];
    uint32_t na = lm_mesh_vertex_tris(m, a, ta, CO_PLACE_MAX_TRIS);
    uint32_t nb = lm_mesh_vertex_tris(m, b, tb, CO_PLACE_MAX_TRIS);
    na = na < CO_PLACE_MAX_TRIS ? na : CO_PLACE_MAX_TRIS;
    nb = nb < CO_PLACE_MAX_TRIS ? nb : CO_PLACE_MAX_TRIS;
    for (uint32_t i = 0; i < na; i++)
        q_add_tri(q, m, ta[i]);
    for (uint32_t i = 0; i < nb; i++) {
        int shared = 0;
        for (int k = 0; k < 3; k++)
            shared |= lm_tri_vertex(m, tb[i], k) == a;
        if (!shared)
            q_add_tri(q, m, tb[i]);
    }
}

/* Solve A p = -b (Cramer); 0 when the system is too close to singular. */
static int q_solve(const quadric *q, double p[3])
{
    const double *a = q->a;
    double m[3][3] = {{a[0], a[1], a[2]}, {a[1], a[3], a[4]}, {a[2], a[4], a[5]}};
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double scale = fabs(a[0]) + fabs(a[3]) + fabs(a[5]);
    if (!(fabs(det) > 1e-9 * scale * scale * scale))
        return 0;
    for (int c = 0; c < 3; c++) {
        double t[3][3];
        memcpy(t, m, sizeof t);
        for (int r = 0; r < 3; r++)
            t[r][c] = -q->b[r];
        p[c] = (t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1]) -
                t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0]) +
                t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0])) /
               det;
    }
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

/* Parameter of p's projection onto segment ab, clamped to [0, 1]. */
static double seg_param(const float *a, const float *b, const double p[3])
{
    double e[3], d[3], ee = 0, ed = 0;
    for (int k = 0; k < 3; k++) {
        e[k] = (double)b[k] - a[k];
        d[k] = p[k] - a[k];
        ee += e[k] * e[k];
        ed += e[k] * d[k];
    }
    double t = ee > 0 ? ed / ee : 0.5;
    return t < 0 ? 0 : t > 1 ? 1 : t;
}

/* The best point of the segment under the quadric (a quadratic in t). */
static double seg_best(const quadric *q, const float *a, const float *b)
{
    double pa[3], pb[3], pm[3];
    for (int k = 0; k < 3; k++) {
        pa[k] = a[k], pb[k] = b[k];
        pm[k] = 0.5 * ((double)a[k] + b[k]);
    }
    double f0 = q_eval(q, pa), f1 = q_eval(q, pb), fm = q_eval(q, pm);
    double c2 = 2 * f0 + 2 * f1 - 4 * fm, c1 = -3 * f0 - f1 + 4 * fm;
    double t = c2 > 0 ? -c1 / (2 * c2) : (f0 <= f1 ? 0 : 1);
    return t < 0 ? 0 : t > 1 ? 1 : t;
}

static void qem_place(const lm_mesh *m, uint32_t a, uint32_t b, co_place *out)
{
    quadric q;
    edge_quadric(m, a, b, &q);
    const float *pa = m->pos[a], *pb = m->pos[b];
    double p[3], len2 = 0;
    for (int k = 0; k < 3; k++)
        len2 += ((double)pb[k] - pa[k]) * ((double)pb[k] - pa[k]);
    int ok = q_solve(&q, p);
    if (ok) {
        double d2 = 0;
        for (int k = 0; k < 3; k++)
            d2 += (p[k] - 0.5 * ((double)pa[k] + pb[k])) * (p[k] - 0.5 * ((double)pa[k] + pb[k]));
        ok = d2 <= CO_PLACE_REACH * CO_PLACE_REACH * len2;
    }
    double t;
    if (ok) {
        t = seg_param(pa, pb, p);
    } else {
        t = seg_best(&q, pa, pb);
        for (int k = 0; k < 3; k++)
            p[k] = (double)pa[k] + t * ((double)pb[k] - pa[k]);
    }
    for (int k = 0; k < 3; k++)
        out->pos[k] = (float)p[k];
    out->t = (float)t;
    /* a point the other candidates already try is not tried twice */
    out->valid = memcmp(out->pos, pa, sizeof out->pos) && memcmp(out->pos, pb, sizeof out->pos);
}

void co_place_all(const lm_mesh *m, uint32_t a, uint32_t b, co_place out[CO_PLACE_KINDS])
{
    for (int k = 0; k < CO_PLACE_KINDS; k++)
        out[k] = (co_place){.kind = (co_place_kind)k, .valid = 1, .keep = a, .drop = b};
    memcpy(out[CO_PLACE_KEEP_A].pos, m->pos[a], sizeof out[0].pos);
    out[CO_PLACE_KEEP_B].keep = b;
    out[CO_PLACE_KEEP_B].drop = a;
    memcpy(out[CO_PLACE_KEEP_B].pos, m->pos[b], sizeof out[0].pos);
    for (int k = 0; k < 3; k++)
        out[CO_PLACE_MID].pos[k] = 0.5f * (m->pos[a][k] + m->pos[b][k]);
    out[CO_PLACE_MID].t = 0.5f;
    qem_place(m, a, b, &out[CO_PLACE_QEM]);
    if (!memcmp(out[CO_PLACE_QEM].pos, out[CO_PLACE_MID].pos, sizeof out[0].pos))
        out[CO_PLACE_QEM].valid = 0;
}

const char *co_place_name(co_place_kind k)
{
    static const char *const names[CO_PLACE_KINDS] = {"keep_a", "keep_b", "mid", "qem"};
    return (unsigned)k < CO_PLACE_KINDS ? names[k] : "?";
}
