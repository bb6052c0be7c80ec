/* coordinator/simplify/simplify_cluster.c — Rossignac–Borrel vertex clustering, as the paper's
 * Figure 7a input.
 *
 * A uniform grid of cubic cells covers the bounding box; all vertices in a cell merge into one.
 * Its position is the point minimising the summed plane quadrics of the original triangles around
 * the cell's vertices (Lindstrom 2000, "out-of-core simplification"), regularised towards the
 * mean of the cell's vertices for directions the quadric leaves free (flat or straight regions),
 * and clamped to the cell. Wedges merge per (cell, material) with attributes averaged over the
 * corners that use them, so UV seams inside a cell vanish (the texture stretch the paper shows).
 * Triangles whose three corners fall in fewer than three cells are dropped, repeated triangles
 * are kept once, and double-sided faces (the same three cells in opposite orientations, e.g. the
 * two sides of a thin sheet) are removed altogether, as the paper does, which opens a few holes.
 * The grid resolution is searched (bisection on log cell size) until the live vertex count is
 * within CO_SIMPLIFY_TOLERANCE of the target. A part the clustering removed altogether (its
 * triangles all fell into fewer than three cells) comes back at its smallest non-empty QEM form
 * (co_simplify_keep_parts): no part disappears silently. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "coordinator/simplify/simplify_internal.h"

#define CL_MAX_CELLS_PER_AXIS (1u << 20)
#define CL_MAX_EVALS 48
#define CL_EMPTY UINT64_MAX

/* ---- u64 -> u32 hash map (open addressing, linear probing) -------------------------------- */

typedef struct cmap {
    uint64_t *keys;
    uint32_t *vals;
    size_t cap; /* power of two */
    uint32_t n;
} cmap;

static lm_status cmap_init(cmap *m, size_t expected)
{
    size_t cap = 64;
    while (cap < 2 * expected)
        cap *= 2;
    m->keys = malloc(cap * sizeof *m->keys);
    m->vals = malloc(cap * sizeof *m->vals);
    m->cap = cap;
    m->n = 0;
    if (!m->keys || !m->vals)
        return lm_fail(LM_E_NOMEM, "out of memory for a clustering table of %zu cells", cap);
    memset(m->keys, 0xff, cap * sizeof *m->keys);
    return LM_OK;
}

static void cmap_free(cmap *m)
{
    free(m->keys);
    free(m->vals);
    memset(m, 0, sizeof *m);
}

static void cmap_clear(cmap *m)
{
    memset(m->keys, 0xff, m->cap * sizeof *m->keys);
    m->n = 0;
}

/* Id of key; a new key gets the next id. The table never fills: capacity >= 2x the keys. */
static uint32_t cmap_get_or_add(cmap *m, uint64_t key)
{
    uint64_t h = key * 0x9E3779B97F4A7C15ull;
    size_t i = (size_t)(h >> 17) & (m->cap - 1);
    while (m->keys[i] != CL_EMPTY) {
        if (m->keys[i] == key)
            return m->vals[i];
        i = (i + 1) & (m->cap - 1);
    }
    m->keys[i] = key;
    m->vals[i] = m->n;
    return m->n++;
}

/* ---- one clustering of the topology (no attributes) ---------------------------------------- */

typedef struct cand {
    uint32_t c[3]; /* cells of the corners, sorted ascending */
    uint32_t t;    /* input triangle */
    uint32_t odd;  /* 1 when the corner order is an odd permutation of c */
} cand;

typedef struct cluster_ctx {
    const lm_mesh *in;
    double lo[3], hi[3], extent; /* bounding box and its largest side */
    double h;                    /* cell side of the current clustering */
    uint64_t dim[3];
    cmap cells;
    uint32_t *vcell; /* [n_verts] cell of each vertex (LM_NONE for dead ones) */
    cand *cands;     /* [live_tris] non-degenerate triangles, then sorted */
    size_t n_cands, n_kept;
    uint8_t *keep;   /* [n_tris] 1 when the input triangle survives */
    uint32_t *stamp; /* [live_verts] pass that last counted the cell */
    uint32_t pass;
    co_simplify_stats st;
} cluster_ctx;

static uint64_t cell_key(const cluster_ctx *C, const float p[3])
{
    uint64_t ix[3];
    for (int k = 0; k < 3; k++) {
        double f = floor(((double)p[k] - C->lo[k]) / C->h);
        ix[k] = f < 0 ? 0 : (uint64_t)f >= C->dim[k] ? C->dim[k] - 1 : (uint64_t)f;
    }
    return ix[0] + C->dim[0] * (ix[1] + C->dim[1] * ix[2]);
}

static void assign_cells(cluster_ctx *C)
{
    const lm_mesh *in = C->in;
    for (int k = 0; k < 3; k++) {
        double n = floor((C->hi[k] - C->lo[k]) / C->h) + 1;
        C->dim[k] = n > CL_MAX_CELLS_PER_AXIS ? CL_MAX_CELLS_PER_AXIS : (uint64_t)n;
    }
    cmap_clear(&C->cells);
    for (uint32_t v = 0; v < in->n_verts; v++)
        C->vcell[v] =
            in->vert_alive[v] ? cmap_get_or_add(&C->cells, cell_key(C, in->pos[v])) : LM_NONE;
}

static int cand_cmp(const void *pa, const void *pb)
{
    const cand *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->c[k] != b->c[k])
            return a->c[k] < b->c[k] ? -1 : 1;
    return a->t < b->t ? -1 : a->t > b->t;
}

/* Sort three cells; returns 1 when that took an odd number of swaps. */
static uint32_t sort3(uint32_t c[3])
{
    uint32_t odd = 0, x;
#define CL_SWAP(i, j)                                                                              \
    if (c[i] > c[j]) {                                                                             \
        x = c[i];                                                                                  \
        c[i] = c[j];                                                                               \
        c[j] = x;                                                                                  \
        odd ^= 1;                                                                                  \
    }
    CL_SWAP(0, 1)
    CL_SWAP(1, 2)
    CL_SWAP(0, 1)
#undef CL_SWAP
    return odd;
}

/* Triangles spanning three cells, sorted so equal cell triples are adjacent. */
static void collect_cands(cluster_ctx *C)
{
    const lm_mesh *in = C->in;
    C->n_cands = 0;
    for (uint32_t t = 0; t < in->n_tris; t++) {
        C->keep[t] = 0;
        if (!in->tri_alive[t])
            continue;
        cand c = {.t = t};
        for (int k = 0; k < 3; k++)
            c.c[k] = C->vcell[lm_tri_vertex(in, t, k)];
        if (c.c[0] == c.c[1] || c.c[1] == c.c[2] || c.c[0] == c.c[2]) {
            C->st.degenerate_removed++;
            continue;
        }
        c.odd = sort3(c.c);
        C->cands[C->n_cands++] = c;
    }
    qsort(C->cands, C->n_cands, sizeof *C->cands, cand_cmp);
}

/* Per group of equal cell triples: both orientations present -> drop all (double-sided);
 * otherwise keep the first (lowest input id) and drop repeats. */
static void select_tris(cluster_ctx *C)
{
    C->n_kept = 0;
    for (size_t i = 0; i < C->n_cands;) {
        size_t j = i + 1;
        uint32_t seen[2] = {0, 0};
        seen[C->cands[i].odd] = 1;
        while (j < C->n_cands && !memcmp(C->cands[j].c, C->cands[i].c, sizeof C->cands[i].c))
            seen[C->cands[j++].odd] = 1;
        if (seen[0] && seen[1]) {
            C->st.double_sided_removed += (uint32_t)(j - i);
        } else {
            C->keep[C->cands[i].t] = 1;
            C->n_kept++;
            C->st.duplicates_removed += (uint32_t)(j - i - 1);
        }
        i = j;
    }
}

/* Cluster with cell side h; returns the number of live output vertices. */
static uint32_t cluster_topology(cluster_ctx *C, double h)
{
    C->h = h;
    memset(&C->st, 0, sizeof C->st);
    C->st.cell_size = h;
    assign_cells(C);
    collect_cands(C);
    select_tris(C);
    uint32_t stamp = ++C->pass, count = 0;
    for (size_t i = 0; i < C->n_cands; i++) {
        if (!C->keep[C->cands[i].t])
            continue;
        for (int k = 0; k < 3; k++) {
            uint32_t c = C->cands[i].c[k];
            if (C->stamp[c] != stamp) {
                C->stamp[c] = stamp;
                count++;
            }
        }
    }
    return count;
}

static lm_status ctx_init(cluster_ctx *C, const lm_mesh *in)
{
    memset(C, 0, sizeof *C);
    C->in = in;
    float lo[3], hi[3];
    lm_mesh_bounds(in, lo, hi);
    for (int k = 0; k < 3; k++) {
        C->lo[k] = lo[k];
        C->hi[k] = hi[k];
        C->extent = fmax(C->extent, (double)hi[k] - lo[k]);
    }
    C->vcell = malloc(((size_t)in->n_verts + 1) * sizeof *C->vcell);
    C->cands = malloc(((size_t)in->live_tris + 1) * sizeof *C->cands);
    C->keep = malloc((size_t)in->n_tris + 1);
    C->stamp = calloc((size_t)in->live_verts + 1, sizeof *C->stamp);
    if (!C->vcell || !C->cands || !C->keep || !C->stamp)
        return lm_fail(LM_E_NOMEM, "out of memory clustering %u triangles", in->live_tris);
    return cmap_init(&C->cells, in->live_verts);
}

static void ctx_free(cluster_ctx *C)
{
    free(C->vcell);
    free(C->cands);
    free(C->keep);
    free(C->stamp);
    cmap_free(&C->cells);
}

/* ---- cell positions: quadric-optimal point, clamped to the cell ----------------------------- */

enum { Q_XX, Q_XY, Q_XZ, Q_YY, Q_YZ, Q_ZZ, Q_BX, Q_BY, Q_BZ, Q_C, Q_SX, Q_SY, Q_SZ, Q_N, Q_LEN };

/* Add the area-weighted plane quadric of every input triangle to the cells of its corners, and
 * every vertex to its cell's mean. acc is [n_cells][Q_LEN]. */
static void accumulate_cells(const cluster_ctx *C, double *acc)
{
    const lm_mesh *in = C->in;
    for (uint32_t t = 0; t < in->n_tris; t++) {
        if (!in->tri_alive[t])
            continue;
        const float *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = in->pos[lm_tri_vertex(in, t, k)];
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++) {
            u[k] = (double)p[1][k] - p[0][k];
            v[k] = (double)p[2][k] - p[0][k];
        }
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 0))
            continue;
        double w = 0.5 * len, d = -(n[0] * p[0][0] + n[1] * p[0][1] + n[2] * p[0][2]) / len;
        for (int k = 0; k < 3; k++)
            n[k] /= len;
        for (int k = 0; k < 3; k++) {
            double *q = acc + (size_t)C->vcell[lm_tri_vertex(in, t, k)] * Q_LEN;
            q[Q_XX] += w * n[0] * n[0], q[Q_XY] += w * n[0] * n[1], q[Q_XZ] += w * n[0] * n[2];
            q[Q_YY] += w * n[1] * n[1], q[Q_YZ] += w * n[1] * n[2], q[Q_ZZ] += w * n[2] * n[2];
            q[Q_BX] += w * d * n[0], q[Q_BY] += w * d * n[1], q[Q_BZ] += w * d * n[2];
            q[Q_C] += w * d * d;
        }
    }
    for (uint32_t v = 0; v < in->n_verts; v++) {
        if (!in->vert_alive[v])
            continue;
        double *q = acc + (size_t)C->vcell[v] * Q_LEN;
        q[Q_SX] += in->pos[v][0], q[Q_SY] += in->pos[v][1], q[Q_SZ] += in->pos[v][2];
        q[Q_N] += 1;
    }
}

static double det3(const double a[3][3])
{
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/* Minimise x'Ax + 2b'x + lambda|x - mean|^2 (Cramer's rule), then clamp to the cell. */
static void cell_position(const cluster_ctx *C, const double *q, float out[3])
{
    double mean[3] = {q[Q_SX] / q[Q_N], q[Q_SY] / q[Q_N], q[Q_SZ] / q[Q_N]};
    double tr = q[Q_XX] + q[Q_YY] + q[Q_ZZ], lambda = 1e-3 * tr / 3.0;
    double x[3] = {mean[0], mean[1], mean[2]};
    if (tr > 0) {
        double A[3][3] = {{q[Q_XX] + lambda, q[Q_XY], q[Q_XZ]},
                          {q[Q_XY], q[Q_YY] + lambda, q[Q_YZ]},
                          {q[Q_XZ], q[Q_YZ], q[Q_ZZ] + lambda}};
        double r[3] = {-q[Q_BX] + lambda * mean[0], -q[Q_BY] + lambda * mean[1],
                       -q[Q_BZ] + lambda * mean[2]};
        double D = det3(A);
        for (int k = 0; k < 3 && D != 0; k++) {
            double Ak[3][3];
            memcpy(Ak, A, sizeof Ak);
            for (int i = 0; i < 3; i++)
                Ak[i][k] = r[i];
            x[k] = det3(Ak) / D;
        }
    }
    for (int k = 0; k < 3; k++) {
        double f = floor((mean[k] - C->lo[k]) / C->h);
        f = f < 0 ? 0 : f > (double)(C->dim[k] - 1) ? (double)(C->dim[k] - 1) : f;
        double lo = C->lo[k] + f * C->h, hi = lo + C->h;
        x[k] = isfinite(x[k]) ? x[k] : mean[k];
        out[k] = (float)(x[k] < lo ? lo : x[k] > hi ? hi : x[k]);
    }
}

/* ---- output mesh -------------------------------------------------------------------------------
 */

/* Merged wedges: per (cell, material), attributes summed over the corners that use them. */
typedef struct wedge_acc {
    cmap map;
    uint32_t *cell;   /* [n] cell of each merged wedge */
    double (*sum)[9]; /* normal xyz, uv, rgba */
    uint32_t *count;
    uint32_t *tri_w; /* [3 * n_tris] merged wedge of each kept corner */
} wedge_acc;

static void wedge_acc_free(wedge_acc *W)
{
    cmap_free(&W->map);
    free(W->cell);
    free(W->sum);
    free(W->count);
    free(W->tri_w);
}

static lm_status merge_wedges(const cluster_ctx *C, wedge_acc *W)
{
    const lm_mesh *in = C->in;
    uint64_t n_mat = in->n_materials ? in->n_materials : 1;
    size_t most = 3 * C->n_cands + 1;
    memset(W, 0, sizeof *W);
    W->cell = malloc(most * sizeof *W->cell);
    W->sum = calloc(most, sizeof *W->sum);
    W->count = calloc(most, sizeof *W->count);
    W->tri_w = malloc(((size_t)in->n_tris * 3 + 1) * sizeof *W->tri_w);
    if (!W->cell || !W->sum || !W->count || !W->tri_w)
        return lm_fail(LM_E_NOMEM, "out of memory merging wedges");
    lm_status s = cmap_init(&W->map, most);
    for (uint32_t t = 0; t < in->n_tris && !s; t++) {
        if (!C->keep[t])
            continue;
        for (int k = 0; k < 3; k++) {
            const lm_wedge *src = &in->wedges[in->tris[t].w[k]];
            uint32_t c = C->vcell[src->vertex];
            uint32_t id = cmap_get_or_add(&W->map, (uint64_t)c * n_mat + in->tris[t].material);
            W->tri_w[3 * (size_t)t + k] = id;
            W->cell[id] = c;
            double *a = W->sum[id];
            a[0] += src->normal[0], a[1] += src->normal[1], a[2] += src->normal[2];
            a[3] += src->uv[0], a[4] += src->uv[1];
            for (int i = 0; i < 4; i++)
                a[5 + i] += src->color[i];
            W->count[id]++;
        }
    }
    return s;
}

static lm_wedge mean_wedge(const wedge_acc *W, uint32_t id, uint32_t vertex)
{
    const double *a = W->sum[id];
    double n = W->count[id], len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    lm_wedge w = {.vertex = vertex};
    for (int k = 0; k < 3; k++)
        w.normal[k] = len > 0 ? (float)(a[k] / len) : (k == 2 ? 1.0f : 0.0f);
    w.uv[0] = (float)(a[3] / n);
    w.uv[1] = (float)(a[4] / n);
    for (int k = 0; k < 4; k++)
        w.color[k] = (float)(a[5 + k] / n);
    return w;
}

/* Vertices (used cells, ascending), wedges (first use order), kept triangles (input order). */
static lm_status emit_mesh(const cluster_ctx *C, const double *acc, const wedge_acc *W, lm_mesh *m)
{
    const lm_mesh *in = C->in;
    uint32_t n_cells = C->cells.n;
    uint32_t *cell_out = malloc(((size_t)n_cells + 1) * sizeof *cell_out);
    if (!cell_out)
        return lm_fail(LM_E_NOMEM, "out of memory building the clustered mesh");
    for (uint32_t c = 0; c < n_cells; c++)
        cell_out[c] = LM_NONE;
    for (uint32_t id = 0; id < W->map.n; id++)
        cell_out[W->cell[id]] = 0;
    lm_status s = LM_OK;
    for (uint32_t c = 0; c < n_cells && !s; c++) {
        if (cell_out[c] == LM_NONE)
            continue;
        float p[3];
        cell_position(C, acc + (size_t)c * Q_LEN, p);
        s = lm_mesh_add_vertex(m, p, &cell_out[c]);
    }
    for (uint32_t id = 0; id < W->map.n && !s; id++) {
        lm_wedge w = mean_wedge(W, id, cell_out[W->cell[id]]);
        s = lm_mesh_add_wedge(m, &w, NULL);
    }
    for (uint32_t t = 0; t < in->n_tris && !s; t++) {
        uint32_t id = 0;
        if (C->keep[t] &&
            !(s = lm_mesh_add_tri(m, &W->tri_w[3 * (size_t)t], in->tris[t].material, &id)))
            m->tris[id].part = in->tris[t].part;
    }
    free(cell_out);
    return s;
}

static lm_status build_output(const cluster_ctx *C, lm_mesh **out)
{
    *out = NULL;
    if (C->n_kept == 0)
        return lm_fail(LM_E_RANGE, "clustering with cells of side %g left no triangles", C->h);
    double *acc = calloc((size_t)C->cells.n * Q_LEN, sizeof *acc);
    wedge_acc W;
    lm_mesh *m = NULL;
    lm_status s = acc ? merge_wedges(C, &W) : lm_fail(LM_E_NOMEM, "out of memory clustering");
    if (!s)
        s = lm_mesh_create(&m);
    if (!s) {
        m->attrs = C->in->attrs;
        accumulate_cells(C, acc);
        s = co_simplify_copy_materials(C->in, m);
    }
    if (!s)
        s = lm_mesh_copy_parts(C->in, m);
    if (!s)
        s = emit_mesh(C, acc, &W, m);
    if (acc)
        wedge_acc_free(&W);
    free(acc);
    if (!s && !(C->in->attrs & LM_ATTR_NORMAL))
        lm_mesh_compute_normals(m);
    if (!s)
        s = co_simplify_finish(&m);
    else
        lm_mesh_destroy(m);
    if (!s)
        *out = m;
    return s;
}

/* ---- resolution search and entry points ------------------------------------------------------ */

typedef struct cl_search {
    uint32_t target, evals;
    double best_h;
    uint32_t best_v;
} cl_search;

static uint32_t eval_h(cluster_ctx *C, cl_search *S, double h)
{
    uint32_t v = cluster_topology(C, h);
    S->evals++;
    double d = fabs((double)v - S->target), d_best = fabs((double)S->best_v - S->target);
    if (S->evals == 1 || d < d_best) {
        S->best_h = h;
        S->best_v = v;
    }
    return v;
}

static int cl_close(uint32_t v, uint32_t target)
{
    return fabs((double)v - target) <= fmax(1.0, 0.01 * target);
}

/* Bisection on log(h): small h = many vertices. */
static void search_h(cluster_ctx *C, cl_search *S)
{
    double h_min = C->extent / CL_MAX_CELLS_PER_AXIS, h_max = C->extent * 2.0;
    double h = C->extent * sqrt(2.0 / S->target), small = 0, big = 0;
    uint32_t v = eval_h(C, S, h);
    while (!cl_close(v, S->target) && S->evals < CL_MAX_EVALS) {
        if (v < S->target)
            big = h;
        else
            small = h;
        if (small > 0 && big > 0)
            h = sqrt(small * big);
        else
            h = small > 0 ? h * 2 : h / 2;
        if (h < h_min || h > h_max || (small > 0 && big > 0 && big / small < 1 + 1e-7))
            return;
        v = eval_h(C, S, h);
    }
}

static void fill_stats(const cluster_ctx *C, uint32_t evals, co_simplify_stats *stats)
{
    if (!stats)
        return;
    *stats = C->st;
    stats->passes = evals;
}

lm_status co_simplify_cluster_grid(const lm_mesh *in, double cell_size, co_simplify_stats *stats,
                                   lm_mesh **out)
{
    *out = NULL;
    if (!(cell_size > 0) || !isfinite(cell_size))
        return lm_fail(LM_E_INVALID, "clustering cell size %g is not a positive number", cell_size);
    cluster_ctx C;
    lm_status s = ctx_init(&C, in);
    if (!s) {
        double h = fmax(cell_size, C.extent / CL_MAX_CELLS_PER_AXIS);
        cluster_topology(&C, h > 0 ? h : 1.0);
        s = build_output(&C, out);
        fill_stats(&C, 1, stats);
    }
    ctx_free(&C);
    return s;
}

lm_status co_simplify_cluster(const lm_mesh *in, uint32_t target_verts, co_simplify_stats *stats,
                              lm_mesh **out)
{
    *out = NULL;
    cluster_ctx C;
    lm_status s = ctx_init(&C, in);
    if (!s && !(C.extent > 0))
        s = lm_fail(LM_E_RANGE, "the model has no extent: every vertex is at one point");
    cl_search S = {.target = target_verts};
    uint32_t kept = 0;
    if (!s) {
        search_h(&C, &S);
        if (C.h != S.best_h)
            cluster_topology(&C, S.best_h);
        s = build_output(&C, out);
        fill_stats(&C, S.evals, stats);
    }
    ctx_free(&C);
    if (!s && (s = co_simplify_keep_parts(in, *out, &kept)) != LM_OK) {
        lm_mesh_destroy(*out);
        *out = NULL;
    }
    if (s || co_simplify_reached((*out)->live_verts, target_verts))
        return s;
    if (kept)
        return lm_fail(LM_E_RANGE,
                       "vertex clustering reached %u vertices at best (cell side %g; with %u "
                       "part%s it would have removed, kept at %s smallest), above the target %u",
                       (*out)->live_verts, S.best_h, kept, kept == 1 ? "" : "s",
                       kept == 1 ? "its" : "their", target_verts);
    return lm_fail(LM_E_RANGE,
                   "vertex clustering reached %u vertices at best (cell side %g), above the "
                   "target %u",
                   (*out)->live_verts, S.best_h, target_verts);
}
