/* coordinator/simplify/isimp.h — image-driven simplification (Lindstrom & Turk 2000, as chapter II
 * of Pfeiffer 2001 describes it) and its shard variant (chapter III): greedy edge collapses, the
 * cheapest first, each priced by the exact change of the image energy its best placement causes
 * (co_place: endpoints, midpoint, quadric point), with lazy re-evaluation.
 *
 * The loop reads as: price every edge (in batches) → repeat { take the lowest entries of the
 * queue while they may be stale and re-price them together; when the lowest is exact, collapse
 * it, commit it, mark stale what it may have changed }. An entry is stale when a committed
 * collapse touched a vertex of the triangles its changes remove (its shard), or — image method —
 * when a committed change's footprint meets its own in some view (co_fp_meet): outside its
 * footprint a change leaves every pixel, so every ΔE there, as it was. A collapse is therefore
 * only ever made at a cost that is exact for the mesh it is made on. New edges start stale with
 * the cost of the edge they replace.
 *
 * Legal moves only (lm_mesh_collapse_edge: link condition, borders, components of 4 vertices);
 * seams and part borders are crossed when the images say so (merged wedges blend, parts keep their
 * triangles). The decisions depend only on the exact int64 prices, so the result is the same for
 * any split of the views (local, split, worker processes). */
#ifndef LM_COORDINATOR_SIMPLIFY_ISIMP_H
#define LM_COORDINATOR_SIMPLIFY_ISIMP_H

#include <stdint.h>

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"
#include "coordinator/simplify/placement.h"
#include "coordinator/simplify/pm.h"
#include "coordinator/simplify/pricer.h"

/* One collapse made, for the caller's hook. */
typedef struct co_isimp_step {
    uint32_t index;       /* 0, 1, ... */
    uint32_t keep, drop;  /* the surviving and the removed vertex */
    co_place_kind place;  /* where keep went */
    int64_t cost;         /* ΔE it was made at */
    uint32_t live_verts;  /* after it */
    uint64_t evaluations; /* patches priced so far (the first pass included) */
    co_pm_split *split;   /* the vertex split undoing it (with record_splits; the hook may
                             take its arrays), else NULL */
} co_isimp_step;

typedef struct co_isimp_stats {
    uint32_t collapses;
    uint64_t edge_prices;  /* edges priced (each: all its placements) */
    uint64_t evaluations;  /* patches priced */
    uint64_t calls;        /* evaluate calls */
    uint64_t renders;      /* shard renders */
    uint64_t stale_pops;   /* entries found stale at the top of the queue */
    uint64_t marked_stale; /* entries a commit made stale through their footprint */
    int stuck;             /* stopped above the target: no legal collapse left */
    double seconds;
} co_isimp_stats;

/* Zero means default for every field but views. */
typedef struct co_isimp_config {
    co_price_method method;
    uint32_t target_verts;    /* stop at this many live vertices */
    const lm_view_set *views; /* the views' view set (footprints, shards) */
    int derived_normals;      /* normals follow the geometry (else they are blended attributes) */
    uint32_t max_batch;       /* patches per evaluate call; 0 = 256 */
    uint32_t rebatch_edges;   /* stale entries re-priced together at most; 0 = 64 */
    int record_splits;        /* hand each step's vertex split to on_step */
    int verify;               /* tests: after each collapse re-price every entry taken as exact
                                 and fail (LM_E_INTERNAL) if one differs; very slow */
    int unsafe_no_footprints; /* tests only: skip the footprint staleness test (to show that
                                 verify catches the stale costs it prevents) */
    lm_status (*on_step)(void *ctx, const lm_mesh *m, co_isimp_step *s);
    /* After each batch of the first pricing of every edge: `done` of `total` edges priced; NULL =
       none. A status other than LM_OK (from either hook) stops the run with it. */
    lm_status (*on_priced)(void *ctx, uint32_t done, uint32_t total);
    void *ctx;
} co_isimp_config;

/* Simplify m in place (adjacency built; compact; normals as derived_normals says). Image method:
 * views hold the original's targets and m as the current mesh, and follow every collapse. Shard
 * method: views that offer retarget; their current mesh is replaced. Returns LM_OK also when it
 * got stuck above the target (stats->stuck). */
lm_status co_isimp_run(lm_mesh *m, lm_views *views, const co_isimp_config *cfg,
                       co_isimp_stats *stats);

#endif
