/* coordinator/simplify/adapt_curvature.c — vertex normals and the directional curvature along an
 * edge for the shape-adaptive simplifier (see adapt_curvature.h). */
#include "coordinator/simplify/adapt_curvature.h"

#include <math.h>
#include <string.h>

void co_adapt_tri_cross(const lm_mesh *m, uint32_t t, double n[3])
{
    const float *p[3];
    for (int k = 0; k < 3; k++)
        p[k] = m->pos[m->wedges[m->tris[t].w[k]].vertex];
    double u[3], v[3];
    for (int i = 0; i < 3; i++) {
        u[i] = (double)p[1][i] - (double)p[0][i];
        v[i] = (double)p[2][i] - (double)p[0][i];
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

void co_adapt_vertex_normals(const lm_mesh *m, double (*out)[3])
{
    memset(out, 0, (size_t)m->n_verts * sizeof *out);
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        double n[3];
        co_adapt_tri_cross(m, t, n); /* |n| = twice the area: area weighting */
        for (int k = 0; k < 3; k++) {
            double *o = out[m->wedges[m->tris[t].w[k]].vertex];
            o[0] += n[0];
            o[1] += n[1];
            o[2] += n[2];
        }
    }
    for (uint32_t v = 0; v < m->n_verts; v++) {
        double *o = out[v], len = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
        if (len > 0) {
            o[0] /= len;
            o[1] /= len;
            o[2] /= len;
        }
    }
}

double co_adapt_edge_curvature(const double a[3], const double na[3], const double b[3],
                               const double nb[3])
{
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (len2 <= 0)
        return 0;
    double ha = fabs(na[0] * d[0] + na[1] * d[1] + na[2] * d[2]);
    double hb = fabs(nb[0] * d[0] + nb[1] * d[1] + nb[2] * d[2]);
    return (ha + hb) / len2; /* mean of 2 h / L^2 at both ends */
}
