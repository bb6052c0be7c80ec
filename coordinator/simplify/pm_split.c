/* coordinator/simplify/pm_split.c — vertex splits captured from the journal of a collapse, and
 * the recorder that keeps them in collapse order. */
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "coordinator/simplify/pm.h"
#include "coordinator/simplify/pm_internal.h"

void co_pm_split_free(co_pm_split *s)
{
    free(s->verts);
    free(s->wedges);
    free(s->tris);
    memset(s, 0, sizeof *s);
}

typedef struct id_list {
    uint32_t *ids;
    size_t n, cap;
} id_list;

typedef struct touched {
    id_list v, w, t;
    lm_status st;
} touched;

static void push(touched *t, id_list *l, uint32_t id)
{
    if (t->st)
        return;
    if (l->n == l->cap && !LM_GROW(&l->ids, &l->cap, l->n + 1, 32)) {
        t->st = lm_fail(LM_E_NOMEM, "out of memory recording a vertex split");
        return;
    }
    l->ids[l->n++] = id;
}

static void visit(void *ctx, int what, uint32_t id)
{
    touched *t = ctx;
    push(t, what == LM_TOUCH_VERTEX ? &t->v : what == LM_TOUCH_WEDGE ? &t->w : &t->t, id);
}

static int cmp_u32(const void *x, const void *y)
{
    uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
    return (a > b) - (a < b);
}

static void sort_unique(id_list *l)
{
    if (l->n)
        qsort(l->ids, l->n, sizeof *l->ids, cmp_u32);
    size_t k = 0;
    for (size_t i = 0; i < l->n; i++)
        if (k == 0 || l->ids[i] != l->ids[k - 1])
            l->ids[k++] = l->ids[i];
    l->n = k;
}

/* The values of the touched elements in the mesh as it is (the state before the change). */
static lm_status read_values(const lm_mesh *m, const touched *t, co_pm_split *s)
{
    s->verts = calloc(t->v.n + 1, sizeof *s->verts);
    s->wedges = calloc(t->w.n + 1, sizeof *s->wedges);
    s->tris = calloc(t->t.n + 1, sizeof *s->tris);
    if (!s->verts || !s->wedges || !s->tris)
        return lm_fail(LM_E_NOMEM, "out of memory recording a vertex split");
    for (size_t i = 0; i < t->v.n; i++) {
        uint32_t id = t->v.ids[i];
        int in = id < m->n_verts;
        s->verts[i] = (co_pm_vert){.id = id, .alive = in && m->vert_alive[id]};
        if (in)
            memcpy(s->verts[i].pos, m->pos[id], sizeof s->verts[i].pos);
    }
    for (size_t i = 0; i < t->w.n; i++) {
        uint32_t id = t->w.ids[i];
        int in = id < m->n_wedges;
        s->wedges[i] = (co_pm_wedge){.id = id, .alive = in && m->wedge_alive[id]};
        if (in)
            s->wedges[i].w = m->wedges[id];
    }
    for (size_t i = 0; i < t->t.n; i++) {
        uint32_t id = t->t.ids[i];
        int in = id < m->n_tris;
        s->tris[i] = (co_pm_tri){.id = id, .alive = in && m->tri_alive[id]};
        if (in)
            s->tris[i].t = m->tris[id];
    }
    s->n_verts = (uint32_t)t->v.n;
    s->n_wedges = (uint32_t)t->w.n;
    s->n_tris = (uint32_t)t->t.n;
    return LM_OK;
}

lm_status co_pm_split_capture(lm_mesh *m, lm_journal *j, size_t mark, lm_status (*redo)(void *ctx),
                              void *ctx, co_pm_split *out)
{
    memset(out, 0, sizeof *out);
    touched t = {0};
    lm_journal_scan(j, mark, visit, &t);
    sort_unique(&t.v);
    sort_unique(&t.w);
    sort_unique(&t.t);
    lm_status st = t.st;
    if (st == LM_OK) {
        lm_journal_rollback(m, j, mark);
        st = read_values(m, &t, out);
        lm_status s2 = redo(ctx);
        st = st ? st : s2;
    }
    free(t.v.ids);
    free(t.w.ids);
    free(t.t.ids);
    if (st)
        co_pm_split_free(out);
    return st;
}

struct co_pm_recorder {
    co_pm_split *s;
    uint32_t n, cap;
};

lm_status co_pm_recorder_create(co_pm_recorder **out)
{
    *out = calloc(1, sizeof **out);
    return *out ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for the progressive mesh");
}

void co_pm_recorder_destroy(co_pm_recorder *r)
{
    if (!r)
        return;
    for (uint32_t i = 0; i < r->n; i++)
        co_pm_split_free(&r->s[i]);
    free(r->s);
    free(r);
}

lm_status co_pm_recorder_take(co_pm_recorder *r, co_pm_split *s)
{
    if (r->n == r->cap && !LM_GROW32(&r->s, &r->cap, (size_t)r->n + 1, 256))
        return lm_fail(LM_E_NOMEM, "out of memory for the progressive mesh");
    r->s[r->n++] = *s;
    memset(s, 0, sizeof *s);
    return LM_OK;
}

uint32_t co_pm_recorder_count(const co_pm_recorder *r)
{
    return r->n;
}

const co_pm_split *co_pm_recorder_at(const co_pm_recorder *r, uint32_t i)
{
    return &r->s[i];
}
