/* coordinator/simplify/pricer.c — the pricer object and the image method: evaluate in chunks
 * against the current mesh, commit the collapses made. The shard method is pricer_shard.c. */
#include <stdlib.h>

#include "coordinator/simplify/pricer_internal.h"

#define CO_PRICER_DEFAULT_BATCH 256

lm_status co_pricer_create(co_price_method method, lm_views *views, const lm_view_set *vs,
                           uint32_t max_batch, co_pricer **out)
{
    *out = NULL;
    if (method == CO_PRICE_SHARD && !views->ops->retarget)
        return lm_fail(LM_E_UNSUPPORTED, "the shard method renders in process: these views "
                                         "cannot take their own images as targets");
    co_pricer *p = calloc(1, sizeof *p);
    if (!p)
        return lm_fail(LM_E_NOMEM, "out of memory for the pricer");
    p->method = method;
    p->views = views;
    p->vs = vs;
    p->max_batch = max_batch ? max_batch : CO_PRICER_DEFAULT_BATCH;
    *out = p;
    return LM_OK;
}

void co_pricer_destroy(co_pricer *p)
{
    if (!p)
        return;
    co_shard_free(p);
    free(p);
}

/* evaluate patches[first .. first + n) in chunks of at most max_batch. */
lm_status co_pricer_evaluate(co_pricer *p, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n && st == LM_OK; i += p->max_batch) {
        uint32_t k = n - i < p->max_batch ? n - i : p->max_batch;
        st = p->views->ops->evaluate(p->views, patches + i, k, delta + i);
        p->stats.calls++;
        p->stats.evaluations += k;
    }
    return st;
}

lm_status co_pricer_price(co_pricer *p, co_cands *c, co_eq *q)
{
    if (p->method == CO_PRICE_SHARD)
        return co_shard_price(p, c, q);
    return co_pricer_evaluate(p, c->patches, c->n_patches, c->delta);
}

lm_status co_pricer_commit(co_pricer *p, const lm_patch *patch)
{
    if (p->method == CO_PRICE_SHARD)
        return LM_OK;
    return p->views->ops->commit(p->views, patch);
}

int co_pricer_is_local(const co_pricer *p)
{
    return p->method == CO_PRICE_SHARD;
}

void co_pricer_stats_get(const co_pricer *p, co_pricer_stats *out)
{
    *out = p->stats;
}
