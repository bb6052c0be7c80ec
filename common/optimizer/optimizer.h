/* common/optimizer/optimizer.h — the Lindstrom–Turk optimizer (paper §5) as one object.
 * It owns the coarse mesh being optimized and talks to the views only through common/views_api.h.
 * Time is counted in ΔE evaluations; with the same inputs and seed the sequence of decisions, and
 * so the output, is identical. All state needed to continue is serialisable (checkpoints), so a run
 * resumed from a checkpoint ends with the same result as an uninterrupted one. */
#ifndef LM_COMMON_OPTIMIZER_OPTIMIZER_H
#define LM_COMMON_OPTIMIZER_OPTIMIZER_H

#include <stdint.h>
#include <stdio.h>

#include "common/mesh.h"
#include "common/views_api.h"

/* Move kinds (paper Table 1), each with optimisation levels 0..3. */
typedef enum lm_move_kind {
    LM_MOVE_NOOP,
    LM_MOVE_SWAP,
    LM_MOVE_SPLIT,
    LM_MOVE_COLLAPSE,
    LM_MOVE_KINDS
} lm_move_kind;

typedef struct lm_params {
    uint64_t seed;  /* 0 = default 1 */
    uint32_t attrs; /* LM_ATTR_* optimised besides positions; normals not in the set are derived */
    uint32_t edges_per_iteration;   /* the plan's size: edges planned per iteration (groups of
                                       edges in flight are taken from it); 0 =
                                       LM_DEFAULT_EDGES_PER_ITERATION; at most
                                       LM_MAX_EDGES_PER_ITERATION. A job parameter (kept in
                                       checkpoints): the output depends on it */
    uint32_t simplex_evals_per_dim; /* 0 = 32 (at most 32n evaluations per simplex run) */
    uint32_t edges_in_flight; /* edges optimised at once, their evaluations in one batch (lanes.h);
                                 0 = 1, the paper's order; at most LM_MAX_EDGES_IN_FLIGHT. A job
                                 parameter (kept in checkpoints), never the number of workers: the
                                 output depends on it and on nothing else of the machinery */
    uint32_t
        lane_isolation;     /* 1: with edges in flight, each lane sees only its group's start and
                               its own actions, merged in lane order afterwards (lanes.h), so a
                               lane could run in another process; 0 = shared, today's (the
                               default). Ignored (0) with one edge in flight; kept in checkpoints */
    const lm_mesh *surface; /* the original (borrowed, must outlive the optimizer): the surface of
                               the geometric term (surface_term.h, weight lm_tuning.surface_weight);
                               NULL = no geometric term */
} lm_params;

/* Lanes per group at most (--edges-in-flight 1..1024): what the lanes' per-group arrays are
 * allocated for (per optimizer, at its K) and what wire decoders refuse above. */
#define LM_MAX_EDGES_IN_FLIGHT 1024u
#define LM_DEFAULT_EDGES_PER_ITERATION 64u
#define LM_MAX_EDGES_PER_ITERATION (1u << 20)

typedef struct lm_progress {
    uint64_t evals;                     /* ΔE evaluations so far */
    uint64_t iterations;                /* edge iterations (64 edges each) */
    int64_t energy_start, energy;       /* image energy E at start and now */
    int64_t geometric_start, geometric; /* the geometric term at start and now (0 without one); the
                                           optimizer minimises energy + geometric */
    double geometric_by_workers;        /* share of the evaluations whose geometric term the workers
                                           priced (surface_term.h) */
    uint64_t accepted[LM_MOVE_KINDS];   /* accepted moves by kind (teleports count as SPLIT) */
    uint64_t attempted[LM_MOVE_KINDS];
    uint32_t live_verts, live_tris;
} lm_progress;

typedef struct lm_optimizer lm_optimizer;

/* Takes ownership of `mesh` (the coarse mesh; adjacency built) and borrows `views` (whose target
 * images are already rendered); sends the mesh to the views (set_mesh). The mesh is owned by the
 * optimizer even when creation fails (it is destroyed then). */
lm_status lm_optimizer_create(lm_mesh *mesh, lm_views *views, const lm_params *params,
                              lm_optimizer **out);
void lm_optimizer_destroy(lm_optimizer *opt);

/* Optimise one edge iteration (about 64 edges) unless the evaluation budget `max_evals` (absolute
 * count since the start of the job) is reached first; stops between moves. */
lm_status lm_optimizer_step(lm_optimizer *opt, uint64_t max_evals);

/* Price everything from now on against `views` (borrowed, as at creation) instead of the ones the
 * optimizer has: views of the same original, with other cameras or pixel grids (a job's regrid:
 * the same count and size) or more views and pixels (a view schedule's stage). The caller destroys
 * the old ones after this returns. Sends the current mesh to the new views. With rescale_start the
 * start's image energy becomes start × new / old (the current mesh's image energy on the new and
 * the old views, rounded), so that progress stays a fraction of the start across a chain of view
 * sets (and where the views' count or size changed, the geometric term's scale with them,
 * surface_term.h, the start's geometric energy by the same ratio of scales); without it, the
 * energies of the progress are left as they are (a resume is about to load them). Between steps
 * only. On failure the optimizer must be given views again before its next step. */
lm_status lm_optimizer_replace_views(lm_optimizer *opt, lm_views *views, int rescale_start);

void lm_optimizer_progress(const lm_optimizer *opt, lm_progress *out);

/* For tests: the order in which the lanes of each group of edges in flight run (0 lane order, 1
 * reversed, else a shuffle seeded by it; the merge stays in lane order). With lane_isolation the
 * output does not depend on it. No effect with one edge in flight. */
void lm_optimizer_set_lane_order(lm_optimizer *opt, uint64_t order);

/* What isolated lanes sent and got back as wire messages when run detached. */
typedef struct lm_lane_traffic {
    uint64_t lanes;                       /* lanes run */
    uint64_t request_bytes, result_bytes; /* their messages, in all */
    uint64_t request_max, result_max;     /* the largest of each */
    uint64_t evals;                       /* evaluations the lanes spent */
} lm_lane_traffic;
/* For tests and measurements: with isolated lanes (lane_isolation, edges in flight > 1), on != 0
 * runs every lane of a group, one after the other, as another process would (lane_host.h): its
 * request encoded and decoded, the lane run on a host of its own (its own mesh copy, the same
 * views), its result encoded and decoded, then merged as usual; the output is the same. Without
 * isolated lanes it does nothing. traffic (may be NULL) gets the messages' sizes so far. */
lm_status lm_optimizer_set_lanes_detached(lm_optimizer *opt, int on);
void lm_optimizer_lane_traffic(const lm_optimizer *opt, lm_lane_traffic *traffic);
/* With isolated lanes (lane_isolation, edges in flight > 1): run every group's lanes with runner
 * (common/optimizer/lane_runner.h; copied; NULL: in process again, the default) and merge their
 * results in lane order; the output bytes are those of lanes run in process. The runner's ctx
 * must outlive its use. Without isolated lanes it does nothing. */
typedef struct lm_lane_runner lm_lane_runner;
void lm_optimizer_set_lane_runner(lm_optimizer *opt, const lm_lane_runner *runner);
/* The current mesh (owned by the optimizer; valid until the next step/destroy). */
const lm_mesh *lm_optimizer_mesh(const lm_optimizer *opt);

/* Serialise the complete state (mesh, statistics, scheduler, PRNG, counters) / restore it into an
 * optimizer created on the same original, views and params. Versioned binary, checked on read. */
lm_status lm_optimizer_save(const lm_optimizer *opt, FILE *fp);
lm_status lm_optimizer_load(lm_optimizer *opt, FILE *fp);
/* A mesh in the optimizer state's record (dead slots included), for a job's copies of meshes
 * (the best validation mesh): save m, or load into m one saved from a mesh with m's materials and
 * parts (m's arrays replaced; adjacency not built). */
lm_status lm_optimizer_save_mesh(const lm_mesh *m, FILE *fp);
lm_status lm_optimizer_load_mesh(lm_mesh *m, FILE *fp);
/* The same on a binio stream (binio.h; e.g. in memory): the status is also b's. */
struct lm_bin;
lm_status lm_optimizer_save_mesh_bin(const lm_mesh *m, struct lm_bin *b);
lm_status lm_optimizer_load_mesh_bin(lm_mesh *m, struct lm_bin *b);

#endif
