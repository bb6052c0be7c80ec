/* common/tangents.c — per-triangle UV-derivative frames, their accumulation per wedge and the
 * Gram–Schmidt step to the normal (see tangents.h). */
#include "common/tangents.h"

#include <math.h>
#include <stdlib.h>

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* v scaled to unit length; 0 (and v zeroed) where it is zero or not finite. */
static int unit3(double v[3])
{
    double len = sqrt(dot3(v, v));
    if (!(len > 1e-30) || !isfinite(len)) {
        v[0] = v[1] = v[2] = 0.0;
        return 0;
    }
    for (int k = 0; k < 3; k++)
        v[k] /= len;
    return 1;
}

void lm_tri_tangent_frame(const float p[3][3], const float uv[3][2], double t[3], double b[3])
{
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)p[1][k] - p[0][k];
        e2[k] = (double)p[2][k] - p[0][k];
    }
    double du1 = (double)uv[1][0] - uv[0][0], dv1 = (double)uv[1][1] - uv[0][1];
    double du2 = (double)uv[2][0] - uv[0][0], dv2 = (double)uv[2][1] - uv[0][1];
    double r = du1 * dv2 - du2 * dv1;
    for (int k = 0; k < 3; k++) { /* divided by r: only its sign matters once made unit */
        t[k] = r < 0.0 ? e2[k] * dv1 - e1[k] * dv2 : e1[k] * dv2 - e2[k] * dv1;
        b[k] = r < 0.0 ? e1[k] * du2 - e2[k] * du1 : e2[k] * du1 - e1[k] * du2;
    }
    if (r == 0.0 || !isfinite(r) || !unit3(t) || !unit3(b))
        t[0] = t[1] = t[2] = b[0] = b[1] = b[2] = 0.0;
}

/* A fixed unit vector orthogonal to unit n: the axis least along n, made orthogonal. */
static void any_orthogonal(const double n[3], double out[3])
{
    int a = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0
            : fabs(n[1]) <= fabs(n[2])                           ? 1
                                                                 : 2;
    double axis[3] = {0, 0, 0};
    axis[a] = 1.0;
    for (int k = 0; k < 3; k++)
        out[k] = axis[k] - n[k] * n[a];
    if (!unit3(out))
        out[0] = 1.0;
}

/* Unit normal nn, unit tangent tt orthogonal to it, handedness (±1) of b against nn × tt. */
static double orthogonal(const float n[3], const double t[3], const double b[3], double nn[3],
                         double tt[3])
{
    nn[0] = n[0], nn[1] = n[1], nn[2] = n[2];
    if (!unit3(nn))
        nn[2] = 1.0;
    double d = dot3(nn, t);
    for (int k = 0; k < 3; k++)
        tt[k] = t[k] - nn[k] * d;
    if (!(dot3(tt, tt) > 1e-12) || !unit3(tt))
        any_orthogonal(nn, tt);
    double c[3];
    cross3(nn, tt, c);
    return dot3(c, b) < 0.0 ? -1.0 : 1.0;
}

void lm_tangent_orthogonal(const float n[3], const double t[3], const double b[3], float out[4])
{
    double nn[3], tt[3];
    out[3] = (float)orthogonal(n, t, b, nn, tt);
    for (int k = 0; k < 3; k++)
        out[k] = (float)tt[k];
}

void lm_tangent_basis(const float n[3], const double t[3], const double b[3], double out[9])
{
    double nn[3], tt[3], c[3];
    double w = orthogonal(n, t, b, nn, tt);
    cross3(nn, tt, c);
    for (int k = 0; k < 3; k++) {
        out[k] = tt[k];
        out[3 + k] = w * c[k];
        out[6 + k] = nn[k];
    }
}

lm_status lm_mesh_tangents(const lm_mesh *m, float (**out)[4])
{
    double(*acc)[6] = calloc((size_t)m->n_wedges + 1, sizeof *acc);
    float(*tan)[4] = malloc(((size_t)m->n_wedges + 1) * sizeof *tan);
    if (!acc || !tan) {
        free(acc);
        free(tan);
        return lm_fail(LM_E_NOMEM, "out of memory for the tangents of %u wedges", m->n_wedges);
    }
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        float p[3][3], uv[3][2];
        for (int k = 0; k < 3; k++) {
            const lm_wedge *w = &m->wedges[m->tris[t].w[k]];
            for (int a = 0; a < 3; a++)
                p[k][a] = m->pos[w->vertex][a];
            uv[k][0] = w->uv[0], uv[k][1] = w->uv[1];
        }
        double ft[3], fb[3];
        lm_tri_tangent_frame(p, uv, ft, fb);
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 3; a++) {
                acc[m->tris[t].w[k]][a] += ft[a];
                acc[m->tris[t].w[k]][3 + a] += fb[a];
            }
    }
    for (uint32_t w = 0; w < m->n_wedges; w++)
        lm_tangent_orthogonal(m->wedges[w].normal, acc[w], acc[w] + 3, tan[w]);
    free(acc);
    *out = tan;
    return LM_OK;
}
