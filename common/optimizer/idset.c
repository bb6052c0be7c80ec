/* common/optimizer/idset.c — insertion-ordered id sets with generation stamps. */
#include "common/optimizer/idset.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

void lm_idset_init(lm_idset *s)
{
    memset(s, 0, sizeof *s);
    s->gen = 1;
}

void lm_idset_free(lm_idset *s)
{
    free(s->ids);
    free(s->stamp);
    lm_idset_init(s);
}

void lm_idset_clear(lm_idset *s)
{
    s->n = 0;
    if (++s->gen == 0) { /* wrapped: forget every stamp */
        if (s->stamp)
            memset(s->stamp, 0, (size_t)s->range * sizeof *s->stamp);
        s->gen = 1;
    }
}

static lm_status grow_range(lm_idset *s, uint32_t id)
{
    size_t r = lm_grow_cap(s->range, (size_t)id + 1, 256, UINT32_MAX);
    if (!r || !LM_RESIZE(&s->stamp, r))
        return lm_fail(LM_E_NOMEM, "out of memory growing an id set to %llu ids",
                       (unsigned long long)r);
    memset(s->stamp + s->range, 0, (r - s->range) * sizeof *s->stamp);
    s->range = (uint32_t)r;
    return LM_OK;
}

lm_status lm_idset_add(lm_idset *s, uint32_t id)
{
    if (id >= s->range) {
        lm_status st = grow_range(s, id);
        if (st)
            return st;
    }
    if (s->stamp[id] == s->gen)
        return LM_OK;
    if (s->n == s->cap && !LM_GROW32(&s->ids, &s->cap, (size_t)s->n + 1, 64))
        return lm_fail(LM_E_NOMEM, "out of memory growing an id set to %u members",
                       (uint32_t)lm_grow_cap(s->cap, (size_t)s->n + 1, 64, UINT32_MAX));
    s->stamp[id] = s->gen;
    s->ids[s->n++] = id;
    return LM_OK;
}

int lm_idset_has(const lm_idset *s, uint32_t id)
{
    return id < s->range && s->stamp[id] == s->gen;
}

void lm_idset_sort(lm_idset *s)
{
    for (uint32_t i = 1; i < s->n; i++) {
        uint32_t x = s->ids[i], k = i;
        for (; k > 0 && s->ids[k - 1] > x; k--)
            s->ids[k] = s->ids[k - 1];
        s->ids[k] = x;
    }
}

void lm_idset_truncate(lm_idset *s, uint32_t n)
{
    if (n >= s->n)
        return;
    /* dropped members must leave the set too */
    for (uint32_t i = n; i < s->n; i++)
        s->stamp[s->ids[i]] = 0;
    s->n = n;
}
