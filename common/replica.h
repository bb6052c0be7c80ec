/* common/replica.h — the worker's copy of the current mesh as the views see it: triangle records
 * (id, material, per-corner data) indexed by their stable ids, changed only by set_mesh and by
 * committed patches. No GL. */
#ifndef LM_WORKER_REPLICA_H
#define LM_WORKER_REPLICA_H

#include <stddef.h>
#include <stdint.h>

#include "common/patch.h"

typedef struct lm_replica {
    lm_tri_data *tris; /* [cap] valid where alive[id] */
    uint8_t *alive;    /* [cap] */
    size_t cap;
    size_t n_alive;
} lm_replica;

void lm_replica_init(lm_replica *r);
void lm_replica_free(lm_replica *r);
void lm_replica_clear(lm_replica *r);
/* Make t->id alive with this data (it must not be alive). */
lm_status lm_replica_put(lm_replica *r, const lm_tri_data *t);
/* Kill an alive id. */
void lm_replica_kill(lm_replica *r, uint32_t id);

static inline int lm_replica_alive(const lm_replica *r, uint32_t id)
{
    return id < r->cap && r->alive[id];
}

/* Exactly these triangles (ids distinct: a repeated one is refused). On failure the replica is
 * left partial (the caller sets it again). */
lm_status lm_replica_set(lm_replica *r, const lm_tri_data *tris, size_t n);

/* The patch applied, checked as the views check it: removed ids alive, added ids free after the
 * removals. On failure the replica may be half-applied (the caller sets it again). */
lm_status lm_replica_apply(lm_replica *r, const lm_patch *p);

/* The current record of id (NULL when it is not alive), as lm_wire_current_fn wants it (ctx: the
 * replica). */
const lm_tri_data *lm_replica_current(const void *ctx, uint32_t id);

#endif
