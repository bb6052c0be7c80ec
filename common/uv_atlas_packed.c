/* common/uv_atlas_packed.c — the packed chart atlas (see uv_atlas.h): the charts of uv_charts.h
 * at one texel density, shelf-packed largest first with gutters, the density the largest that
 * packs (bisection), and the mesh with a wedge per (chart, vertex, normal, colour). */
#include "common/uv_atlas.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/uv_charts.h"

#define SEARCH_STEPS 24 /* bisection steps of the density */

typedef struct pack {
    const lm_charts *c;
    int size;
    uint32_t *by_height; /* charts, tallest first */
    double (*at)[2];     /* texel x, y (from the top) of each chart's rectangle's corner */
} pack;

/* A chart's sort key: tallest first, then widest, then first made. */
typedef struct key {
    double h, w;
    uint32_t c;
} key;

static int taller(const void *pa, const void *pb)
{
    const key *a = pa, *b = pb;
    if (a->h != b->h)
        return a->h > b->h ? -1 : 1;
    if (a->w != b->w)
        return a->w > b->w ? -1 : 1;
    return a->c < b->c ? -1 : a->c > b->c;
}

/* The charts of c tallest first into order. */
static lm_status by_height(const lm_charts *c, uint32_t *order)
{
    key *k = malloc(((size_t)c->n_charts + 1) * sizeof *k);
    if (!k)
        return lm_fail(LM_E_NOMEM, "out of memory for an atlas");
    for (uint32_t i = 0; i < c->n_charts; i++)
        k[i] = (key){c->extent[i][1], c->extent[i][0], i};
    qsort(k, c->n_charts, sizeof *k, taller);
    for (uint32_t i = 0; i < c->n_charts; i++)
        order[i] = k[i].c;
    free(k);
    return LM_OK;
}

/* A chart's rectangle at density d: its texels spanned plus the gutter. */
static double cell(double extent, double d)
{
    return ceil(extent * d) + LM_ATLAS_GUTTER;
}

/* Shelves, tallest first, from the top-left at density d (texels per world unit); 1 when every
 * chart fits, p->at set. Half a gutter stays between the map's sides and the charts. */
static int shelf(pack *p, double d)
{
    double half = 0.5 * LM_ATLAS_GUTTER, x = half, y = half, row = 0.0, end = p->size - half;
    for (uint32_t j = 0; j < p->c->n_charts; j++) {
        uint32_t c = p->by_height[j];
        double w = cell(p->c->extent[c][0], d), h = cell(p->c->extent[c][1], d);
        if (x + w > end && x > half)
            x = half, y += row, row = 0.0;
        if (x + w > end || y + h > end)
            return 0;
        p->at[c][0] = x + half, p->at[c][1] = y + half;
        row = h > row ? h : row;
        x += w;
    }
    return 1;
}

/* The largest density that packs (p->at for it); 0 when none does. */
static double density(pack *p)
{
    double hi = p->c->area > 0.0 ? sqrt((double)p->size * p->size / p->c->area) : 1.0, lo = hi;
    int steps = 0;
    while (!shelf(p, lo) && steps++ < 60)
        lo *= 0.5;
    if (steps > 60 || !(lo > 0.0))
        return 0.0;
    if (lo == hi)
        return lo;
    for (int k = 0; k < SEARCH_STEPS; k++) {
        double mid = 0.5 * (lo + hi);
        if (shelf(p, mid))
            lo = mid;
        else
            hi = mid;
    }
    shelf(p, lo);
    return lo;
}

/* The mesh under construction: wedges found per vertex, chart and attributes. */
typedef struct build {
    const lm_mesh *src;
    const lm_charts *c;
    const pack *p;
    double d;
    lm_mesh *dst;
    uint32_t *vmap;  /* src vertex -> dst vertex */
    uint32_t *head;  /* src vertex -> first dst wedge made for it (LM_NONE) */
    uint32_t *next;  /* dst wedge -> next dst wedge of the same src vertex */
    uint32_t *chart; /* dst wedge -> its chart */
    size_t cap;
} build;

static lm_status grow_wedge_lists(build *b, uint32_t need)
{
    if (need < b->cap)
        return LM_OK;
    size_t cap = b->cap ? 2 * b->cap : 1024;
    while (cap <= need)
        cap *= 2;
    uint32_t *next = realloc(b->next, cap * sizeof *next);
    if (next)
        b->next = next;
    uint32_t *chart = next ? realloc(b->chart, cap * sizeof *chart) : NULL;
    if (chart)
        b->chart = chart;
    if (!next || !chart)
        return lm_fail(LM_E_NOMEM, "out of memory for an atlas");
    b->cap = cap;
    return LM_OK;
}

/* The same wedge inside one chart: normal and colour equal to the bit. */
static int same_attrs(const lm_wedge *a, const lm_wedge *b)
{
    return memcmp(a->normal, b->normal, sizeof a->normal) == 0 &&
           memcmp(a->color, b->color, sizeof a->color) == 0;
}

/* The texture coordinates of chart point xy of chart c. */
static void chart_uv(const build *b, uint32_t c, const double xy[2], float uv[2])
{
    double x = b->p->at[c][0] + xy[0] * b->d;
    double y = b->p->at[c][1] + (b->c->extent[c][1] - xy[1]) * b->d;
    uv[0] = (float)(x / b->p->size);
    uv[1] = (float)(1.0 - y / b->p->size);
}

/* The dst wedge of corner k of live triangle i: found, else made. */
static lm_status corner_wedge(build *b, uint32_t i, int k, uint32_t *out)
{
    uint32_t c = b->c->chart[i];
    lm_wedge we = b->src->wedges[b->src->tris[b->c->tri[i]].w[k]];
    uint32_t v = we.vertex;
    for (uint32_t w = b->head[v]; w != LM_NONE; w = b->next[w])
        if (b->chart[w] == c && same_attrs(&b->dst->wedges[w], &we)) {
            *out = w;
            return LM_OK;
        }
    we.vertex = b->vmap[v];
    chart_uv(b, c, b->c->xy[i][k], we.uv);
    lm_status st = lm_mesh_add_wedge(b->dst, &we, out);
    if (st == LM_OK)
        st = grow_wedge_lists(b, *out);
    if (st != LM_OK)
        return st;
    b->chart[*out] = c, b->next[*out] = b->head[v], b->head[v] = *out;
    return LM_OK;
}

static lm_status add_tris(build *b)
{
    for (uint32_t i = 0; i < b->c->n_tris; i++) {
        uint32_t w[3], t = b->c->tri[i], id;
        for (int k = 0; k < 3; k++) {
            lm_status st = corner_wedge(b, i, k, &w[k]);
            if (st != LM_OK)
                return st;
        }
        lm_status st = lm_mesh_add_tri(b->dst, w, b->src->tris[t].material, &id);
        if (st != LM_OK)
            return st;
        b->dst->tris[id].part = b->src->tris[t].part;
    }
    return LM_OK;
}

static lm_status fill(build *b)
{
    const lm_mesh *src = b->src;
    b->vmap = malloc(((size_t)src->n_verts + 1) * sizeof *b->vmap);
    b->head = malloc(((size_t)src->n_verts + 1) * sizeof *b->head);
    if (!b->vmap || !b->head)
        return lm_fail(LM_E_NOMEM, "out of memory for an atlas");
    lm_status st = LM_OK;
    for (uint32_t v = 0; st == LM_OK && v < src->n_verts; v++) {
        b->vmap[v] = b->head[v] = LM_NONE;
        if (src->vert_alive[v])
            st = lm_mesh_add_vertex(b->dst, src->pos[v], &b->vmap[v]);
    }
    if (st == LM_OK)
        st = add_tris(b);
    if (st == LM_OK)
        st = lm_mesh_copy_materials(src, b->dst);
    if (st == LM_OK)
        st = lm_mesh_copy_parts(src, b->dst);
    b->dst->attrs = src->attrs | LM_ATTR_UV;
    return st;
}

static lm_status packed(const lm_mesh *src, int size, const lm_charts *c, lm_mesh **out)
{
    pack p = {c, size, malloc(((size_t)c->n_charts + 1) * sizeof(uint32_t)),
              malloc(((size_t)c->n_charts + 1) * sizeof(double[2]))};
    build b = {0};
    lm_status st = p.by_height && p.at ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for an atlas");
    if (st == LM_OK)
        st = by_height(c, p.by_height);
    if (st == LM_OK) {
        b.d = density(&p);
        if (!(b.d > 0.0))
            st = lm_fail(LM_E_INVALID, "%u charts do not pack into %d x %d texels", c->n_charts,
                         size, size);
    }
    if (st == LM_OK)
        st = lm_mesh_create(&b.dst);
    if (st == LM_OK) {
        b.src = src, b.c = c, b.p = &p;
        st = fill(&b);
    }
    free(b.vmap);
    free(b.head);
    free(b.next);
    free(b.chart);
    free(p.by_height);
    free(p.at);
    if (st != LM_OK) {
        lm_mesh_destroy(b.dst);
        return st;
    }
    *out = b.dst;
    return LM_OK;
}

lm_status lm_atlas_packed(const lm_mesh *src, int size, lm_mesh **out, uint32_t *n_charts)
{
    *out = NULL;
    lm_charts c;
    lm_status st = lm_charts_make(src, &c);
    if (st != LM_OK)
        return st;
    if (n_charts)
        *n_charts = c.n_charts;
    st = packed(src, size, &c, out);
    lm_charts_free(&c);
    return st;
}
