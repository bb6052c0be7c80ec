/* common/optimizer/moves.h — one operation (connectivity move × optimisation level, paper §5.2
 * and Table 1) on one edge: perform the connectivity change on the mesh (journaled), optimise the
 * level's vertex set by downhill simplex over positions and the --attrs wedge attributes, and
 * accept (apply and commit to the views) or reject (roll back).
 *
 * Every candidate is turned into a patch of the affected triangles (ids before vs ids now) and
 * priced by views->ops->evaluate, one batch per simplex batch. Normals that are not optimised are
 * derived: area-weighted vertex normals recomputed for every vertex whose neighbourhood changed,
 * exactly as lm_mesh_compute_normals computes them. Points that leave the bounding region or are
 * not finite are refused without being evaluated.
 * Ownership: borrows the mesh and the views; owns its journal, simplex and scratch memory (no
 * allocation per evaluation once warm). */
#ifndef LM_COMMON_OPTIMIZER_MOVES_H
#define LM_COMMON_OPTIMIZER_MOVES_H

#include <stddef.h>
#include <stdint.h>

#include "common/mesh.h"
#include "common/mesh_topology.h"
#include "common/optimizer/idset.h"
#include "common/optimizer/optimizer.h"
#include "common/views_api.h"

/* Zero means default for every field. */
typedef struct lm_moves_config {
    uint32_t attrs;         /* LM_ATTR_* optimised besides positions; normals otherwise derived */
    uint32_t evals_per_dim; /* simplex limit: evals_per_dim * n; 0 = 32 */
    uint32_t max_set_verts; /* vertex sets are cut to this many (core vertices kept); 0 = 8 */
    uint32_t max_dim;       /* and to this many parameters; 0 = 160 */
    double pos_step;        /* initial displacement: fraction of mean incident edge length; 0=0.2 */
    double normal_step;     /* absolute; 0 = 0.15 */
    double uv_step;         /* fraction of the mean uv edge length at the wedge; 0 = 0.2 */
    double color_step;      /* absolute; 0 = 0.05 */
    double size_tol;        /* simplex size tolerance (relative to the steps); 0 = 0.25 */
    double f_rtol;          /* simplex relative value tolerance; 0 = none */
    float centre[3];        /* positions farther than bound_radius from centre are refused */
    float bound_radius;     /* 0 = no bound */
} lm_moves_config;

/* Where an operation acts: the edge, its opposite vertices, and the vertex the move creates
 * (split) or keeps (collapse: a survives). */
typedef struct lm_move_site {
    lm_move_kind kind;
    uint32_t a, b;
    uint32_t c, d; /* third vertices of the edge's triangles; LM_NONE where absent */
    uint32_t v;    /* split: new vertex; collapse: a; otherwise LM_NONE */
} lm_move_site;

typedef struct lm_move_result {
    int legal;         /* the connectivity change was allowed (else nothing was evaluated) */
    int accepted;      /* applied to the mesh and committed to the views */
    int64_t delta;     /* best ΔE found against the committed mesh (INT64_MAX if none) */
    uint32_t evals;    /* evaluations spent */
    uint32_t set_size; /* vertices optimised */
    lm_move_site site;
} lm_move_result;

typedef struct lm_moves lm_moves;

/* An accepted operation, as lm_moves_replay can do it again on another copy of the mesh. */
typedef struct lm_move_record {
    lm_move_kind kind;
    int level;
    uint32_t a, b;
    uint32_t v;      /* the vertex the move created (split) or kept (collapse); else LM_NONE */
    size_t mark;     /* journal position before the operation */
    uint32_t dim;    /* parameters */
    const double *x; /* their values (valid during the call only) */
    int64_t delta;   /* ΔE it was accepted with */
} lm_move_record;

/* Who wants to know about accepted operations (before their patch reaches the views) and about
 * reverts (before the views get the whole mesh again). */
typedef struct lm_moves_observer {
    void (*accepted)(void *ctx, const lm_move_record *r);
    void (*reverted)(void *ctx, size_t mark);
    void *ctx;
} lm_moves_observer;

/* Every zero field of c takes its default (the values listed above): the one place they live. */
void lm_moves_config_defaults(lm_moves_config *c);

lm_status lm_moves_create(lm_mesh *mesh, lm_views *views, const lm_moves_config *cfg,
                          lm_moves **out);
void lm_moves_destroy(lm_moves *mv);

/* Try `kind` at `level` on edge (a, b); accept when the best ΔE < accept_below. Illegal moves
 * return LM_OK with res->legal = 0. Errors from the views are returned. */
lm_status lm_moves_try(lm_moves *mv, lm_move_kind kind, int level, uint32_t a, uint32_t b,
                       int64_t accept_below, lm_move_result *res);

/* Triangles removed (committed ids) and present now around the last accepted move (sorted).
 * Valid until the next lm_moves_try. */
void lm_moves_last_change(const lm_moves *mv, const uint32_t **before, uint32_t *n_before,
                          const uint32_t **now, uint32_t *n_now);

/* Price against `views` (borrowed) from now on; the caller sends them the mesh. */
void lm_moves_set_views(lm_moves *mv, lm_views *views);

/* The mesh the moves act on. */
const lm_mesh *lm_moves_mesh(const lm_moves *mv);

/* Evaluations this object sent to the views since creation (or lm_moves_set_evals). */
uint64_t lm_moves_evals(const lm_moves *mv);
void lm_moves_set_evals(lm_moves *mv, uint64_t evals);
/* The optimizer's clock (what statistics attenuate by): this object's evaluations, or a counter
 * shared with others (lm_moves_share_clock: every evaluation of either advances it). */
uint64_t lm_moves_clock(const lm_moves *mv);
void lm_moves_share_clock(lm_moves *mv, uint64_t *clock);
uint64_t *lm_moves_clock_ptr(lm_moves *mv);
void lm_moves_observe(lm_moves *mv, const lm_moves_observer *obs);

/* Do an accepted operation again (on a copy of the mesh that matches the one it was found on, up
 * to vertex ids `r` names in this mesh): the connectivity change, the vertex set, the parameters.
 * It stays in the mesh, journaled (lm_moves_mark/revert/forget), and is NOT sent to the views;
 * *v the vertex it created or kept. LM_E_ILLEGAL (mesh unchanged) when it no longer fits. */
lm_status lm_moves_replay(lm_moves *mv, const lm_move_record *r, uint32_t *v);
/* The journal of this object's mesh changes (for lm_patch_from_journal). */
const lm_journal *lm_moves_journal(const lm_moves *mv);

/* Undo support across accepted moves: a journal position, rolling the mesh back to it and
 * re-sending the whole mesh to the views, and forgetting the journal (changes kept). */
size_t lm_moves_mark(const lm_moves *mv);
lm_status lm_moves_revert(lm_moves *mv, size_t mark);
/* The mesh back to `mark` without telling the views (changes that never reached them). */
void lm_moves_rollback(lm_moves *mv, size_t mark);
void lm_moves_forget(lm_moves *mv);

/* The vertex set of Table 1 for `level` of site->kind, on the mesh after the connectivity change:
 *   no-op    1: ⌊e⌋ = {a,b}   2: ⌊⌊⌈e⌉⌋⌋ = {a,b,c,d}   3: ⌊⌈⌊e⌋⌉⌋ (a, b and their rings)
 *   swap     0: ∅   1: ⌊e'⌋ = {c,d}   2: ⌊⌊⌈e'⌉⌋⌋ = {c,d,a,b}   3: ⌊⌈⌊e'⌋⌉⌋
 *   split    0,1: {v}   2: v ∪ ⌊⌊⌈e⌉⌋⌋ \ ⌊e⌋ = {v,c,d}   3: v ∪ ⌊⌈⌊e⌋⌉⌋
 *   collapse 0,1: {v}   2: {v,c,d}   3: ⌊⌈v⌉⌋
 * Core vertices come first, ring vertices after in ascending order. Level 0 is not optimised. */
lm_status lm_moves_vertex_set(const lm_mesh *m, const lm_move_site *site, int level, lm_idset *out);

/* Area-weighted normal of vertex v written into all its wedges (journaled), computed like
 * lm_mesh_compute_normals. */
void lm_moves_derive_normal(lm_mesh *m, uint32_t v, lm_journal *j);

#endif
