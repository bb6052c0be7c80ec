/* coordinator/simplify/pm.h — progressive meshes (Hoppe 1996) from the image simplifier: the
 * coarsest mesh M0 and the vertex splits that undo its edge collapses one by one, in a file that
 * rebuilds the mesh of any vertex count between M0's and the simplifier's start exactly — the
 * same mesh, written to the same bytes, as the simplifier stopped at that count.
 *
 * A vertex split here is literal: the state, before the collapse, of every element the collapse
 * changed (the removed vertex, the kept one's position, the wedges merged or re-owned or given new
 * normals, the triangles that died or changed corners), by element id. Applying it restores the
 * finer mesh bit for bit; each split brings back exactly one vertex. Ids are the simplifier's
 * (dead slots included), so the mesh of n vertices, compacted, is the simplifier's output.
 * The file format is in coordinator/simplify/SIMPLIFY.md; co_pm_read checks every count, id and
 * reference (a hostile file is a one-line LM_E_FORMAT error). */
#ifndef LM_COORDINATOR_SIMPLIFY_PM_H
#define LM_COORDINATOR_SIMPLIFY_PM_H

#include <stddef.h>
#include <stdint.h>

#include "common/mesh.h"
#include "common/mesh_topology.h"

#define CO_PM_VERSION 1

typedef struct co_pm_vert {
    uint32_t id, alive;
    float pos[3];
} co_pm_vert;

typedef struct co_pm_wedge {
    uint32_t id, alive;
    lm_wedge w;
} co_pm_wedge;

typedef struct co_pm_tri {
    uint32_t id, alive;
    lm_tri t;
} co_pm_tri;

/* One vertex split: elements as they were before the collapse it undoes (ids ascending). */
typedef struct co_pm_split {
    uint32_t n_verts, n_wedges, n_tris;
    co_pm_vert *verts;
    co_pm_wedge *wedges;
    co_pm_tri *tris;
} co_pm_split;

void co_pm_split_free(co_pm_split *s);

/* The split of the change journaled in j after `mark` (the mesh as it is now): the touched
 * elements' ids from the journal, their values read after a rollback, then the change is done
 * again with redo(ctx) — which must redo it exactly (the collapse is deterministic). */
lm_status co_pm_split_capture(lm_mesh *m, lm_journal *j, size_t mark, lm_status (*redo)(void *ctx),
                              void *ctx, co_pm_split *out);

/* Splits in the order their collapses happened. */
typedef struct co_pm_recorder co_pm_recorder;
lm_status co_pm_recorder_create(co_pm_recorder **out);
void co_pm_recorder_destroy(co_pm_recorder *r);
/* Takes the split's arrays (s is emptied). */
lm_status co_pm_recorder_take(co_pm_recorder *r, co_pm_split *s);
uint32_t co_pm_recorder_count(const co_pm_recorder *r);

/* Write the progressive mesh atomically: base is the simplifier's mesh after its last recorded
 * collapse (dead slots included), full_verts the live vertices before its first. Materials (and
 * their textures, as PNG) and parts come from base. */
lm_status co_pm_write(const char *path, const lm_mesh *base, const co_pm_recorder *r,
                      uint32_t full_verts);

typedef struct co_pm co_pm;
/* Read and check a file; textures are decoded when decode_textures (0 leaves materials without
 * them: for checks that need no pixels). */
lm_status co_pm_read(const char *path, co_pm **out);
lm_status co_pm_read_memory(const uint8_t *data, size_t size, int decode_textures, co_pm **out);
void co_pm_destroy(co_pm *pm);
/* Vertex counts of M0 and of the finest mesh. */
void co_pm_range(const co_pm *pm, uint32_t *base_verts, uint32_t *full_verts);
/* The mesh of `verts` live vertices (base..full), compact, adjacency built. */
lm_status co_pm_extract(const co_pm *pm, uint32_t verts, lm_mesh **out);

#endif
