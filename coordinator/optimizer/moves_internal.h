/* coordinator/optimizer/moves_internal.h — state shared by moves.c (the operation flow) and
 * move_params.c (the parameter vector of a vertex set). Not for other files. */
#ifndef LM_COORDINATOR_MOVES_INTERNAL_H
#define LM_COORDINATOR_MOVES_INTERNAL_H

#include "common/patch.h"
#include "coordinator/optimizer/moves.h"
#include "coordinator/optimizer/simplex.h"

#define CO_MOVES_BUF 4096u /* incident triangles / neighbours of one vertex handled at most */

struct co_moves {
    lm_mesh *m;
    lm_views *views;
    co_moves_config cfg;
    int derived_normals;
    uint32_t wattrs; /* parameters per wedge */
    lm_journal *j;
    co_simplex *simplex;
    co_idset V;   /* vertices optimised */
    co_idset W;   /* their wedges (when attributes are optimised) */
    co_idset ops; /* vertices of triangles the connectivity change touched */
    co_idset R;   /* vertices whose triangles render differently (normals recomputed if derived) */
    co_idset B;   /* triangle ids removed from the committed mesh */
    co_idset T;   /* triangle ids present now */
    uint32_t dim;
    double *x, *step;  /* [max_dim] */
    lm_patch *patches; /* [max_dim + 1] */
    int64_t *deltas;   /* [max_dim + 1] */
    uint32_t *slot;    /* [max_dim + 1] */
    uint32_t *buf;     /* [CO_MOVES_BUF] */
    uint64_t evals;    /* evaluations this object sent */
    uint64_t *clock;   /* the optimizer's clock (&evals unless shared) */
    co_moves_observer obs;
    co_move_site site;
};

/* Parameter vector of mv->V: fills W, dim, x (current values) and step; cuts V to fit max_dim. */
lm_status co_params_layout(co_moves *mv);
/* 1 if x may be evaluated (finite, inside the bound). */
int co_params_valid(const co_moves *mv, const double *x);
/* Write x into the mesh (journaled) and re-derive normals of mv->R when normals are derived. */
void co_params_apply(co_moves *mv, const double *x);

#endif
