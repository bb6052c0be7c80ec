/* worker/render/shared/patch_prepare.c — a patch's checks against the current mesh and its
 * per-id marks, alike for both backends (see patch_prepare.h). */
#include "worker/render/shared/patch_prepare.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/mesh.h"

/* The added records' ids and materials; *need: ids the marks must hold. */
static lm_status check_added(const lm_patch *p, uint32_t n_mat, size_t *need)
{
    for (uint32_t i = 0; i < p->n_added; i++) {
        if (p->added[i].id >= LM_MESH_MAX_TRIS)
            return lm_fail(LM_E_RANGE, "patch adds triangle id %u beyond the limit",
                           p->added[i].id);
        if (p->added[i].material >= n_mat)
            return lm_fail(LM_E_RANGE, "patch triangle %u uses material %u of %u", p->added[i].id,
                           p->added[i].material, n_mat);
        *need = p->added[i].id + 1u > *need ? p->added[i].id + 1u : *need;
    }
    return LM_OK;
}

static lm_status grow(uint32_t **a, size_t old, size_t cap)
{
    uint32_t *b = realloc(*a, cap * sizeof *b);
    if (!b)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu triangle marks", cap);
    memset(b + old, 0, (cap - old) * sizeof *b);
    *a = b;
    return LM_OK;
}

static lm_status marks_reserve(wk_patch_marks *m, size_t need)
{
    if (need <= m->cap)
        return LM_OK;
    size_t cap = lm_grow_cap(m->cap, need, 1024, SIZE_MAX);
    if (grow(&m->removed, m->cap, cap) != LM_OK || grow(&m->added, m->cap, cap) != LM_OK)
        return LM_E_NOMEM;
    m->cap = cap;
    return LM_OK;
}

static uint32_t next_stamp(wk_patch_marks *m)
{
    if (++m->now == 0) {
        memset(m->removed, 0, m->cap * sizeof *m->removed);
        memset(m->added, 0, m->cap * sizeof *m->added);
        m->now = 1;
    }
    return m->now;
}

lm_status wk_patch_prepare(wk_patch_marks *m, const lm_replica *rep, uint32_t n_mat,
                           const lm_patch *p)
{
    size_t need = rep->cap;
    lm_status st = check_added(p, n_mat, &need);
    if (st == LM_OK)
        st = marks_reserve(m, need);
    if (st != LM_OK)
        return st;
    uint32_t now = next_stamp(m);
    for (uint32_t i = 0; i < p->n_removed; i++) {
        uint32_t id = p->removed[i];
        if (!lm_replica_alive(rep, id) || m->removed[id] == now)
            return lm_fail(LM_E_INVALID, "patch removes triangle %u which is %s", id,
                           lm_replica_alive(rep, id) ? "listed twice" : "not in the mesh");
        m->removed[id] = now;
    }
    for (uint32_t i = 0; i < p->n_added; i++) {
        uint32_t id = p->added[i].id;
        int twice = m->added[id] == now;
        if (twice || (lm_replica_alive(rep, id) && m->removed[id] != now))
            return lm_fail(LM_E_INVALID, "patch adds triangle %u which is %s", id,
                           twice ? "listed twice" : "alive and not removed");
        m->added[id] = now;
    }
    return LM_OK;
}

void wk_patch_marks_free(wk_patch_marks *m)
{
    free(m->removed);
    free(m->added);
    memset(m, 0, sizeof *m);
}
