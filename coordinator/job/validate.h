/* coordinator/job/validate.h — a job's validation (`optimize --validate-every K`): views the
 * optimizer never fits (view_turn.h), the current mesh judged on them every K evaluations, a copy
 * of the best mesh so far (the job's output), and the count of checks since the last new best
 * (a plateau: the job then fits new training views). Every number here is a function of the
 * evaluation counts at which the checks fall and of exact integer energies: the same for any
 * number of workers, and saved in the job's checkpoint so a resumed run goes on the same way. */
#ifndef LM_COORDINATOR_JOB_VALIDATE_H
#define LM_COORDINATOR_JOB_VALIDATE_H

#include <stdint.h>
#include <stdio.h>

#include "common/error.h"
#include "common/mesh.h"
#include "common/views_api.h"

typedef struct co_validation {
    lm_views *views;      /* the validation views (owned) */
    lm_mesh *best;        /* copy of the best mesh so far; NULL before the first check */
    int64_t best_energy;  /* its energy on the validation views */
    int64_t first_energy; /* the first check's (the start's): what progress shows fractions of */
    int64_t last_energy;  /* the last check's */
    uint64_t best_evals;  /* evaluations when the best mesh was the optimizer's */
    uint64_t next_evals;  /* evaluations at which the next check is due */
    uint32_t checks;      /* checks so far */
    uint32_t since_best;  /* checks since the last new best */
    uint32_t epoch;       /* training views in force: 0 = the job's, n = after the n-th plateau */
} co_validation;

/* Judge `m` (the optimizer's mesh after `evals` evaluations) on the validation views; a strictly
 * lower energy than the best (or the first check) makes a copy of it the best. *improved (may be
 * NULL) says whether it did. Counts the check unless `count` is 0 (the job's last look at its
 * final mesh, which no checkpoint keeps). */
lm_status co_validation_check(co_validation *v, const lm_mesh *m, uint64_t evals, int count,
                              int *improved);

/* The state (not the views) into a checkpoint payload, and back: `like` is a mesh with the
 * optimizer's materials and parts (the best mesh is loaded into a copy of it). */
lm_status co_validation_save(const co_validation *v, FILE *fp);
lm_status co_validation_load(co_validation *v, const lm_mesh *like, FILE *fp);

/* The views and the best mesh go. */
void co_validation_free(co_validation *v);

#endif
