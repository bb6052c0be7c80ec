/* common/replica.c — triangle records of the current mesh by id (see replica.h). */
#include "common/replica.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

void lm_replica_init(lm_replica *r)
{
    memset(r, 0, sizeof *r);
}

void lm_replica_free(lm_replica *r)
{
    free(r->tris);
    free(r->alive);
    lm_replica_init(r);
}

void lm_replica_clear(lm_replica *r)
{
    if (r->cap)
        memset(r->alive, 0, r->cap);
    r->n_alive = 0;
}

static lm_status grow(lm_replica *r, uint32_t id)
{
    if (id >= LM_MESH_MAX_TRIS)
        return lm_fail(LM_E_RANGE, "triangle id %u exceeds the limit %u", id, LM_MESH_MAX_TRIS);
    size_t cap = lm_grow_cap(r->cap, (size_t)id + 1, 1024, SIZE_MAX);
    if (!LM_RESIZE(&r->tris, cap) || !LM_RESIZE(&r->alive, cap))
        return lm_fail(LM_E_NOMEM, "out of memory growing the mesh replica to %zu triangles", cap);
    memset(r->alive + r->cap, 0, cap - r->cap);
    r->cap = cap;
    return LM_OK;
}

lm_status lm_replica_put(lm_replica *r, const lm_tri_data *t)
{
    if (t->id >= r->cap) {
        lm_status st = grow(r, t->id);
        if (st != LM_OK)
            return st;
    }
    LM_ASSERT(!r->alive[t->id]);
    r->tris[t->id] = *t;
    r->alive[t->id] = 1;
    r->n_alive++;
    return LM_OK;
}

void lm_replica_kill(lm_replica *r, uint32_t id)
{
    LM_ASSERT(lm_replica_alive(r, id));
    r->alive[id] = 0;
    r->n_alive--;
}

lm_status lm_replica_set(lm_replica *r, const lm_tri_data *tris, size_t n)
{
    lm_replica_clear(r);
    lm_status st = LM_OK;
    for (size_t i = 0; i < n && st == LM_OK; i++) {
        if (lm_replica_alive(r, tris[i].id))
            return lm_fail(LM_E_INVALID, "triangle id %u appears twice in the mesh", tris[i].id);
        st = lm_replica_put(r, &tris[i]);
    }
    return st;
}

lm_status lm_replica_apply(lm_replica *r, const lm_patch *p)
{
    for (uint32_t i = 0; i < p->n_removed; i++)
        if (!lm_replica_alive(r, p->removed[i]))
            return lm_fail(LM_E_INVALID, "patch removes triangle %u which is not in the mesh",
                           p->removed[i]);
    for (uint32_t i = 0; i < p->n_removed; i++)
        lm_replica_kill(r, p->removed[i]);
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < p->n_added && st == LM_OK; i++) {
        if (lm_replica_alive(r, p->added[i].id))
            return lm_fail(LM_E_INVALID, "patch adds triangle %u which is alive and not removed",
                           p->added[i].id);
        st = lm_replica_put(r, &p->added[i]);
    }
    return st;
}

const lm_tri_data *lm_replica_current(const void *ctx, uint32_t id)
{
    const lm_replica *r = ctx;
    return lm_replica_alive(r, id) ? &r->tris[id] : NULL;
}
