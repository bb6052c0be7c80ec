/* common/optimizer/move_params.c — the parameter vector of a vertex set (paper §5.1):
 * positions, then per wedge of those vertices the optimised attributes (normal xyz, uv, colour
 * rgb); initial simplex steps scaled to the local geometry and attribute ranges; writing a vector
 * back into the mesh with derived normals recomputed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/moves_internal.h"

static lm_status collect_wedges(lm_moves *mv)
{
    lm_idset_clear(&mv->W);
    if (!mv->wattrs)
        return LM_OK;
    const lm_mesh *m = mv->m;
    for (uint32_t i = 0; i < mv->V.n; i++) {
        uint32_t v = mv->V.ids[i];
        uint32_t n = lm_mesh_vertex_tris(m, v, mv->buf, LM_MOVES_BUF);
        if (n > LM_MOVES_BUF)
            return lm_fail(LM_E_RANGE, "vertex %u has %u triangles (limit %u)", v, n, LM_MOVES_BUF);
        for (uint32_t k = 0; k < n; k++)
            for (int c = 0; c < 3; c++) {
                uint32_t w = m->tris[mv->buf[k]].w[c];
                if (m->wedges[w].vertex == v) {
                    lm_status s = lm_idset_add(&mv->W, w);
                    if (s)
                        return s;
                }
            }
    }
    return LM_OK;
}

static double dist3(const float *a, const float *b)
{
    double d = 0;
    for (int k = 0; k < 3; k++)
        d += ((double)a[k] - b[k]) * ((double)a[k] - b[k]);
    return sqrt(d);
}

/* Mean length of the edges at v; a fallback from the bound when v has none. */
static double mean_edge(lm_moves *mv, uint32_t v)
{
    const lm_mesh *m = mv->m;
    uint32_t n = lm_mesh_vertex_tris(m, v, mv->buf, LM_MOVES_BUF);
    if (n > LM_MOVES_BUF)
        n = LM_MOVES_BUF;
    double sum = 0;
    uint32_t cnt = 0;
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t o = lm_tri_vertex(m, mv->buf[i], k);
            if (o != v) {
                sum += dist3(m->pos[v], m->pos[o]);
                cnt++;
            }
        }
    double r = mv->cfg.bound_radius > 0 ? mv->cfg.bound_radius * 0.02 : 1e-3;
    return cnt && sum > 0 ? sum / cnt : r;
}

/* Mean uv distance from wedge w to the other corners of its triangles. */
static double mean_uv_edge(lm_moves *mv, uint32_t w)
{
    const lm_mesh *m = mv->m;
    uint32_t v = m->wedges[w].vertex;
    uint32_t n = lm_mesh_vertex_tris(m, v, mv->buf, LM_MOVES_BUF);
    if (n > LM_MOVES_BUF)
        n = LM_MOVES_BUF;
    double sum = 0;
    uint32_t cnt = 0;
    for (uint32_t i = 0; i < n; i++) {
        const lm_tri *t = &m->tris[mv->buf[i]];
        if (t->w[0] != w && t->w[1] != w && t->w[2] != w)
            continue;
        for (int k = 0; k < 3; k++) {
            if (t->w[k] == w)
                continue;
            const float *a = m->wedges[w].uv, *b = m->wedges[t->w[k]].uv;
            sum += hypot((double)a[0] - b[0], (double)a[1] - b[1]);
            cnt++;
        }
    }
    return cnt && sum > 0 ? sum / cnt : 0.01;
}

static uint32_t fill_wedge(lm_moves *mv, uint32_t w, double *x, double *step)
{
    const lm_wedge *wd = &mv->m->wedges[w];
    const lm_moves_config *c = &mv->cfg;
    uint32_t o = 0;
    if (c->attrs & LM_ATTR_NORMAL)
        for (int k = 0; k < 3; k++, o++) {
            x[o] = wd->normal[k];
            step[o] = c->normal_step;
        }
    if (c->attrs & LM_ATTR_UV) {
        double s = c->uv_step * mean_uv_edge(mv, w);
        for (int k = 0; k < 2; k++, o++) {
            x[o] = wd->uv[k];
            step[o] = s;
        }
    }
    if (c->attrs & LM_ATTR_COLOR)
        for (int k = 0; k < 3; k++, o++) {
            x[o] = wd->color[k];
            /* step towards the inside of [0, 1] so the first vertex is not clamped away */
            step[o] = wd->color[k] > 0.5f ? -c->color_step : c->color_step;
        }
    return o;
}

lm_status lm_params_layout(lm_moves *mv)
{
    lm_status s;
    for (;;) {
        if ((s = collect_wedges(mv)))
            return s;
        mv->dim = 3 * mv->V.n + mv->wattrs * mv->W.n;
        if (mv->dim <= mv->cfg.max_dim)
            break;
        if (mv->V.n <= 1)
            return lm_fail(LM_E_RANGE, "vertex %u has too many wedges to optimise (%u parameters)",
                           mv->V.n ? mv->V.ids[0] : LM_NONE, mv->dim);
        lm_idset_truncate(&mv->V, mv->V.n - 1);
    }
    for (uint32_t i = 0; i < mv->V.n; i++) {
        uint32_t v = mv->V.ids[i];
        double s3 = mv->cfg.pos_step * mean_edge(mv, v);
        for (int k = 0; k < 3; k++) {
            mv->x[3 * i + k] = mv->m->pos[v][k];
            mv->step[3 * i + k] = s3;
        }
    }
    uint32_t o = 3 * mv->V.n;
    for (uint32_t i = 0; i < mv->W.n; i++)
        o += fill_wedge(mv, mv->W.ids[i], mv->x + o, mv->step + o);
    LM_ASSERT(o == mv->dim);
    return LM_OK;
}

int lm_params_valid(const lm_moves *mv, const double *x)
{
    for (uint32_t i = 0; i < mv->dim; i++)
        if (!isfinite(x[i]) || fabs(x[i]) > 1e18)
            return 0;
    if (!(mv->cfg.bound_radius > 0))
        return 1;
    double r2 = (double)mv->cfg.bound_radius * mv->cfg.bound_radius;
    for (uint32_t i = 0; i < mv->V.n; i++) {
        double d = 0;
        for (int k = 0; k < 3; k++)
            d += (x[3 * i + k] - mv->cfg.centre[k]) * (x[3 * i + k] - mv->cfg.centre[k]);
        if (d > r2)
            return 0;
    }
    return 1;
}

static float clamp01(double v)
{
    return v < 0 ? 0.0f : v > 1 ? 1.0f : (float)v;
}

static void apply_wedge(lm_moves *mv, uint32_t w, const double *x)
{
    lm_wedge wd = mv->m->wedges[w];
    uint32_t o = 0;
    if (mv->cfg.attrs & LM_ATTR_NORMAL)
        for (int k = 0; k < 3; k++)
            wd.normal[k] = (float)x[o++];
    if (mv->cfg.attrs & LM_ATTR_UV)
        for (int k = 0; k < 2; k++)
            wd.uv[k] = (float)x[o++];
    if (mv->cfg.attrs & LM_ATTR_COLOR)
        for (int k = 0; k < 3; k++)
            wd.color[k] = clamp01(x[o++]);
    lm_mesh_set_wedge(mv->m, w, &wd, mv->j);
}

void lm_params_apply(lm_moves *mv, const double *x)
{
    for (uint32_t i = 0; i < mv->V.n; i++) {
        float p[3] = {(float)x[3 * i], (float)x[3 * i + 1], (float)x[3 * i + 2]};
        lm_mesh_set_pos(mv->m, mv->V.ids[i], p, mv->j);
    }
    const double *a = x + 3 * mv->V.n;
    for (uint32_t i = 0; i < mv->W.n; i++)
        apply_wedge(mv, mv->W.ids[i], a + (size_t)i * mv->wattrs);
    if (mv->derived_normals)
        for (uint32_t i = 0; i < mv->R.n; i++)
            lm_moves_derive_normal(mv->m, mv->R.ids[i], mv->j);
}

static void set_normal(lm_mesh *m, uint32_t w, const float n[3], lm_journal *j)
{
    if (memcmp(m->wedges[w].normal, n, sizeof m->wedges[w].normal) == 0)
        return;
    lm_wedge x = m->wedges[w];
    memcpy(x.normal, n, sizeof x.normal);
    lm_mesh_set_wedge(m, w, &x, j);
}

void lm_moves_derive_normal(lm_mesh *m, uint32_t v, lm_journal *j)
{
    uint32_t stack[256], *tris = stack;
    uint32_t n = lm_mesh_vertex_tris(m, v, stack, 256);
    if (n > 256) {
        tris = malloc((size_t)n * sizeof *tris);
        LM_ASSERT(tris != NULL);
        lm_mesh_vertex_tris(m, v, tris, n);
    }
    double acc[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; i++) {
        double f[3];
        lm_mesh_face_normal(m, tris[i], f);
        for (int k = 0; k < 3; k++)
            acc[k] += f[k];
    }
    double len = sqrt(acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2]);
    float nrm[3];
    for (int k = 0; k < 3; k++)
        nrm[k] = len > 0 ? (float)(acc[k] / len) : (k == 2 ? 1.0f : 0.0f);
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            if (lm_tri_vertex(m, tris[i], k) == v)
                set_normal(m, m->tris[tris[i]].w[k], nrm, j);
    if (tris != stack)
        free(tris);
}
