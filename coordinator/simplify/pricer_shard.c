/* coordinator/simplify/pricer_shard.c — Pfeiffer's shards: the edges of a batch are put in groups
 * (first fit, in batch order) whose footprints meet in no view; each group's shards are rendered
 * alone (set_mesh of their union), that render becomes the target (retarget), and every placement
 * of every edge of the group is priced against it in one evaluate. Because no two shards of a
 * group can change the same pixel, each price is that of the shard rendered by itself. */
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "coordinator/simplify/pricer_internal.h"

void co_shard_free(co_pricer *p)
{
    free(p->group);
    free(p->order);
    free(p->tris);
    free(p->patches);
    free(p->delta);
}

static lm_status reserve(void **ptr, uint32_t *cap, uint32_t need, size_t elem)
{
    if (!lm_grow32(ptr, cap, need, elem, 64))
        return lm_fail(LM_E_NOMEM, "out of memory for shard groups");
    return LM_OK;
}

/* Group of every edge; returns the number of groups. order[] lists the edges group by group. */
static uint32_t make_groups(co_pricer *p, const co_cands *c, co_eq *q)
{
    uint32_t n = c->n_edges, n_groups = 0, nv = p->vs->count;
    for (uint32_t i = 0; i < n; i++) {
        const co_rect *fi = co_eq_rects(q, c->edges[i].entry);
        uint32_t g = 0;
        for (; g < n_groups; g++) {
            int meets = 0;
            for (uint32_t k = 0; k < i && !meets; k++)
                meets = p->group[k] == g && co_fp_meet(fi, co_eq_rects(q, c->edges[k].entry), nv);
            if (!meets)
                break;
        }
        p->group[i] = g;
        n_groups += g == n_groups;
    }
    uint32_t k = 0;
    for (uint32_t g = 0; g < n_groups; g++)
        for (uint32_t i = 0; i < n; i++)
            if (p->group[i] == g)
                p->order[k++] = i;
    return n_groups;
}

/* Render the shards of order[first..end) alone and price their patches. */
static lm_status price_group(co_pricer *p, co_cands *c, uint32_t first, uint32_t end)
{
    uint32_t nt = 0, np = 0;
    for (uint32_t i = first; i < end; i++) {
        const co_cand_edge *e = &c->edges[p->order[i]];
        nt += e->n_shard;
        np += e->n;
    }
    lm_status st = reserve((void **)&p->tris, &p->cap_tris, nt + 1, sizeof *p->tris);
    uint32_t cap = p->cap_patches;
    if (!st)
        st = reserve((void **)&p->patches, &p->cap_patches, np + 1, sizeof *p->patches);
    if (!st)
        st = reserve((void **)&p->delta, &cap, p->cap_patches, sizeof *p->delta);
    if (st)
        return st;
    nt = np = 0;
    for (uint32_t i = first; i < end; i++) {
        const co_cand_edge *e = &c->edges[p->order[i]];
        memcpy(p->tris + nt, c->shard + e->shard0, (size_t)e->n_shard * sizeof *p->tris);
        memcpy(p->patches + np, c->patches + e->patch0, (size_t)e->n * sizeof *p->patches);
        nt += e->n_shard;
        np += e->n;
    }
    if (np == 0)
        return LM_OK;
    st = p->views->ops->set_mesh(p->views, p->tris, nt);
    if (!st)
        st = lm_views_retarget(p->views);
    p->stats.renders++;
    if (!st)
        st = co_pricer_evaluate(p, p->patches, np, p->delta);
    for (uint32_t i = first, k = 0; !st && i < end; i++) {
        const co_cand_edge *e = &c->edges[p->order[i]];
        memcpy(c->delta + e->patch0, p->delta + k, (size_t)e->n * sizeof *c->delta);
        k += e->n;
    }
    return st;
}

lm_status co_shard_price(co_pricer *p, co_cands *c, co_eq *q)
{
    uint32_t cap = p->cap_group;
    lm_status st = reserve((void **)&p->group, &p->cap_group, c->n_edges + 1, sizeof *p->group);
    if (!st)
        st = reserve((void **)&p->order, &cap, p->cap_group, sizeof *p->order);
    if (st)
        return st;
    uint32_t n_groups = make_groups(p, c, q);
    for (uint32_t i = 0, g = 0; st == LM_OK && g < n_groups; g++) {
        uint32_t end = i;
        while (end < c->n_edges && p->group[p->order[end]] == g)
            end++;
        st = price_group(p, c, i, end);
        i = end;
    }
    return st;
}
