/* coordinator/job/validate.c — validation checks, the best mesh and their checkpoint record
 * (validate.h). */
#include "coordinator/job/validate.h"

#include <stdlib.h>

#include "common/mesh_topology.h"
#include "common/optimizer/binio.h"
#include "common/optimizer/optimizer.h"

#define VALIDATION_MAGIC 0x314c4156u /* "VAL1" */

lm_status co_validation_check(co_validation *v, const lm_mesh *m, uint64_t evals, int count,
                              int *improved)
{
    int64_t e = 0;
    lm_status st = lm_views_set_mesh_from(v->views, m);
    if (st == LM_OK)
        st = v->views->ops->energy(v->views, &e, NULL);
    if (st != LM_OK)
        return st;
    int better = !v->best || e < v->best_energy;
    if (better) {
        lm_mesh *copy;
        st = lm_mesh_clone(m, &copy);
        if (st != LM_OK)
            return st;
        lm_mesh_destroy(v->best);
        v->best = copy;
        v->best_energy = e;
        v->best_evals = evals;
    }
    if (!v->checks && count)
        v->first_energy = e;
    v->last_energy = e;
    if (count) {
        v->checks++;
        v->since_best = better ? 0 : v->since_best + 1;
    }
    if (improved)
        *improved = better;
    return LM_OK;
}

lm_status co_validation_save(const co_validation *v, FILE *fp)
{
    lm_bin b;
    lm_bin_init(&b, fp, "validation state");
    lm_put_u32(&b, VALIDATION_MAGIC);
    lm_put_i64(&b, v->best_energy);
    lm_put_i64(&b, v->first_energy);
    lm_put_i64(&b, v->last_energy);
    lm_put_u64(&b, v->best_evals);
    lm_put_u64(&b, v->next_evals);
    lm_put_u32(&b, v->checks);
    lm_put_u32(&b, v->since_best);
    lm_put_u32(&b, v->epoch);
    lm_put_u32(&b, v->best != NULL);
    if (b.status || !v->best)
        return b.status;
    return lm_optimizer_save_mesh(v->best, fp);
}

lm_status co_validation_load(co_validation *v, const lm_mesh *like, FILE *fp)
{
    lm_bin b;
    lm_bin_init(&b, fp, "validation state");
    if (lm_get_u32(&b) != VALIDATION_MAGIC)
        return b.status ? b.status : lm_bin_bad(&b, "no validation record");
    co_validation s = *v;
    s.best_energy = lm_get_i64(&b);
    s.first_energy = lm_get_i64(&b);
    s.last_energy = lm_get_i64(&b);
    s.best_evals = lm_get_u64(&b);
    s.next_evals = lm_get_u64(&b);
    s.checks = lm_get_u32(&b);
    s.since_best = lm_get_u32(&b);
    s.epoch = lm_get_u32(&b);
    uint32_t has_best = lm_get_u32(&b);
    if (b.status)
        return b.status;
    lm_mesh *best = NULL;
    if (has_best) {
        lm_status st = lm_mesh_clone(like, &best);
        if (st == LM_OK)
            st = lm_optimizer_load_mesh(best, fp);
        if (st == LM_OK)
            st = lm_mesh_build_adjacency(best);
        if (st != LM_OK) {
            lm_mesh_destroy(best);
            return st;
        }
    }
    lm_mesh_destroy(v->best);
    s.best = best;
    *v = s;
    return LM_OK;
}

void co_validation_free(co_validation *v)
{
    lm_views_destroy(v->views);
    lm_mesh_destroy(v->best);
    v->views = NULL;
    v->best = NULL;
}
