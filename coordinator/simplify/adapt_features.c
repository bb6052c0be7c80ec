/* coordinator/simplify/adapt_features.c — feature edges (dihedral angle, boundaries, seams,
 * material and part borders) and the vertex classes built on them (see adapt_features.h). */
#include "coordinator/simplify/adapt_features.h"

#include <math.h>
#include <stdlib.h>

#include "common/mesh_topology.h"
#include "coordinator/simplify/adapt_curvature.h"

static void unit_normal(const lm_mesh *m, uint32_t t, double n[3])
{
    co_adapt_tri_cross(m, t, n);
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int i = 0; i < 3 && len > 0; i++)
        n[i] /= len;
}

int co_adapt_is_feature_edge(const lm_mesh *m, uint32_t a, uint32_t b, double cos_max)
{
    uint32_t t[3];
    uint32_t n = lm_mesh_edge_tris(m, a, b, t, 3);
    if (n != 2)
        return 1; /* boundary or non-manifold */
    if (m->tris[t[0]].material != m->tris[t[1]].material ||
        m->tris[t[0]].part != m->tris[t[1]].part || lm_mesh_edge_is_attr_seam(m, a, b))
        return 1;
    double n0[3], n1[3];
    unit_normal(m, t[0], n0);
    unit_normal(m, t[1], n1);
    return n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2] < cos_max;
}

lm_status co_adapt_vertex_classes(const lm_mesh *m, double cos_max, uint8_t *out)
{
    uint32_t cap = 64, *nb = malloc(cap * sizeof *nb);
    if (!nb)
        return lm_fail(LM_E_NOMEM, "out of memory classifying vertices");
    for (uint32_t v = 0; v < m->n_verts; v++) {
        out[v] = CO_ADAPT_SMOOTH;
        if (!m->vert_alive[v])
            continue;
        uint32_t k = lm_mesh_vertex_neighbors(m, v, nb, cap);
        if (k > cap) {
            uint32_t *g = realloc(nb, (size_t)k * sizeof *nb);
            if (!g) {
                free(nb);
                return lm_fail(LM_E_NOMEM, "out of memory classifying vertices");
            }
            nb = g;
            cap = k;
            k = lm_mesh_vertex_neighbors(m, v, nb, cap);
        }
        uint32_t f = 0;
        for (uint32_t i = 0; i < k; i++)
            f += (uint32_t)co_adapt_is_feature_edge(m, v, nb[i], cos_max);
        out[v] = f == 0 ? CO_ADAPT_SMOOTH : f == 2 ? CO_ADAPT_LINE : CO_ADAPT_CORNER;
    }
    free(nb);
    return LM_OK;
}
