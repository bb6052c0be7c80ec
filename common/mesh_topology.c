/* common/mesh_topology.c — owns the vertex -> triangle adjacency queries, the legal edge operations
 * of Hoppe et al. 1993 (collapse under the link condition, split, swap), wedge merging and the undo
 * journal.
 *
 * Every mutation goes through a handful of journaled primitives (set position / wedge / triangle,
 * kill an element, append an element, insert into / delete from an adjacency list at a recorded
 * position), so lm_journal_rollback() restores the mesh and its adjacency lists bit for bit.
 * Each operation first checks legality and reserves all memory it needs (journal steps,
 * adjacency-list room, appended elements); only then does it mutate, so a refused or failed call
 * leaves the mesh untouched. Hot paths use fixed stack buffers: a vertex may have at most
 * LM_TOPO_MAX_VALENCE incident triangles for the edge operations (LM_E_RANGE beyond). */
#include "common/mesh_topology.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/mesh_internal.h"

#define LM_TOPO_MAX_VALENCE 1024u

/* ---- journal ------------------------------------------------------------------------------ */

enum {
    J_POS,        /* id = vertex, old.pos */
    J_WEDGE,      /* id = wedge, old.wedge */
    J_TRI,        /* id = triangle, old.tri */
    J_ADJ_INS,    /* t = aux was inserted into vtris[id] at idx */
    J_ADJ_DEL,    /* t = aux was removed from vtris[id] at idx */
    J_KILL_VERT,  /* id went from alive to dead */
    J_KILL_WEDGE, /* id */
    J_KILL_TRI,   /* id */
    J_ADD_VERT,   /* id appended (last slot) */
    J_ADD_WEDGE,  /* id */
    J_ADD_TRI,    /* id, linked into adjacency by lm_mesh_add_tri */
};

typedef struct jstep {
    uint32_t kind, id, aux, idx;
    union {
        float pos[3];
        lm_wedge wedge;
        lm_tri tri;
    } old;
} jstep;

struct lm_journal {
    jstep *steps;
    size_t n, cap;
};

lm_status lm_journal_create(lm_journal **out)
{
    lm_journal *j = calloc(1, sizeof *j);
    if (!j)
        return lm_fail(LM_E_NOMEM, "out of memory creating an undo journal");
    *out = j;
    return LM_OK;
}

void lm_journal_destroy(lm_journal *j)
{
    if (!j)
        return;
    free(j->steps);
    free(j);
}

size_t lm_journal_mark(const lm_journal *j)
{
    return j->n;
}

void lm_journal_clear(lm_journal *j)
{
    j->n = 0;
}

/* Make room for `extra` more steps so the recording calls of one operation cannot fail. */
static lm_status journal_reserve(lm_journal *j, size_t extra)
{
    if (!j || j->n + extra <= j->cap)
        return LM_OK;
    size_t cap = lm_grow_cap(j->cap, j->n + extra, 256, SIZE_MAX);
    if (!LM_RESIZE(&j->steps, cap))
        return lm_fail(LM_E_NOMEM, "out of memory growing the undo journal to %zu steps", cap);
    j->cap = cap;
    return LM_OK;
}

static jstep *jpush(lm_journal *j, uint32_t kind, uint32_t id)
{
    if (!j)
        return NULL;
    LM_ASSERT(j->n < j->cap); /* reserved by the operation */
    jstep *s = &j->steps[j->n++];
    s->kind = kind;
    s->id = id;
    s->aux = s->idx = 0;
    return s;
}

/* ---- adjacency access ---------------------------------------------------------------------- */

static const lm_u32vec empty_list;

static int adjacency_ready(const lm_mesh *m)
{
    return m->internal && m->internal->adjacency_built;
}

static const lm_u32vec *vt(const lm_mesh *m, uint32_t v)
{
    const struct lm_mesh_internal *in = m->internal;
    return v < in->cap_vtris ? &in->vtris[v] : &empty_list;
}

static lm_status vec_reserve(lm_u32vec *v, uint32_t extra)
{
    if (v->n + extra <= v->cap)
        return LM_OK;
    if (!LM_GROW32(&v->data, &v->cap, (size_t)v->n + extra, 8))
        return lm_fail(LM_E_NOMEM, "out of memory growing an adjacency list");
    return LM_OK;
}

/* Room for `extra` more triangles in the list of vertex v (which must be < n_verts). */
static lm_status adj_reserve(lm_mesh *m, uint32_t v, uint32_t extra)
{
    lm_status s = lm_mesh_adj_reserve(m, m->n_verts);
    return s ? s : vec_reserve(&m->internal->vtris[v], extra);
}

static void vec_insert_at(lm_u32vec *v, uint32_t idx, uint32_t x)
{
    if (v->n == v->cap)
        LM_ASSERT(vec_reserve(v, 1) == LM_OK); /* only after a rebuild between mark and rollback */
    memmove(v->data + idx + 1, v->data + idx, (size_t)(v->n - idx) * sizeof *v->data);
    v->data[idx] = x;
    v->n++;
}

static void vec_remove_at(lm_u32vec *v, uint32_t idx)
{
    memmove(v->data + idx, v->data + idx + 1, (size_t)(v->n - idx - 1) * sizeof *v->data);
    v->n--;
}

/* ---- journaled primitives ------------------------------------------------------------------ */

static void p_set_pos(lm_mesh *m, uint32_t v, const float p[3], lm_journal *j)
{
    jstep *s = jpush(j, J_POS, v);
    if (s)
        memcpy(s->old.pos, m->pos[v], sizeof s->old.pos);
    memcpy(m->pos[v], p, sizeof m->pos[v]);
}

static void p_set_wedge(lm_mesh *m, uint32_t w, const lm_wedge *value, lm_journal *j)
{
    jstep *s = jpush(j, J_WEDGE, w);
    if (s)
        s->old.wedge = m->wedges[w];
    m->wedges[w] = *value;
}

static void p_set_tri(lm_mesh *m, uint32_t t, const lm_tri *value, lm_journal *j)
{
    jstep *s = jpush(j, J_TRI, t);
    if (s)
        s->old.tri = m->tris[t];
    m->tris[t] = *value;
}

/* Insert t into v's ascending list (room reserved by the caller). */
static void p_adj_ins(lm_mesh *m, uint32_t v, uint32_t t, lm_journal *j)
{
    lm_u32vec *l = &m->internal->vtris[v];
    LM_ASSERT(l->n < l->cap);
    uint32_t i = l->n;
    while (i > 0 && l->data[i - 1] > t)
        i--;
    vec_insert_at(l, i, t);
    jstep *s = jpush(j, J_ADJ_INS, v);
    if (s) {
        s->aux = t;
        s->idx = i;
    }
}

static void p_adj_del(lm_mesh *m, uint32_t v, uint32_t t, lm_journal *j)
{
    lm_u32vec *l = &m->internal->vtris[v];
    uint32_t i = 0;
    while (i < l->n && l->data[i] != t)
        i++;
    LM_ASSERT(i < l->n);
    vec_remove_at(l, i);
    jstep *s = jpush(j, J_ADJ_DEL, v);
    if (s) {
        s->aux = t;
        s->idx = i;
    }
}

static void p_kill_tri(lm_mesh *m, uint32_t t, lm_journal *j)
{
    uint32_t v[3];
    for (int k = 0; k < 3; k++)
        v[k] = lm_tri_vertex(m, t, k);
    for (int k = 0; k < 3; k++)
        if ((k < 1 || v[k] != v[0]) && (k < 2 || v[k] != v[1]))
            p_adj_del(m, v[k], t, j);
    jpush(j, J_KILL_TRI, t);
    m->tri_alive[t] = 0;
    m->live_tris--;
}

static void p_kill_wedge(lm_mesh *m, uint32_t w, lm_journal *j)
{
    jpush(j, J_KILL_WEDGE, w);
    m->wedge_alive[w] = 0;
}

static void p_kill_vert(lm_mesh *m, uint32_t v, lm_journal *j)
{
    jpush(j, J_KILL_VERT, v);
    m->vert_alive[v] = 0;
    m->live_verts--;
}

/* Inverses of the appends done through lm_mesh_add_* (exact: ids are never reused). */
static void undo_add_tri(lm_mesh *m)
{
    uint32_t t = m->n_tris - 1;
    lm_mesh_adj_unlink_tri(m, t);
    if (m->tri_alive[t])
        m->live_tris--;
    m->n_tris--;
}

static void undo_add_vert(lm_mesh *m)
{
    uint32_t v = m->n_verts - 1;
    if (m->vert_alive[v])
        m->live_verts--;
    m->n_verts--;
}

static void undo_step(lm_mesh *m, const jstep *s)
{
    switch (s->kind) {
    case J_POS:
        memcpy(m->pos[s->id], s->old.pos, sizeof m->pos[s->id]);
        break;
    case J_WEDGE:
        m->wedges[s->id] = s->old.wedge;
        break;
    case J_TRI:
        m->tris[s->id] = s->old.tri;
        break;
    case J_ADJ_INS:
        LM_ASSERT(m->internal->vtris[s->id].data[s->idx] == s->aux);
        vec_remove_at(&m->internal->vtris[s->id], s->idx);
        break;
    case J_ADJ_DEL:
        vec_insert_at(&m->internal->vtris[s->id], s->idx, s->aux);
        break;
    case J_KILL_VERT:
        m->vert_alive[s->id] = 1;
        m->live_verts++;
        break;
    case J_KILL_WEDGE:
        m->wedge_alive[s->id] = 1;
        break;
    case J_KILL_TRI:
        m->tri_alive[s->id] = 1;
        m->live_tris++;
        break;
    case J_ADD_VERT:
        LM_ASSERT(s->id + 1 == m->n_verts);
        undo_add_vert(m);
        break;
    case J_ADD_WEDGE:
        LM_ASSERT(s->id + 1 == m->n_wedges);
        m->n_wedges--;
        break;
    case J_ADD_TRI:
        LM_ASSERT(s->id + 1 == m->n_tris);
        undo_add_tri(m);
        break;
    default:
        LM_ASSERT(!"unknown journal step");
    }
}

void lm_journal_scan(const lm_journal *j, size_t mark, lm_journal_visit_fn fn, void *ctx)
{
    LM_ASSERT(mark <= j->n);
    for (size_t i = mark; i < j->n; i++) {
        const jstep *s = &j->steps[i];
        switch (s->kind) {
        case J_POS:
        case J_KILL_VERT:
        case J_ADD_VERT:
            fn(ctx, LM_TOUCH_VERTEX, s->id);
            break;
        case J_WEDGE:
        case J_KILL_WEDGE:
        case J_ADD_WEDGE:
            fn(ctx, LM_TOUCH_WEDGE, s->id);
            break;
        case J_TRI:
            fn(ctx, LM_TOUCH_TRI, s->id);
            break;
        case J_KILL_TRI:
            fn(ctx, LM_TOUCH_TRI_KILLED, s->id);
            break;
        case J_ADD_TRI:
            fn(ctx, LM_TOUCH_TRI_ADDED, s->id);
            break;
        default: /* adjacency steps follow from the triangle steps */
            break;
        }
    }
}

void lm_journal_rollback(lm_mesh *m, lm_journal *j, size_t mark)
{
    LM_ASSERT(mark <= j->n);
    while (j->n > mark)
        undo_step(m, &j->steps[--j->n]);
}

/* ---- building adjacency -------------------------------------------------------------------- */

static void tri_vertices(const lm_mesh *m, uint32_t t, uint32_t v[3])
{
    for (int k = 0; k < 3; k++)
        v[k] = lm_tri_vertex(m, t, k);
}

static int tri_has_vertex(const lm_mesh *m, uint32_t t, uint32_t v)
{
    return lm_tri_vertex(m, t, 0) == v || lm_tri_vertex(m, t, 1) == v ||
           lm_tri_vertex(m, t, 2) == v;
}

/* Distinct vertices of alive triangle t, in corner order; returns their count. */
static int tri_distinct(const lm_mesh *m, uint32_t t, uint32_t v[3])
{
    uint32_t c[3];
    int n = 0;
    tri_vertices(m, t, c);
    for (int k = 0; k < 3; k++)
        if ((k < 1 || c[k] != c[0]) && (k < 2 || c[k] != c[1]))
            v[n++] = c[k];
    return n;
}

static lm_status check_tri_refs(const lm_mesh *m, uint32_t t)
{
    for (int k = 0; k < 3; k++) {
        uint32_t w = m->tris[t].w[k];
        if (w >= m->n_wedges || m->wedges[w].vertex >= m->n_verts)
            return lm_fail(LM_E_RANGE, "triangle %u refers to a missing corner or vertex", t);
    }
    return LM_OK;
}

lm_status lm_mesh_build_adjacency(lm_mesh *m)
{
    lm_status s = lm_mesh_adj_reserve(m, m->n_verts);
    if (s)
        return s;
    struct lm_mesh_internal *in = m->internal;
    in->adjacency_built = 0;
    for (uint32_t v = 0; v < in->cap_vtris; v++)
        in->vtris[v].n = 0;
    /* First pass: count (stored in n), reserve; second pass: fill in ascending triangle order. */
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        if ((s = check_tri_refs(m, t)))
            return s;
        uint32_t v[3];
        int n = tri_distinct(m, t, v);
        for (int k = 0; k < n; k++)
            in->vtris[v[k]].n++;
    }
    for (uint32_t v = 0; v < m->n_verts; v++) {
        uint32_t need = in->vtris[v].n;
        in->vtris[v].n = 0;
        if ((s = vec_reserve(&in->vtris[v], need)))
            return s;
    }
    for (uint32_t t = 0; t < m->n_tris; t++) {
        uint32_t v[3];
        int n = m->tri_alive[t] ? tri_distinct(m, t, v) : 0;
        for (int k = 0; k < n; k++)
            in->vtris[v[k]].data[in->vtris[v[k]].n++] = t;
    }
    in->adjacency_built = 1;
    return LM_OK;
}

/* ---- queries -------------------------------------------------------------------------------- */

static int cmp_u32(const void *x, const void *y)
{
    uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
    return (a > b) - (a < b);
}

static void sort_u32(uint32_t *a, uint32_t n)
{
    if (n > 32) {
        qsort(a, n, sizeof *a, cmp_u32);
        return;
    }
    for (uint32_t i = 1; i < n; i++) {
        uint32_t x = a[i], k = i;
        for (; k > 0 && a[k - 1] > x; k--)
            a[k] = a[k - 1];
        a[k] = x;
    }
}

/* The other vertices of v's triangles (two per triangle, repeats kept), sorted. buf holds
 * 2 * (number of v's triangles). Returns the count. */
static uint32_t gather_nbrs(const lm_mesh *m, uint32_t v, uint32_t *buf)
{
    const lm_u32vec *l = vt(m, v);
    uint32_t n = 0;
    for (uint32_t i = 0; i < l->n; i++) {
        uint32_t c[3];
        tri_vertices(m, l->data[i], c);
        for (int k = 0; k < 3 && n < 2 * l->n; k++)
            if (c[k] != v)
                buf[n++] = c[k];
    }
    sort_u32(buf, n);
    return n;
}

/* Sorted neighbours with repeats in a stack buffer, or a heap one for huge valences.
 * The caller frees *heap. */
static uint32_t nbrs_any(const lm_mesh *m, uint32_t v, uint32_t *stack, uint32_t **heap)
{
    *heap = NULL;
    uint32_t need = 2 * vt(m, v)->n;
    uint32_t *buf = stack;
    if (need > 2 * LM_TOPO_MAX_VALENCE) {
        *heap = buf = malloc((size_t)need * sizeof *buf);
        LM_ASSERT(buf != NULL); /* a few MB at most for the absurd valence that gets here */
    }
    return gather_nbrs(m, v, buf);
}

uint32_t lm_mesh_vertex_tris(const lm_mesh *m, uint32_t v, uint32_t *out, uint32_t cap)
{
    LM_ASSERT(adjacency_ready(m));
    if (v >= m->n_verts)
        return 0;
    const lm_u32vec *l = vt(m, v);
    uint32_t n = l->n < cap ? l->n : cap;
    if (n)
        memcpy(out, l->data, (size_t)n * sizeof *out);
    return l->n;
}

uint32_t lm_mesh_vertex_neighbors(const lm_mesh *m, uint32_t v, uint32_t *out, uint32_t cap)
{
    LM_ASSERT(adjacency_ready(m));
    if (v >= m->n_verts)
        return 0;
    uint32_t stack[2 * LM_TOPO_MAX_VALENCE], *heap;
    uint32_t n = nbrs_any(m, v, stack, &heap);
    const uint32_t *buf = heap ? heap : stack;
    uint32_t d = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (i > 0 && buf[i] == buf[i - 1])
            continue;
        if (d < cap)
            out[d] = buf[i];
        d++;
    }
    free(heap);
    return d;
}

int lm_mesh_vertex_is_boundary(const lm_mesh *m, uint32_t v)
{
    LM_ASSERT(adjacency_ready(m));
    if (v >= m->n_verts)
        return 0;
    uint32_t stack[2 * LM_TOPO_MAX_VALENCE], *heap;
    uint32_t n = nbrs_any(m, v, stack, &heap);
    const uint32_t *buf = heap ? heap : stack;
    int boundary = 0;
    for (uint32_t i = 0; i < n && !boundary; i++)
        boundary = (i == 0 || buf[i] != buf[i - 1]) && (i + 1 == n || buf[i] != buf[i + 1]);
    free(heap);
    return boundary;
}

uint32_t lm_mesh_edge_tris(const lm_mesh *m, uint32_t a, uint32_t b, uint32_t *out, uint32_t cap)
{
    LM_ASSERT(adjacency_ready(m));
    if (a >= m->n_verts || b >= m->n_verts || a == b)
        return 0;
    const lm_u32vec *la = vt(m, a), *lb = vt(m, b);
    if (lb->n < la->n) {
        const lm_u32vec *x = la;
        la = lb;
        lb = x;
        uint32_t y = a;
        a = b;
        b = y;
    }
    uint32_t n = 0;
    for (uint32_t i = 0; i < la->n; i++) {
        if (!tri_has_vertex(m, la->data[i], b))
            continue;
        if (n < cap)
            out[n] = la->data[i];
        n++;
    }
    return n;
}

static uint32_t edge_count(const lm_mesh *m, uint32_t a, uint32_t b)
{
    return lm_mesh_edge_tris(m, a, b, NULL, 0);
}

int lm_mesh_edge_exists(const lm_mesh *m, uint32_t a, uint32_t b)
{
    return edge_count(m, a, b) > 0;
}

int lm_mesh_edge_is_boundary(const lm_mesh *m, uint32_t a, uint32_t b)
{
    return edge_count(m, a, b) == 1;
}

int lm_mesh_edge_is_manifold(const lm_mesh *m, uint32_t a, uint32_t b)
{
    uint32_t n = edge_count(m, a, b);
    return n == 1 || n == 2;
}

/* Wedge of vertex v in triangle t (LM_NONE if v is not a corner). */
static uint32_t wedge_of(const lm_mesh *m, uint32_t t, uint32_t v)
{
    for (int k = 0; k < 3; k++)
        if (m->wedges[m->tris[t].w[k]].vertex == v)
            return m->tris[t].w[k];
    return LM_NONE;
}

int lm_mesh_edge_is_attr_seam(const lm_mesh *m, uint32_t a, uint32_t b)
{
    uint32_t t[LM_TOPO_MAX_VALENCE];
    uint32_t n = lm_mesh_edge_tris(m, a, b, t, LM_TOPO_MAX_VALENCE);
    if (n > LM_TOPO_MAX_VALENCE)
        n = LM_TOPO_MAX_VALENCE;
    for (uint32_t i = 1; i < n; i++)
        if (wedge_of(m, t[i], a) != wedge_of(m, t[0], a) ||
            wedge_of(m, t[i], b) != wedge_of(m, t[0], b))
            return 1;
    return 0;
}

/* ---- edges and Euler characteristic -------------------------------------------------------- */

static int cmp_u64(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

lm_status lm_mesh_list_edges(const lm_mesh *m, uint32_t (**out)[2], size_t *count)
{
    *out = NULL;
    *count = 0;
    uint64_t *keys = malloc(((size_t)m->live_tris * 3 + 1) * sizeof *keys);
    if (!keys)
        return lm_fail(LM_E_NOMEM, "out of memory listing the edges of %u triangles", m->live_tris);
    size_t n = 0;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        uint32_t v[3];
        tri_vertices(m, t, v);
        for (int k = 0; k < 3 && n < (size_t)m->live_tris * 3; k++) {
            uint32_t a = v[k], b = v[(k + 1) % 3];
            if (a != b)
                keys[n++] = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
        }
    }
    qsort(keys, n, sizeof *keys, cmp_u64);
    size_t d = 0;
    for (size_t i = 0; i < n; i++)
        if (i == 0 || keys[i] != keys[i - 1])
            keys[d++] = keys[i];
    uint32_t(*e)[2] = malloc((d + 1) * sizeof *e);
    if (!e) {
        free(keys);
        return lm_fail(LM_E_NOMEM, "out of memory listing %zu edges", d);
    }
    for (size_t i = 0; i < d; i++) {
        e[i][0] = (uint32_t)(keys[i] >> 32);
        e[i][1] = (uint32_t)keys[i];
    }
    free(keys);
    *out = e;
    *count = d;
    return LM_OK;
}

long lm_mesh_euler_characteristic(const lm_mesh *m)
{
    uint32_t(*e)[2];
    size_t ne;
    LM_ASSERT(lm_mesh_list_edges(m, &e, &ne) == LM_OK);
    free(e);
    long v = 0, f = 0;
    for (uint32_t i = 0; i < m->n_verts; i++)
        v += m->vert_alive[i] != 0;
    for (uint32_t t = 0; t < m->n_tris; t++)
        f += m->tri_alive[t] != 0;
    return v - (long)ne + f;
}

/* ---- attribute edits ------------------------------------------------------------------------ */

void lm_mesh_set_pos(lm_mesh *m, uint32_t v, const float p[3], lm_journal *j)
{
    LM_ASSERT(v < m->n_verts);
    LM_ASSERT(journal_reserve(j, 1) == LM_OK);
    p_set_pos(m, v, p, j);
}

/* The owning vertex is kept (a wedge cannot move to another vertex through this call). */
void lm_mesh_set_wedge(lm_mesh *m, uint32_t w, const lm_wedge *value, lm_journal *j)
{
    LM_ASSERT(w < m->n_wedges);
    LM_ASSERT(journal_reserve(j, 1) == LM_OK);
    lm_wedge x = *value;
    x.vertex = m->wedges[w].vertex;
    p_set_wedge(m, w, &x, j);
}

/* Mean of n wedges' attributes (vertex taken from the first). */
static lm_wedge wedge_mean(const lm_mesh *m, const uint32_t *w, int n)
{
    lm_wedge r = m->wedges[w[0]];
    for (int i = 1; i < n; i++) {
        const lm_wedge *x = &m->wedges[w[i]];
        for (int k = 0; k < 3; k++)
            r.normal[k] += x->normal[k];
        for (int k = 0; k < 2; k++)
            r.uv[k] += x->uv[k];
        for (int k = 0; k < 4; k++)
            r.color[k] += x->color[k];
    }
    float s = 1.0f / (float)n;
    for (int k = 0; k < 3; k++)
        r.normal[k] *= s;
    for (int k = 0; k < 2; k++)
        r.uv[k] *= s;
    for (int k = 0; k < 4; k++)
        r.color[k] *= s;
    return r;
}

/* Common preamble of the edge operations: ids in range, alive, adjacency available. */
static lm_status edge_op_begin(lm_mesh *m, uint32_t a, uint32_t b, const char *what)
{
    if (a >= m->n_verts || b >= m->n_verts)
        return lm_fail(LM_E_RANGE, "%s: vertex %u or %u out of range (%u vertices)", what, a, b,
                       m->n_verts);
    if (a == b || !m->vert_alive[a] || !m->vert_alive[b])
        return lm_fail(LM_E_ILLEGAL, "%s: edge (%u, %u) does not exist", what, a, b);
    if (!adjacency_ready(m)) {
        lm_status s = lm_mesh_build_adjacency(m);
        if (s)
            return s;
    }
    if (vt(m, a)->n > LM_TOPO_MAX_VALENCE || vt(m, b)->n > LM_TOPO_MAX_VALENCE)
        return lm_fail(LM_E_RANGE, "%s: vertex %u or %u has more than %u triangles", what, a, b,
                       LM_TOPO_MAX_VALENCE);
    return LM_OK;
}

/* Triangles on edge (a, b): 1 or 2 (else LM_E_ILLEGAL). */
static lm_status manifold_edge(const lm_mesh *m, uint32_t a, uint32_t b, uint32_t t[2], uint32_t *k,
                               const char *what)
{
    *k = lm_mesh_edge_tris(m, a, b, t, 2);
    if (*k == 0)
        return lm_fail(LM_E_ILLEGAL, "%s: edge (%u, %u) does not exist", what, a, b);
    if (*k > 2)
        return lm_fail(LM_E_ILLEGAL, "%s: edge (%u, %u) is non-manifold (%u triangles)", what, a, b,
                       *k);
    return LM_OK;
}

/* Third vertex of triangle t with edge (a, b). */
static uint32_t opposite(const lm_mesh *m, uint32_t t, uint32_t a, uint32_t b)
{
    for (int k = 0; k < 3; k++) {
        uint32_t v = lm_tri_vertex(m, t, k);
        if (v != a && v != b)
            return v;
    }
    return LM_NONE;
}

/* ---- edge collapse: legality ------------------------------------------------------------- */

typedef struct collapse_ctx {
    uint32_t a, b, k;
    uint32_t dying[2], opp[2], wa[2], wb[2];
    uint32_t nopp, opps[2]; /* distinct opposite vertices, ascending */
} collapse_ctx;

static int is_dying(const collapse_ctx *c, uint32_t t)
{
    return t == c->dying[0] || (c->k > 1 && t == c->dying[1]);
}

static lm_status collapse_find(const lm_mesh *m, collapse_ctx *c)
{
    lm_status s = manifold_edge(m, c->a, c->b, c->dying, &c->k, "collapse");
    if (s)
        return s;
    for (uint32_t i = 0; i < c->k; i++) {
        c->opp[i] = opposite(m, c->dying[i], c->a, c->b);
        c->wa[i] = wedge_of(m, c->dying[i], c->a);
        c->wb[i] = wedge_of(m, c->dying[i], c->b);
        if (c->opp[i] == LM_NONE)
            return lm_fail(LM_E_ILLEGAL, "collapse: triangle %u is degenerate", c->dying[i]);
    }
    c->nopp = 1;
    c->opps[0] = c->opp[0];
    if (c->k == 2 && c->opp[1] != c->opp[0]) {
        c->nopp = 2;
        c->opps[0] = c->opp[0] < c->opp[1] ? c->opp[0] : c->opp[1];
        c->opps[1] = c->opp[0] < c->opp[1] ? c->opp[1] : c->opp[0];
    }
    return LM_OK;
}

static int has_single_run(const uint32_t *x, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        if ((i == 0 || x[i] != x[i - 1]) && (i + 1 == n || x[i] != x[i + 1]))
            return 1;
    return 0;
}

/* Boundary rule and link condition: the common neighbours of a and b must be exactly the
 * vertices opposite the edge. */
static lm_status collapse_check_link(const lm_mesh *m, const collapse_ctx *c)
{
    uint32_t na[2 * LM_TOPO_MAX_VALENCE], nb[2 * LM_TOPO_MAX_VALENCE];
    uint32_t ka = gather_nbrs(m, c->a, na), kb = gather_nbrs(m, c->b, nb);
    if (c->k == 2 && has_single_run(na, ka) && has_single_run(nb, kb))
        return lm_fail(LM_E_ILLEGAL,
                       "collapse: (%u, %u) is an interior edge between two "
                       "boundary vertices",
                       c->a, c->b);
    uint32_t i = 0, k = 0, common = 0;
    while (i < ka && k < kb) {
        if (na[i] < nb[k]) {
            i++;
        } else if (na[i] > nb[k]) {
            k++;
        } else {
            uint32_t x = na[i];
            if (x != c->a && x != c->b) {
                if (common >= c->nopp || c->opps[common] != x)
                    return lm_fail(LM_E_ILLEGAL,
                                   "collapse: (%u, %u) fails the link condition "
                                   "(common neighbour %u)",
                                   c->a, c->b, x);
                common++;
            }
            while (i < ka && na[i] == x)
                i++;
            while (k < kb && nb[k] == x)
                k++;
        }
    }
    if (common != c->nopp)
        return lm_fail(LM_E_INTERNAL, "collapse: opposite vertex of (%u, %u) not a neighbour", c->a,
                       c->b);
    return LM_OK;
}

/* Does a surviving triangle of v contain both x and y? */
static int has_tri_with(const lm_mesh *m, const collapse_ctx *c, uint32_t v, uint32_t x, uint32_t y)
{
    const lm_u32vec *l = vt(m, v);
    for (uint32_t i = 0; i < l->n; i++)
        if (!is_dying(c, l->data[i]) && tri_has_vertex(m, l->data[i], x) &&
            tri_has_vertex(m, l->data[i], y))
            return 1;
    return 0;
}

/* No duplicate triangles, no vertex left without triangles. Runs after the link check, so a
 * duplicate can only come from b's triangle over both opposite vertices. */
static lm_status collapse_check_local(const lm_mesh *m, const collapse_ctx *c)
{
    const lm_u32vec *lb = vt(m, c->b);
    for (uint32_t i = 0; c->nopp == 2 && i < lb->n; i++) {
        uint32_t t = lb->data[i];
        if (!is_dying(c, t) && tri_has_vertex(m, t, c->opps[0]) &&
            tri_has_vertex(m, t, c->opps[1]) && has_tri_with(m, c, c->a, c->opps[0], c->opps[1]))
            return lm_fail(LM_E_ILLEGAL, "collapse: (%u, %u) would create a duplicate triangle",
                           c->a, c->b);
    }
    for (uint32_t i = 0; i < c->nopp; i++) {
        const lm_u32vec *l = vt(m, c->opps[i]);
        uint32_t alive = 0;
        for (uint32_t k = 0; k < l->n; k++)
            alive += !is_dying(c, l->data[k]);
        if (!alive)
            return lm_fail(LM_E_ILLEGAL,
                           "collapse: (%u, %u) would leave vertex %u without "
                           "triangles",
                           c->a, c->b, c->opps[i]);
    }
    return LM_OK;
}

/* The component of a after the collapse must keep at least 4 vertices: a bounded search over
 * the collapsed mesh (b read as a, dying triangles skipped) that stops at the 4th vertex. */
static lm_status collapse_check_component(const lm_mesh *m, const collapse_ctx *c)
{
    uint32_t seen[4] = {c->a}, ns = 1;
    for (uint32_t i = 0; i < ns; i++) {
        for (int pass = 0; pass < (seen[i] == c->a ? 2 : 1); pass++) {
            const lm_u32vec *l = vt(m, pass ? c->b : seen[i]);
            for (uint32_t q = 0; q < l->n; q++) {
                if (is_dying(c, l->data[q]))
                    continue;
                for (int k = 0; k < 3; k++) {
                    uint32_t u = lm_tri_vertex(m, l->data[q], k);
                    u = u == c->b ? c->a : u;
                    int known = 0;
                    for (uint32_t s = 0; s < ns; s++)
                        known |= seen[s] == u;
                    if (!known)
                        seen[ns++] = u;
                    if (ns == 4)
                        return LM_OK;
                }
            }
        }
    }
    return lm_fail(LM_E_ILLEGAL, "collapse: (%u, %u) would leave a component of %u vertices", c->a,
                   c->b, ns);
}

/* ---- edge collapse: mutation --------------------------------------------------------------- */

/* b's wedge on each dying triangle merges into a's wedge on it; targets take the mean. */
static void collapse_merge_wedges(lm_mesh *m, const collapse_ctx *c, lm_journal *j)
{
    for (uint32_t i = 0; i < c->k; i++) {
        if (i == 1 && c->wa[1] == c->wa[0])
            continue;
        uint32_t src[3] = {c->wa[i]};
        int n = 1;
        for (uint32_t q = 0; q < c->k; q++) {
            int dup = 0;
            for (int s = 1; s < n; s++)
                dup |= src[s] == c->wb[q];
            if (c->wa[q] == c->wa[i] && !dup)
                src[n++] = c->wb[q];
        }
        lm_wedge w = wedge_mean(m, src, n);
        p_set_wedge(m, c->wa[i], &w, j);
    }
}

/* Target of b's wedge w when it merges (LM_NONE: it is reassigned to a instead). */
static uint32_t merge_target(const collapse_ctx *c, uint32_t w)
{
    for (uint32_t i = 0; i < c->k; i++)
        if (c->wb[i] == w)
            return c->wa[i];
    return LM_NONE;
}

/* Move b's surviving triangles to a: corners on merged wedges are remapped, b's other wedges
 * change owner. */
static void collapse_move_tris(lm_mesh *m, const collapse_ctx *c, lm_journal *j)
{
    lm_u32vec *lb = &m->internal->vtris[c->b];
    while (lb->n > 0) {
        uint32_t t = lb->data[0];
        lm_tri tri = m->tris[t];
        for (int k = 0; k < 3; k++) {
            uint32_t w = tri.w[k];
            if (m->wedges[w].vertex != c->b)
                continue;
            uint32_t to = merge_target(c, w);
            if (to != LM_NONE) {
                tri.w[k] = to;
                p_set_tri(m, t, &tri, j);
            } else {
                lm_wedge x = m->wedges[w];
                x.vertex = c->a;
                p_set_wedge(m, w, &x, j);
            }
        }
        p_adj_del(m, c->b, t, j);
        p_adj_ins(m, c->a, t, j);
    }
}

static int wedge_used(const lm_mesh *m, uint32_t w)
{
    const lm_u32vec *l = vt(m, m->wedges[w].vertex);
    for (uint32_t i = 0; i < l->n; i++) {
        const lm_tri *t = &m->tris[l->data[i]];
        if (t->w[0] == w || t->w[1] == w || t->w[2] == w)
            return 1;
    }
    return 0;
}

/* Kill merged wedges of b and the wedges of the dead triangles nobody uses any more. */
static void collapse_kill_wedges(lm_mesh *m, const collapse_ctx *c, const lm_tri dead[2],
                                 lm_journal *j)
{
    for (uint32_t i = 0; i < c->k; i++) {
        if (m->wedge_alive[c->wb[i]])
            p_kill_wedge(m, c->wb[i], j);
        for (int k = 0; k < 3; k++) {
            uint32_t w = dead[i].w[k];
            if (m->wedge_alive[w] && !wedge_used(m, w))
                p_kill_wedge(m, w, j);
        }
    }
}

static void collapse_apply(lm_mesh *m, const collapse_ctx *c, const float p[3], lm_journal *j)
{
    lm_tri dead[2];
    for (uint32_t i = 0; i < c->k; i++) {
        dead[i] = m->tris[c->dying[i]];
        p_kill_tri(m, c->dying[i], j);
    }
    collapse_merge_wedges(m, c, j);
    collapse_move_tris(m, c, j);
    collapse_kill_wedges(m, c, dead, j);
    p_kill_vert(m, c->b, j);
    if (p)
        p_set_pos(m, c->a, p, j);
}

lm_status lm_mesh_collapse_edge(lm_mesh *m, uint32_t a, uint32_t b, const float p[3], lm_journal *j)
{
    lm_status s = edge_op_begin(m, a, b, "collapse");
    if (s)
        return s;
    if (p && (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])))
        return lm_fail(LM_E_RANGE, "collapse: position for vertex %u is not finite", a);
    collapse_ctx c = {.a = a, .b = b};
    if ((s = collapse_find(m, &c)) || (s = collapse_check_link(m, &c)) ||
        (s = collapse_check_local(m, &c)) || (s = collapse_check_component(m, &c)))
        return s;
    uint32_t nb = vt(m, b)->n;
    /* Dying: 4 steps each; per moved triangle <= 3; wedges <= 2 set + 8 killed; vertex, pos. */
    if ((s = journal_reserve(j, 20 + 3 * (size_t)nb)) || (s = adj_reserve(m, a, nb)))
        return s;
    collapse_apply(m, &c, p, j);
    return LM_OK;
}

/* ---- edge split ------------------------------------------------------------------------------ */

typedef struct split_ctx {
    uint32_t a, b, k, mv;
    uint32_t t[2], wm[2], added_tris;
    int added_vert, added_wedges;
} split_ctx;

static void split_undo_appends(lm_mesh *m, split_ctx *c)
{
    for (; c->added_tris > 0; c->added_tris--)
        undo_add_tri(m);
    for (; c->added_wedges > 0; c->added_wedges--)
        m->n_wedges--;
    if (c->added_vert)
        undo_add_vert(m);
    c->added_vert = 0;
}

/* Appends the midpoint vertex, one wedge per distinct (wedge of a, wedge of b) side pair, and the
 * (m, b, c) half of each side triangle. */
static lm_status split_append(lm_mesh *m, split_ctx *c)
{
    float p[3];
    for (int k = 0; k < 3; k++)
        p[k] = 0.5f * (m->pos[c->a][k] + m->pos[c->b][k]);
    lm_status s = lm_mesh_add_vertex(m, p, &c->mv);
    if (s)
        return s;
    c->added_vert = 1;
    for (uint32_t i = 0; i < c->k; i++) {
        uint32_t w[2] = {wedge_of(m, c->t[i], c->a), wedge_of(m, c->t[i], c->b)};
        if (i == 1 && w[0] == wedge_of(m, c->t[0], c->a) && w[1] == wedge_of(m, c->t[0], c->b)) {
            c->wm[1] = c->wm[0];
            continue;
        }
        lm_wedge x = wedge_mean(m, w, 2);
        x.vertex = c->mv;
        if ((s = lm_mesh_add_wedge(m, &x, &c->wm[i])))
            return s;
        c->added_wedges++;
    }
    if ((s = lm_mesh_adj_reserve(m, m->n_verts)))
        return s;
    for (uint32_t i = 0; i < c->k; i++) {
        lm_tri half = m->tris[c->t[i]];
        for (int k = 0; k < 3; k++)
            if (m->wedges[half.w[k]].vertex == c->a)
                half.w[k] = c->wm[i];
        uint32_t before = m->n_tris, id = LM_NONE;
        s = lm_mesh_add_tri(m, half.w, half.material, &id);
        c->added_tris += m->n_tris - before;
        if (id != LM_NONE && id < m->n_tris)
            m->tris[id].part = half.part; /* the new half stays in its triangle's part */
        if (s)
            return s;
    }
    return vec_reserve(&m->internal->vtris[c->mv], c->k);
}

lm_status lm_mesh_split_edge(lm_mesh *m, uint32_t a, uint32_t b, uint32_t *out_v, lm_journal *j)
{
    lm_status s = edge_op_begin(m, a, b, "split");
    split_ctx c = {.a = a, .b = b};
    if (s || (s = manifold_edge(m, a, b, c.t, &c.k, "split")) || (s = journal_reserve(j, 16)))
        return s;
    uint32_t w0 = m->n_wedges, t0 = m->n_tris;
    if ((s = split_append(m, &c))) {
        split_undo_appends(m, &c);
        return s;
    }
    jpush(j, J_ADD_VERT, c.mv);
    for (uint32_t i = 0; i < (uint32_t)c.added_wedges; i++)
        jpush(j, J_ADD_WEDGE, w0 + i);
    for (uint32_t i = 0; i < c.added_tris; i++)
        jpush(j, J_ADD_TRI, t0 + i);
    for (uint32_t i = 0; i < c.k; i++) { /* the old triangle keeps its id as (a, m, c) */
        lm_tri tri = m->tris[c.t[i]];
        for (int k = 0; k < 3; k++)
            if (m->wedges[tri.w[k]].vertex == b)
                tri.w[k] = c.wm[i];
        p_set_tri(m, c.t[i], &tri, j);
        p_adj_del(m, b, c.t[i], j);
        p_adj_ins(m, c.mv, c.t[i], j);
    }
    if (out_v)
        *out_v = c.mv;
    return LM_OK;
}

/* ---- edge swap ------------------------------------------------------------------------------- */

/* Corner index of vertex v in triangle t (-1 if absent). */
static int corner_of(const lm_mesh *m, uint32_t t, uint32_t v)
{
    for (int k = 0; k < 3; k++)
        if (lm_tri_vertex(m, t, k) == v)
            return k;
    return -1;
}

/* Orders the two triangles so that t[0] runs a -> b and t[1] runs b -> a. */
static lm_status swap_orient(const lm_mesh *m, uint32_t a, uint32_t b, uint32_t t[2])
{
    int dir[2];
    for (int i = 0; i < 2; i++)
        dir[i] = lm_tri_vertex(m, t[i], (corner_of(m, t[i], a) + 1) % 3) == b;
    if (dir[0] == dir[1])
        return lm_fail(LM_E_ILLEGAL,
                       "swap: triangles %u and %u on (%u, %u) are oriented "
                       "inconsistently",
                       t[0], t[1], a, b);
    if (!dir[0]) {
        uint32_t x = t[0];
        t[0] = t[1];
        t[1] = x;
    }
    return LM_OK;
}

static lm_status swap_check(const lm_mesh *m, uint32_t a, uint32_t b, uint32_t t[2])
{
    uint32_t k;
    lm_status s = manifold_edge(m, a, b, t, &k, "swap");
    if (s)
        return s;
    if (k != 2)
        return lm_fail(LM_E_ILLEGAL, "swap: (%u, %u) is a boundary edge", a, b);
    if ((s = swap_orient(m, a, b, t)))
        return s;
    if (wedge_of(m, t[0], a) != wedge_of(m, t[1], a) ||
        wedge_of(m, t[0], b) != wedge_of(m, t[1], b))
        return lm_fail(LM_E_ILLEGAL, "swap: (%u, %u) is an attribute seam", a, b);
    if (m->tris[t[0]].material != m->tris[t[1]].material)
        return lm_fail(LM_E_ILLEGAL, "swap: triangles on (%u, %u) have different materials", a, b);
    if (m->tris[t[0]].part != m->tris[t[1]].part)
        return lm_fail(LM_E_ILLEGAL, "swap: triangles on (%u, %u) are in different parts", a, b);
    uint32_t c = opposite(m, t[0], a, b), d = opposite(m, t[1], a, b);
    if (c == LM_NONE || d == LM_NONE || c == d || lm_mesh_edge_exists(m, c, d))
        return lm_fail(LM_E_ILLEGAL, "swap: (%u, %u) would create an existing edge", a, b);
    return LM_OK;
}

lm_status lm_mesh_swap_edge(lm_mesh *m, uint32_t a, uint32_t b, lm_journal *j)
{
    uint32_t t[2];
    lm_status s = edge_op_begin(m, a, b, "swap");
    if (s || (s = swap_check(m, a, b, t)))
        return s;
    uint32_t c = opposite(m, t[0], a, b), d = opposite(m, t[1], a, b);
    if ((s = journal_reserve(j, 6)) || (s = adj_reserve(m, c, 1)) || (s = adj_reserve(m, d, 1)))
        return s;
    /* (a, b, c) -> (a, d, c) and (b, a, d) -> (b, c, d): the quad a-d-b-c with diagonal cd. */
    lm_tri t0 = m->tris[t[0]], t1 = m->tris[t[1]];
    t0.w[corner_of(m, t[0], b)] = m->tris[t[1]].w[corner_of(m, t[1], d)];
    t1.w[corner_of(m, t[1], a)] = m->tris[t[0]].w[corner_of(m, t[0], c)];
    p_set_tri(m, t[0], &t0, j);
    p_set_tri(m, t[1], &t1, j);
    p_adj_del(m, b, t[0], j);
    p_adj_ins(m, d, t[0], j);
    p_adj_del(m, a, t[1], j);
    p_adj_ins(m, c, t[1], j);
    return LM_OK;
}

/* ---- wedge merging ------------------------------------------------------------------------- */

typedef struct wedge_key {
    uint32_t vertex;
    float attr[9]; /* selected attributes, others zero */
    uint32_t id;
} wedge_key;

static int cmp_wedge_key(const void *x, const void *y)
{
    const wedge_key *a = x, *b = y;
    if (a->vertex != b->vertex)
        return a->vertex < b->vertex ? -1 : 1;
    int c = memcmp(a->attr, b->attr, sizeof a->attr);
    if (c)
        return c;
    return (a->id > b->id) - (a->id < b->id);
}

static wedge_key make_key(const lm_wedge *w, uint32_t id, uint32_t attrs)
{
    wedge_key k;
    memset(&k, 0, sizeof k);
    k.vertex = w->vertex;
    k.id = id;
    if (attrs & LM_ATTR_NORMAL)
        memcpy(k.attr, w->normal, sizeof w->normal);
    if (attrs & LM_ATTR_UV)
        memcpy(k.attr + 3, w->uv, sizeof w->uv);
    if (attrs & LM_ATTR_COLOR)
        memcpy(k.attr + 5, w->color, sizeof w->color);
    return k;
}

uint32_t lm_mesh_merge_wedges(lm_mesh *m, uint32_t compare_attrs)
{
    wedge_key *keys = malloc(((size_t)m->n_wedges + 1) * sizeof *keys);
    uint32_t *map = malloc(((size_t)m->n_wedges + 1) * sizeof *map);
    if (!keys || !map) {
        free(keys);
        free(map);
        lm_fail(LM_E_NOMEM, "out of memory merging %u wedges", m->n_wedges);
        return 0;
    }
    uint32_t n = 0, merged = 0;
    for (uint32_t i = 0; i < m->n_wedges; i++) {
        map[i] = i;
        if (m->wedge_alive[i])
            keys[n++] = make_key(&m->wedges[i], i, compare_attrs);
    }
    qsort(keys, n, sizeof *keys, cmp_wedge_key);
    for (uint32_t i = 1, first = 0; i < n; i++) {
        if (keys[i].vertex != keys[first].vertex ||
            memcmp(keys[i].attr, keys[first].attr, sizeof keys[i].attr) != 0) {
            first = i;
            continue;
        }
        map[keys[i].id] = keys[first].id;
        m->wedge_alive[keys[i].id] = 0;
        merged++;
    }
    for (uint32_t t = 0; t < m->n_tris && merged; t++)
        for (int k = 0; k < 3; k++)
            if (m->tris[t].w[k] < m->n_wedges)
                m->tris[t].w[k] = map[m->tris[t].w[k]];
    free(keys);
    free(map);
    return merged;
}
