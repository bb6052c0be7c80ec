/* common/bake_walk.c — the walk every bake shares (see bake_walk.h): the result's UV triangles
 * rasterised at texel centres (the owner of each texel), the per-texel frame and line query, the
 * sinks, the gutters. */
#include "common/bake_walk.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/bvh.h"
#include "common/tangents.h"

#define STRICT 1e-6 /* barycentrics above this: strictly inside (overlap test) */
#define EDGE -1e-9  /* at or above this: on the triangle (ownership) */

typedef struct owners {
    int size;
    uint32_t *tri;  /* [size²] owning triangle or LM_NONE */
    uint8_t *inner; /* [size²] 1 when strictly inside its owner */
    uint64_t texels, overlaps;
} owners;

/* Texel-space corners of triangle t: x = u size, y = (1 - v) size (rows top to bottom). */
static void uv_corners(const lm_mesh *m, uint32_t t, int size, double c[3][2])
{
    for (int k = 0; k < 3; k++) {
        const lm_wedge *w = &m->wedges[m->tris[t].w[k]];
        c[k][0] = (double)w->uv[0] * size;
        c[k][1] = (1.0 - (double)w->uv[1]) * size;
    }
}

/* Barycentrics of point (x, y) in texel-space triangle c; 0 when c has no area. */
static int uv_bary(const double c[3][2], double x, double y, double b[3])
{
    double area =
        (c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[2][0] - c[0][0]) * (c[1][1] - c[0][1]);
    if (area == 0.0 || !isfinite(area))
        return 0;
    for (int k = 0; k < 3; k++) {
        const double *p = c[(k + 1) % 3], *q = c[(k + 2) % 3];
        b[k] = ((q[0] - p[0]) * (y - p[1]) - (x - p[0]) * (q[1] - p[1])) / area;
    }
    return 1;
}

static void own_texel(owners *o, uint32_t t, size_t i, const double b[3])
{
    int inner = b[0] > STRICT && b[1] > STRICT && b[2] > STRICT;
    if (o->tri[i] == LM_NONE) {
        o->tri[i] = t, o->inner[i] = (uint8_t)inner, o->texels++;
        return;
    }
    if (inner && o->inner[i])
        o->overlaps++;
    else if (inner)
        o->tri[i] = t, o->inner[i] = 1;
}

static void raster_tri(const lm_mesh *m, uint32_t t, owners *o)
{
    double c[3][2], b[3];
    uv_corners(m, t, o->size, c);
    double lo[2] = {c[0][0], c[0][1]}, hi[2] = {c[0][0], c[0][1]};
    for (int k = 1; k < 3; k++)
        for (int a = 0; a < 2; a++) {
            lo[a] = c[k][a] < lo[a] ? c[k][a] : lo[a];
            hi[a] = c[k][a] > hi[a] ? c[k][a] : hi[a];
        }
    int x0 = (int)floor(lo[0]), x1 = (int)ceil(hi[0]), y0 = (int)floor(lo[1]),
        y1 = (int)ceil(hi[1]);
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > o->size - 1 ? o->size - 1 : x1, y1 = y1 > o->size - 1 ? o->size - 1 : y1;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            if (uv_bary(c, x + 0.5, y + 0.5, b) && b[0] >= EDGE && b[1] >= EDGE && b[2] >= EDGE)
                own_texel(o, t, (size_t)y * o->size + x, b);
}

static void owners_free(owners *o)
{
    free(o->tri);
    free(o->inner);
}

/* Every texel's owner (LM_NONE outside the charts). */
static lm_status owners_make(const lm_mesh *m, int size, owners *o)
{
    memset(o, 0, sizeof *o);
    o->size = size;
    size_t n = (size_t)size * size;
    o->tri = malloc(n * sizeof *o->tri);
    o->inner = calloc(n, 1);
    if (!o->tri || !o->inner) {
        owners_free(o);
        return lm_fail(LM_E_NOMEM, "out of memory for a %d x %d bake", size, size);
    }
    for (size_t i = 0; i < n; i++)
        o->tri[i] = LM_NONE;
    for (uint32_t t = 0; t < m->n_tris; t++)
        if (m->tri_alive[t])
            raster_tri(m, t, o);
    return LM_OK;
}

static int uvs_in_unit_square(const lm_mesh *m)
{
    for (uint32_t t = 0; t < m->n_tris; t++)
        for (int k = 0; m->tri_alive[t] && k < 3; k++) {
            const float *uv = m->wedges[m->tris[t].w[k]].uv;
            if (!(uv[0] >= 0.0f && uv[0] <= 1.0f && uv[1] >= 0.0f && uv[1] <= 1.0f))
                return 0;
        }
    return 1;
}

lm_status lm_bake_uv_check(const lm_mesh *m, int size, lm_bake_stats *stats)
{
    if (!(m->attrs & LM_ATTR_UV))
        return lm_fail(LM_E_INVALID, "the mesh has no texture coordinates");
    if (!uvs_in_unit_square(m))
        return lm_fail(LM_E_INVALID, "the mesh's texture coordinates leave [0, 1] (a repeated "
                                     "texture)");
    owners o;
    lm_status st = owners_make(m, size, &o);
    if (st != LM_OK)
        return st;
    if (stats)
        stats->texels = o.texels, stats->overlaps = o.overlaps;
    owners_free(&o);
    if (o.overlaps)
        return lm_fail(LM_E_INVALID,
                       "the mesh's texture coordinates overlap (%llu of %llu texels at %d x %d "
                       "lie inside two triangles)",
                       (unsigned long long)o.overlaps, (unsigned long long)o.texels, size, size);
    return LM_OK;
}

typedef struct walk {
    const lm_bvh *bvh;
    const float (*tan)[4];
    double reach; /* the line's half length */
    lm_bake_stats *stats;
} walk;

/* The result's point, unit frame (T, B, N) at barycentrics b of its triangle t. 0 when the
 * normal vanishes. */
static int res_frame(const lm_mesh *res, const float (*tan)[4], uint32_t t, const double b[3],
                     double p[3], double f[9])
{
    double *T = f, *B = f + 3, *N = f + 6, w = 0.0;
    memset(f, 0, 9 * sizeof *f);
    p[0] = p[1] = p[2] = 0.0;
    for (int k = 0; k < 3; k++) {
        uint32_t wi = res->tris[t].w[k];
        const lm_wedge *we = &res->wedges[wi];
        for (int a = 0; a < 3; a++) {
            p[a] += b[k] * res->pos[we->vertex][a];
            N[a] += b[k] * we->normal[a];
            T[a] += b[k] * tan[wi][a];
        }
        w += b[k] * tan[wi][3];
    }
    if (!lm_bake_unit3(N))
        return 0;
    double d = lm_bake_dot3(N, T);
    for (int a = 0; a < 3; a++)
        T[a] -= N[a] * d;
    if (!lm_bake_unit3(T))
        return 0;
    double s = w < 0.0 ? -1.0 : 1.0;
    B[0] = s * (N[1] * T[2] - N[2] * T[1]);
    B[1] = s * (N[2] * T[0] - N[0] * T[2]);
    B[2] = s * (N[0] * T[1] - N[1] * T[0]);
    return 1;
}

/* The point of texel (x, y) owned by t: the result's side, then the original's. */
static void texel_point(const walk *w, lm_bake_point *pt, int size, int x, int y)
{
    double uc[3][2];
    pt->hit = LM_NONE;
    pt->framed = 0;
    uv_corners(pt->res, pt->tri, size, uc);
    if (!uv_bary(uc, x + 0.5, y + 0.5, pt->b))
        return;
    double sum = 0.0;
    for (int k = 0; k < 3; k++)
        sum += pt->b[k] = pt->b[k] < 0.0 ? 0.0 : pt->b[k];
    for (int k = 0; k < 3; k++)
        pt->b[k] /= sum;
    pt->framed = res_frame(pt->res, w->tan, pt->tri, pt->b, pt->p, pt->f);
    double th;
    if (pt->framed && lm_bvh_line_hit(w->bvh, pt->p, pt->f + 6, w->reach, 1, &pt->hit, &th, pt->hb))
        w->stats->hits++;
    else
        lm_bvh_closest_tri(w->bvh, pt->p, &pt->hit, pt->hb);
}

/* Passes until every texel is filled: each texel outside the charts next to (8-neighbourhood,
 * fixed order) one filled by an earlier pass takes its value. */
static void dilate(lm_image *const *imgs, int n_imgs, uint16_t *filled, int s)
{
    int grew = 1;
    static const int dx[8] = {-1, 1, 0, 0, -1, 1, -1, 1}, dy[8] = {0, 0, -1, 1, -1, -1, 1, 1};
    for (uint16_t pass = 2; grew && pass < UINT16_MAX; pass++) {
        grew = 0;
        for (int y = 0; y < s; y++)
            for (int x = 0; x < s; x++) {
                size_t i = (size_t)y * s + x;
                for (int k = 0; !filled[i] && k < 8; k++) {
                    int nx = x + dx[k], ny = y + dy[k];
                    if (nx < 0 || ny < 0 || nx >= s || ny >= s)
                        continue;
                    size_t j = (size_t)ny * s + nx;
                    if (!filled[j] || filled[j] == pass)
                        continue;
                    for (int m = 0; m < n_imgs; m++)
                        if (imgs[m])
                            memcpy(imgs[m]->pixels + 4 * i, imgs[m]->pixels + 4 * j, 4);
                    filled[i] = pass;
                    grew = 1;
                }
            }
    }
}

static lm_status walk_texels(const walk *w, const owners *o, lm_bake_point *pt,
                             const lm_bake_sink *sinks, int n_sinks, lm_image *const *imgs,
                             int n_imgs)
{
    uint16_t *filled = calloc((size_t)o->size * o->size, sizeof *filled);
    if (!filled)
        return lm_fail(LM_E_NOMEM, "out of memory for a bake's gutters");
    for (int y = 0; y < o->size; y++)
        for (int x = 0; x < o->size; x++) {
            size_t i = (size_t)y * o->size + x;
            if (o->tri[i] == LM_NONE)
                continue;
            pt->tri = o->tri[i];
            texel_point(w, pt, o->size, x, y);
            for (int s = 0; s < n_sinks; s++)
                sinks[s].texel(sinks[s].arg, pt, i);
            filled[i] = 1;
        }
    dilate(imgs, n_imgs, filled, o->size);
    free(filled);
    return LM_OK;
}

static double diagonal(const lm_mesh *m)
{
    float lo[3], hi[3];
    lm_mesh_bounds(m, lo, hi);
    double d[3] = {(double)hi[0] - lo[0], (double)hi[1] - lo[1], (double)hi[2] - lo[2]};
    return sqrt(lm_bake_dot3(d, d));
}

lm_status lm_bake_walk(const lm_mesh *orig, const lm_mesh *res, int size, const lm_bake_sink *sinks,
                       int n_sinks, lm_image *const *imgs, int n_imgs, lm_bake_stats *stats)
{
    lm_bake_stats local = {0};
    stats = stats ? stats : &local;
    memset(stats, 0, sizeof *stats);
    owners o;
    lm_bvh *bvh = NULL;
    float(*tan)[4] = NULL;
    lm_status st = owners_make(res, size, &o);
    if (st != LM_OK)
        return st;
    stats->texels = o.texels, stats->overlaps = o.overlaps;
    st = lm_bvh_create(orig, &bvh);
    if (st == LM_OK)
        st = lm_mesh_tangents(res, &tan);
    walk w = {bvh, (const float(*)[4])tan, 0.1 * diagonal(orig), stats};
    lm_bake_point pt;
    memset(&pt, 0, sizeof pt);
    pt.orig = orig, pt.res = res;
    if (st == LM_OK)
        st = walk_texels(&w, &o, &pt, sinks, n_sinks, imgs, n_imgs);
    owners_free(&o);
    lm_bvh_destroy(bvh);
    free(tan);
    return st;
}

void lm_bake_sample(const lm_image *img, double u, double v, double px[4])
{
    double fx = (u - floor(u)) * img->width - 0.5, fy = (1.0 - (v - floor(v))) * img->height - 0.5;
    double x0 = floor(fx), y0 = floor(fy), ax = fx - x0, ay = fy - y0;
    for (int ch = 0; ch < 4; ch++) {
        double acc = 0.0;
        for (int k = 0; k < 4; k++) {
            int x = (int)x0 + (k & 1), y = (int)y0 + (k >> 1);
            x = ((x % img->width) + img->width) % img->width;
            y = ((y % img->height) + img->height) % img->height;
            double wgt = ((k & 1) ? ax : 1.0 - ax) * ((k >> 1) ? ay : 1.0 - ay);
            acc += wgt * img->pixels[((size_t)y * img->width + x) * 4 + ch];
        }
        px[ch] = acc;
    }
}
