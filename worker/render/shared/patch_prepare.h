/* worker/render/shared/patch_prepare.h — the checks both backends make of a patch against the
 * current mesh before evaluating or committing it, and the per-id marks they leave: which ids
 * the patch removes and which it adds (stamps, so that a new patch needs no clearing). */
#ifndef LM_WORKER_RENDER_SHARED_PATCH_PREPARE_H
#define LM_WORKER_RENDER_SHARED_PATCH_PREPARE_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/patch.h"
#include "common/replica.h"

typedef struct wk_patch_marks {
    uint32_t *removed; /* [cap] per id: the stamp of the last patch that removed it */
    uint32_t *added;   /* [cap] ... that added it */
    size_t cap;        /* ids the arrays hold (a power of two times 1024) */
    uint32_t now;      /* the stamp of the patch prepared last; 1 after a (re)start, when every
                        * older stamp was cleared */
} wk_patch_marks;

/* Checks patch p against replica rep, whose records index n_mat materials: every added id below
 * LM_MESH_MAX_TRIS and its material below n_mat (LM_E_RANGE), every removed id alive and listed
 * once, every added id listed once and not alive unless removed (LM_E_INVALID). On LM_OK the
 * patch's ids carry the fresh stamp m->now, and the marks hold every id of rep and of p. */
lm_status wk_patch_prepare(wk_patch_marks *m, const lm_replica *rep, uint32_t n_mat,
                           const lm_patch *p);
void wk_patch_marks_free(wk_patch_marks *m);

/* Whether the patch prepared last removes / adds id (below m->cap). */
static inline int wk_patch_removes(const wk_patch_marks *m, uint32_t id)
{
    return m->removed[id] == m->now;
}
static inline int wk_patch_adds(const wk_patch_marks *m, uint32_t id)
{
    return m->added[id] == m->now;
}

#endif
