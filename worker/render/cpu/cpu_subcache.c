/* worker/render/cpu/cpu_subcache.c — per-view table of the current triangles' subs (see
 * cpu_subcache.h). */
#include "worker/render/cpu/cpu_subcache.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

void wk_cpu_subcache_init(wk_cpu_subcache *c, uint32_t n_views)
{
    memset(c, 0, sizeof *c);
    c->n_views = n_views;
    c->enabled = 1;
}

void wk_cpu_subcache_free(wk_cpu_subcache *c)
{
    for (uint32_t h = 0; h < LM_MAX_VIEWS; h++) {
        free(c->sub[h]);
        free(c->state[h]);
    }
    uint32_t n = c->n_views;
    wk_cpu_subcache_init(c, n);
}

lm_status wk_cpu_subcache_reserve(wk_cpu_subcache *c, size_t need)
{
    if (!c->enabled || need <= c->cap)
        return LM_OK;
    size_t cap = lm_grow_cap(c->cap, need, 1024, SIZE_MAX);
    if (cap * c->n_views * sizeof(wk_cpu_sub) > WK_CPU_SUBCACHE_BYTES) {
        wk_cpu_subcache_free(c);
        c->enabled = 0; /* too large a mesh for the table: set up each time */
        return LM_OK;
    }
    for (uint32_t h = 0; h < c->n_views; h++) {
        if (!c->state[h])
            continue; /* made on first use, at the new capacity */
        wk_cpu_sub *s = realloc(c->sub[h], cap * sizeof *s);
        if (s)
            c->sub[h] = s;
        uint8_t *st = realloc(c->state[h], cap);
        if (!s || !st)
            return lm_fail(LM_E_NOMEM, "out of memory for %zu triangle setups", cap);
        memset(st + c->cap, 0, cap - c->cap);
        c->state[h] = st;
    }
    c->cap = cap;
    return LM_OK;
}

void wk_cpu_subcache_forget(wk_cpu_subcache *c, uint32_t id)
{
    for (uint32_t h = 0; c->enabled && id < c->cap && h < c->n_views; h++)
        if (c->state[h])
            c->state[h][id] = 0;
}

void wk_cpu_subcache_clear(wk_cpu_subcache *c)
{
    for (uint32_t h = 0; h < c->n_views; h++)
        if (c->state[h])
            memset(c->state[h], 0, c->cap);
}

const wk_cpu_sub *wk_cpu_subcache_get(wk_cpu_subcache *c, const wk_cpu_view *v, uint32_t h,
                                      const lm_tri_data *t, wk_cpu_sub *scratch, int *n)
{
    if (!c->enabled || t->id >= c->cap) {
        *n = wk_cpu_tri_setup(v, t, scratch);
        return scratch;
    }
    if (!c->state[h]) {
        c->sub[h] = malloc(c->cap * sizeof *c->sub[h]);
        c->state[h] = calloc(c->cap, 1);
        if (!c->sub[h] || !c->state[h]) {
            free(c->sub[h]);
            free(c->state[h]);
            c->sub[h] = NULL;
            c->state[h] = NULL;
            *n = wk_cpu_tri_setup(v, t, scratch); /* no room: set up each time */
            return scratch;
        }
    }
    uint8_t *state = &c->state[h][t->id];
    wk_cpu_sub *slot = &c->sub[h][t->id];
    if (*state == 1 || *state == 2) {
        *n = *state == 1;
        return slot;
    }
    *n = wk_cpu_tri_setup(v, t, scratch);
    if (*state == 3 || *n > 1) {
        *state = 3; /* several subs (clipped): set up each time */
        return scratch;
    }
    *state = *n == 1 ? 1 : 2;
    if (*n == 1)
        *slot = scratch[0];
    return slot;
}

const wk_cpu_sub *wk_cpu_subcache_peek(const wk_cpu_subcache *c, uint32_t h, uint32_t id)
{
    if (!c->enabled || id >= c->cap || !c->state[h] || c->state[h][id] != 1)
        return NULL;
    return &c->sub[h][id];
}

void wk_cpu_subcache_prefetch(const wk_cpu_subcache *c, uint32_t h, uint32_t id)
{
    if (!c->enabled || id >= c->cap || !c->state[h])
        return;
    __builtin_prefetch(&c->state[h][id]);
    const char *s = (const char *)&c->sub[h][id];
    for (size_t b = 0; b < sizeof(wk_cpu_sub); b += 64)
        __builtin_prefetch(s + b);
}
