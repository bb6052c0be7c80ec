/* coordinator/simplify/candidates.h — the priced alternatives of a batch of edges: for each edge
 * every legal placement's patch (lm_patch_from_journal of the placed collapse, rolled back at
 * once), the triangles those patches remove as they are now (the edge's shard), the vertices of
 * those triangles, and the per-view footprint of all of it (the edge queue keeps the last two).
 * Building a batch leaves the mesh exactly as it was. */
#ifndef LM_COORDINATOR_SIMPLIFY_CANDIDATES_H
#define LM_COORDINATOR_SIMPLIFY_CANDIDATES_H

#include "common/mesh_topology.h"
#include "common/patch.h"
#include "common/view.h"
#include "coordinator/simplify/edge_queue.h"
#include "coordinator/simplify/fp_corners.h"
#include "coordinator/simplify/placement.h"

typedef struct co_cand_edge {
    uint32_t entry;     /* in the edge queue */
    uint32_t patch0, n; /* its patches: patches[patch0 .. patch0 + n) */
    uint8_t kind[CO_PLACE_KINDS];
    uint32_t shard0, n_shard; /* its removed triangles: shard[shard0 .. + n_shard) */
} co_cand_edge;

typedef struct co_cands {
    co_cand_edge *edges;
    uint32_t n_edges, cap_edges;
    lm_patch *patches;
    uint32_t n_patches, cap_patches;
    int64_t *delta; /* [cap_patches]: filled by the pricer */
    lm_tri_data *shard;
    uint32_t n_shard, cap_shard;
    uint32_t *tri_stamp, *vert_stamp, stamp; /* per id: dedupe within one edge */
    uint32_t cap_tri_stamp, cap_vert_stamp;
    uint32_t *verts;
    uint32_t cap_verts;
    lm_journal *j;
    co_fp_corners corners; /* one edge's triangles, for its footprint */
} co_cands;

lm_status co_cands_init(co_cands *c);
void co_cands_free(co_cands *c);

/* The candidates of entries[0..n) of q on m (their footprints and vertices go into q). */
lm_status co_cands_build(co_cands *c, lm_mesh *m, co_eq *q, const lm_view_set *vs,
                         int derived_normals, const uint32_t *entries, uint32_t n);

#endif
