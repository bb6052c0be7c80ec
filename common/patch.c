/* common/patch.c — building patches (removed ids + added triangle records) from a mesh, and the
 * one way a whole mesh is sent to the views (lm_views_set_mesh_from), and the views' optional ops
 * with their stand-ins (lm_views_retarget, lm_views_evaluate_overlapped, lm_views_surface_term). */
#include "common/patch.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/mesh_topology.h"
#include "common/views_api.h"

void lm_tri_data_from_mesh(const lm_mesh *m, uint32_t t, lm_tri_data *out)
{
    const lm_tri *tri = &m->tris[t];
    out->id = t;
    out->material = tri->material;
    for (int k = 0; k < 3; k++) {
        const lm_wedge *w = &m->wedges[tri->w[k]];
        lm_corner *c = &out->c[k];
        memcpy(c->pos, m->pos[w->vertex], sizeof c->pos);
        memcpy(c->normal, w->normal, sizeof c->normal);
        memcpy(c->uv, w->uv, sizeof c->uv);
        memcpy(c->color, w->color, sizeof c->color);
    }
}

lm_status lm_mesh_export_tris(const lm_mesh *m, lm_tri_data **out, size_t *count)
{
    lm_tri_data *d = malloc(((size_t)m->live_tris + 1) * sizeof *d);
    if (!d)
        return lm_fail(LM_E_NOMEM, "out of memory exporting %u triangles", m->live_tris);
    size_t n = 0;
    for (uint32_t t = 0; t < m->n_tris; t++)
        if (m->tri_alive[t])
            lm_tri_data_from_mesh(m, t, &d[n++]);
    *out = d;
    *count = n;
    return LM_OK;
}

void lm_patch_init(lm_patch *p)
{
    memset(p, 0, sizeof *p);
}

void lm_patch_reset(lm_patch *p)
{
    p->n_removed = 0;
    p->n_added = 0;
}

void lm_patch_free(lm_patch *p)
{
    free(p->removed);
    free(p->added);
    lm_patch_init(p);
}

static lm_status reserve(void **arr, uint32_t *cap, uint32_t need, size_t elem)
{
    if (!lm_grow32(arr, cap, need, elem, 16))
        return lm_fail(LM_E_NOMEM, "out of memory building a patch");
    return LM_OK;
}

lm_status lm_patch_remove(lm_patch *p, uint32_t id)
{
    lm_status s =
        reserve((void **)&p->removed, &p->cap_removed, p->n_removed + 1, sizeof(uint32_t));
    if (!s)
        p->removed[p->n_removed++] = id;
    return s;
}

lm_status lm_patch_add(lm_patch *p, const lm_tri_data *t)
{
    lm_status s = reserve((void **)&p->added, &p->cap_added, p->n_added + 1, sizeof *t);
    if (!s)
        p->added[p->n_added++] = *t;
    return s;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

lm_status lm_patch_build(lm_patch *p, const lm_mesh *m, const uint32_t *before, size_t n_before,
                         const uint32_t *now, size_t n_now)
{
    lm_patch_reset(p);
    lm_status s =
        reserve((void **)&p->removed, &p->cap_removed, (uint32_t)n_before + 1, sizeof(uint32_t));
    if (s)
        return s;
    memcpy(p->removed, before, n_before * sizeof *before);
    qsort(p->removed, n_before, sizeof *p->removed, cmp_u32);
    uint32_t k = 0;
    for (size_t i = 0; i < n_before; i++)
        if (k == 0 || p->removed[k - 1] != p->removed[i])
            p->removed[k++] = p->removed[i];
    p->n_removed = k;
    s = reserve((void **)&p->added, &p->cap_added, (uint32_t)n_now + 1, sizeof *p->added);
    uint32_t *ids = s ? NULL : malloc((n_now + 1) * sizeof *ids);
    if (!s && !ids)
        s = lm_fail(LM_E_NOMEM, "out of memory building a patch");
    if (s)
        return s;
    /* the live triangles of now by id, each once: ids sorted first, records read once each */
    size_t n = 0;
    for (size_t i = 0; i < n_now; i++)
        if (now[i] < m->n_tris && m->tri_alive[now[i]])
            ids[n++] = now[i];
    qsort(ids, n, sizeof *ids, cmp_u32);
    for (size_t i = 0; i < n; i++)
        if (i == 0 || ids[i - 1] != ids[i])
            lm_tri_data_from_mesh(m, ids[i], &p->added[p->n_added++]);
    free(ids);
    return LM_OK;
}

/* ---- the patch of a journal span ----------------------------------------------------------- */

typedef struct tri_event {
    uint32_t id; /* below m->n_tris */
    uint8_t born, died;
} tri_event;

typedef struct touched {
    uint32_t *verts, *tris;
    size_t n_verts, n_tris, cap_verts, cap_tris;
    tri_event *ev; /* the journal's triangle records (sorted by id once gathered) */
    size_t n_ev, cap_ev;
    const lm_mesh *m;
    lm_status st;
} touched;

static void push_id(touched *t, uint32_t **a, size_t *n, size_t *cap, uint32_t id)
{
    if (t->st)
        return;
    if (*n == *cap && !LM_GROW(a, cap, *n + 1, 64)) {
        t->st = lm_fail(LM_E_NOMEM, "out of memory gathering a change");
        return;
    }
    (*a)[(*n)++] = id;
}

static void visit(void *ctx, int what, uint32_t id)
{
    touched *t = ctx;
    switch (what) {
    case LM_TOUCH_VERTEX:
        push_id(t, &t->verts, &t->n_verts, &t->cap_verts, id);
        break;
    case LM_TOUCH_WEDGE:
        if (id < t->m->n_wedges)
            push_id(t, &t->verts, &t->n_verts, &t->cap_verts, t->m->wedges[id].vertex);
        break;
    default:
        if (id < t->m->n_tris && !t->st) {
            if (t->n_ev == t->cap_ev && !LM_GROW(&t->ev, &t->cap_ev, t->n_ev + 1, 16)) {
                t->st = lm_fail(LM_E_NOMEM, "out of memory gathering a change");
                return;
            }
            t->ev[t->n_ev++] =
                (tri_event){id, what == LM_TOUCH_TRI_ADDED, what == LM_TOUCH_TRI_KILLED};
        }
        push_id(t, &t->tris, &t->n_tris, &t->cap_tris, id);
    }
}

/* The triangles around every touched vertex join the touched ones. */
static void add_incident(touched *t)
{
    uint32_t buf[1024];
    size_t nv = t->n_verts;
    for (size_t i = 0; i < nv && !t->st; i++) {
        uint32_t v = t->verts[i];
        if (v >= t->m->n_verts || !t->m->vert_alive[v])
            continue;
        uint32_t n = lm_mesh_vertex_tris(t->m, v, buf, 1024);
        if (n > 1024) {
            t->st = lm_fail(LM_E_RANGE, "vertex %u has %u triangles (limit 1024)", v, n);
            return;
        }
        for (uint32_t k = 0; k < n; k++)
            push_id(t, &t->tris, &t->n_tris, &t->cap_tris, buf[k]);
    }
}

static int cmp_event(const void *a, const void *b)
{
    uint32_t x = ((const tri_event *)a)->id, y = ((const tri_event *)b)->id;
    return (x > y) - (x < y);
}

/* Whether the journal's records (sorted by id) say triangle id was born (added) and whether it
 * died (killed). */
static void born_died(const touched *t, uint32_t id, int *born, int *died)
{
    size_t lo = 0, hi = t->n_ev;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (t->ev[mid].id < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    *born = *died = 0;
    for (size_t i = lo; i < t->n_ev && t->ev[i].id == id; i++) {
        *born |= t->ev[i].born;
        *died |= t->ev[i].died;
    }
}

lm_status lm_patch_from_journal(lm_patch *p, const lm_mesh *m, const lm_journal *j, size_t mark)
{
    touched t = {.m = m};
    lm_journal_scan(j, mark, visit, &t);
    if (t.n_ev)
        qsort(t.ev, t.n_ev, sizeof *t.ev, cmp_event);
    add_incident(&t);
    uint32_t *before = t.st ? NULL : malloc((t.n_tris + 1) * sizeof *before);
    if (!t.st && !before)
        t.st = lm_fail(LM_E_NOMEM, "out of memory gathering a change");
    size_t nb = 0;
    for (size_t i = 0; i < t.n_tris && !t.st; i++) {
        uint32_t id = t.tris[i];
        int born, died;
        if (id >= m->n_tris)
            continue;
        born_died(&t, id, &born, &died);
        if (!born && (m->tri_alive[id] || died))
            before[nb++] = id;
    }
    if (!t.st)
        t.st = lm_patch_build(p, m, before, nb, t.tris, t.n_tris);
    free(before);
    free(t.verts);
    free(t.tris);
    free(t.ev);
    return t.st;
}

lm_status lm_views_set_mesh_from(lm_views *v, const lm_mesh *m)
{
    lm_tri_data *tris = NULL;
    size_t n = 0;
    lm_status st = lm_mesh_export_tris(m, &tris, &n);
    if (st != LM_OK)
        return st;
    st = v->ops->set_mesh(v, tris, n);
    free(tris);
    return st;
}

lm_status lm_views_retarget(lm_views *v)
{
    if (!v->ops->retarget)
        return lm_fail(LM_E_UNSUPPORTED, "these views cannot take their current images as "
                                         "targets (in-process views can)");
    return v->ops->retarget(v);
}

lm_status lm_views_evaluate_overlapped(lm_views *v, const lm_patch *patches, uint32_t n,
                                       int64_t *delta, void (*overlap)(void *ctx), void *ctx)
{
    if (v->ops->evaluate_overlapped)
        return v->ops->evaluate_overlapped(v, patches, n, delta, overlap, ctx);
    overlap(ctx);
    return v->ops->evaluate(v, patches, n, delta);
}

lm_status lm_views_surface_term(lm_views *v, const lm_mesh *surface, double k)
{
    if (!v->ops->surface_term)
        return lm_fail(LM_E_UNSUPPORTED, "these views do not price the geometric term");
    return v->ops->surface_term(v, surface, k);
}
