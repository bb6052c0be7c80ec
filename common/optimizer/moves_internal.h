/* common/optimizer/moves_internal.h — state shared by moves.c (the operation flow) and
 * move_params.c (the parameter vector of a vertex set). Not for other files. */
#ifndef LM_COMMON_OPTIMIZER_MOVES_INTERNAL_H
#define LM_COMMON_OPTIMIZER_MOVES_INTERNAL_H

#include "common/optimizer/moves.h"
#include "common/optimizer/simplex.h"
#include "common/patch.h"

#define LM_MOVES_BUF 4096u /* incident triangles / neighbours of one vertex handled at most */

struct lm_moves {
    lm_mesh *m;
    lm_views *views;
    lm_moves_config cfg;
    int derived_normals;
    uint32_t wattrs; /* parameters per wedge */
    lm_journal *j;
    lm_simplex *simplex;
    lm_idset V;   /* vertices optimised */
    lm_idset W;   /* their wedges (when attributes are optimised) */
    lm_idset ops; /* vertices of triangles the connectivity change touched */
    lm_idset R;   /* vertices whose triangles render differently (normals recomputed if derived) */
    lm_idset B;   /* triangle ids removed from the committed mesh */
    lm_idset T;   /* triangle ids present now */
    uint32_t dim;
    double *x, *step;  /* [max_dim] */
    lm_patch *patches; /* [max_dim + 1] */
    int64_t *deltas;   /* [max_dim + 1] */
    uint32_t *slot;    /* [max_dim + 1] */
    uint32_t *buf;     /* [LM_MOVES_BUF] */
    uint64_t evals;    /* evaluations this object sent */
    uint64_t *clock;   /* the optimizer's clock (&evals unless shared) */
    lm_moves_observer obs;
    lm_move_site site;
};

/* Parameter vector of mv->V: fills W, dim, x (current values) and step; cuts V to fit max_dim. */
lm_status lm_params_layout(lm_moves *mv);
/* 1 if x may be evaluated (finite, inside the bound). */
int lm_params_valid(const lm_moves *mv, const double *x);
/* Write x into the mesh (journaled) and re-derive normals of mv->R when normals are derived. */
void lm_params_apply(lm_moves *mv, const double *x);

#endif
