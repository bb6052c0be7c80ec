/* coordinator/cli/bench_moves.c — random single-vertex moves with their 1-ring patches (the
 * downhill simplex's typical evaluation) for `lumesh bench eval`. */
#include "coordinator/cli/bench_moves.h"

#include <math.h>

#include "common/mesh_topology.h"

#define RING_CAP 256

static uint64_t next_u64(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

static float signed_unit(uint64_t *s)
{
    return (float)((double)(next_u64(s) >> 11) / 4503599627370496.0 - 1.0);
}

static float mean_edge(const lm_mesh *m)
{
    double sum = 0;
    size_t n = 0;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        for (int k = 0; k < 3; k++) {
            const float *a = m->pos[lm_tri_vertex(m, t, k)],
                        *b = m->pos[lm_tri_vertex(m, t, (k + 1) % 3)];
            sum +=
                sqrt((double)(a[0] - b[0]) * (a[0] - b[0]) + (double)(a[1] - b[1]) * (a[1] - b[1]) +
                     (double)(a[2] - b[2]) * (a[2] - b[2]));
            n++;
        }
    }
    return n ? (float)(sum / n) : 1.0f;
}

/* One move of vertex v by d: removed = ring, added = ring with v's corners displaced. */
static lm_status vertex_patch(const lm_mesh *m, uint32_t v, const float d[3], lm_patch *p)
{
    uint32_t ring[RING_CAP];
    uint32_t n = lm_mesh_vertex_tris(m, v, ring, RING_CAP);
    if (n > RING_CAP)
        n = RING_CAP;
    lm_status st = lm_patch_build(p, m, ring, n, ring, n);
    for (uint32_t i = 0; st == LM_OK && i < p->n_added; i++)
        for (int k = 0; k < 3; k++)
            if (lm_tri_vertex(m, p->added[i].id, k) == v)
                for (int a = 0; a < 3; a++)
                    p->added[i].c[k].pos[a] += d[a];
    return st;
}

lm_status co_bench_vertex_moves(const lm_mesh *m, uint64_t seed, lm_patch *out, uint32_t n)
{
    if (m->live_tris == 0)
        return lm_fail(LM_E_INVALID, "the benchmark mesh has no triangles");
    uint64_t s = seed * 0x9E3779B97F4A7C15ull + 0x2545F4914F6CDD1Dull;
    float step = mean_edge(m) / 3.0f;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t v;
        do
            v = (uint32_t)(next_u64(&s) % m->n_verts);
        while (!m->vert_alive[v] || lm_mesh_vertex_tris(m, v, NULL, 0) == 0);
        float d[3] = {step * signed_unit(&s), step * signed_unit(&s), step * signed_unit(&s)};
        lm_status st = vertex_patch(m, v, d, &out[i]);
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}
