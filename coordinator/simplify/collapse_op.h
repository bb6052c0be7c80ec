/* coordinator/simplify/collapse_op.h — one edge collapse with its placement, as the simplifiers
 * do it and price it: lm_mesh_collapse_edge (the legality rules of common/mesh_topology.h), the
 * wedges merged across the edge set to the placement's blend of the two sides' attributes, and,
 * where normals are derived from the geometry, the area-weighted normals of the kept vertex and
 * its ring recomputed (as lm_mesh_compute_normals computes them). Every change is journaled, so
 * the patch the views price is lm_patch_from_journal of the span, and a rollback undoes it. */
#ifndef LM_COORDINATOR_SIMPLIFY_COLLAPSE_OP_H
#define LM_COORDINATOR_SIMPLIFY_COLLAPSE_OP_H

#include "common/mesh.h"
#include "common/mesh_topology.h"
#include "coordinator/simplify/placement.h"

/* Apply pl to m. LM_E_ILLEGAL (mesh unchanged, message cleared) when the collapse is not allowed
 * or a vertex has more neighbours than the operations handle. */
lm_status co_collapse_apply(lm_mesh *m, const co_place *pl, int derived_normals, lm_journal *j);

#endif
