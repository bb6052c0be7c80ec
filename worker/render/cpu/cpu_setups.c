/* worker/render/cpu/cpu_setups.c — the subs of one evaluation pass and their pool (see
 * cpu_setups.h). */
#include "worker/render/cpu/cpu_setups.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

void wk_cpu_setups_reset(wk_cpu_setups *s)
{
    s->n = 0;
    s->used = 0;
}

void wk_cpu_setups_free(wk_cpu_setups *s)
{
    for (size_t i = 0; i < s->n_chunks; i++)
        free(s->chunks[i]);
    free(s->chunks);
    free(s->sub);
    free(s->tri);
    free(s->shade);
    free(s->shade_ready);
    memset(s, 0, sizeof *s);
}

lm_status wk_cpu_setups_pool(wk_cpu_setups *s, int k, wk_cpu_sub **out)
{
    LM_ASSERT(k >= 0 && k <= WK_CPU_MAX_SUBS);
    size_t at = s->used % WK_CPU_POOL_CHUNK;
    if (at + (size_t)k > WK_CPU_POOL_CHUNK)
        s->used += WK_CPU_POOL_CHUNK - at; /* k consecutive subs: start a new chunk */
    size_t c = s->used / WK_CPU_POOL_CHUNK;
    if (c >= s->n_chunks) {
        wk_cpu_sub **a = realloc(s->chunks, (c + 1) * sizeof *a);
        if (!a)
            return lm_fail(LM_E_NOMEM, "out of memory for a pool of triangle setups");
        s->chunks = a;
        a[c] = malloc(WK_CPU_POOL_CHUNK * sizeof **a);
        if (!a[c])
            return lm_fail(LM_E_NOMEM, "out of memory for a pool of triangle setups");
        s->n_chunks = c + 1;
    }
    *out = s->chunks[c] + s->used % WK_CPU_POOL_CHUNK;
    s->used += (size_t)k;
    return LM_OK;
}

static lm_status reserve(wk_cpu_setups *s, size_t need)
{
    if (need <= s->cap)
        return LM_OK;
    size_t cap = lm_grow_cap(s->cap, need, 256, SIZE_MAX);
    if (!LM_RESIZE(&s->sub, cap) || !LM_RESIZE(&s->tri, cap) || !LM_RESIZE(&s->shade, cap) ||
        !LM_RESIZE(&s->shade_ready, cap))
        return lm_fail(LM_E_NOMEM, "out of memory for %zu triangle setups", cap);
    s->cap = cap;
    return LM_OK;
}

lm_status wk_cpu_setups_push(wk_cpu_setups *s, const wk_cpu_sub *subs, int k, const lm_tri_data *t)
{
    lm_status st = reserve(s, s->n + (size_t)k);
    for (int i = 0; st == LM_OK && i < k; i++) {
        s->sub[s->n] = &subs[i];
        s->tri[s->n] = t;
        s->shade_ready[s->n++] = 0;
    }
    return st;
}
