/* coordinator/geometric/edge_set.c — the outer loop's edge sets: an open-addressing map (linear
 * probing, deletion by backward shift, so no tombstones) and the candidate set built on it. */
#include "coordinator/geometric/edge_set.h"

#include <stdlib.h>
#include <string.h>

static uint32_t slot(uint64_t key, uint32_t cap)
{
    key ^= key >> 33;
    key *= 0xff51afd7ed558ccdULL;
    key ^= key >> 33;
    return (uint32_t)key & (cap - 1);
}

void co_geo_map_free(co_geo_map *m)
{
    free(m->key);
    free(m->val);
    memset(m, 0, sizeof *m);
}

uint32_t co_geo_map_get(const co_geo_map *m, uint64_t key)
{
    if (!m->cap)
        return UINT32_MAX;
    for (uint32_t i = slot(key, m->cap);; i = (i + 1) & (m->cap - 1)) {
        if (m->key[i] == key)
            return m->val[i];
        if (!m->key[i])
            return UINT32_MAX;
    }
}

static lm_status grow(co_geo_map *m)
{
    co_geo_map b = {.cap = m->cap ? m->cap * 2 : 1024};
    b.key = calloc(b.cap, sizeof *b.key);
    b.val = malloc((size_t)b.cap * sizeof *b.val);
    if (!b.key || !b.val) {
        co_geo_map_free(&b);
        return lm_fail(LM_E_NOMEM, "out of memory for the edge sets");
    }
    for (uint32_t i = 0; i < m->cap; i++)
        if (m->key[i])
            co_geo_map_put(&b, m->key[i], m->val[i]);
    co_geo_map_free(m);
    *m = b;
    return LM_OK;
}

lm_status co_geo_map_put(co_geo_map *m, uint64_t key, uint32_t val)
{
    if ((m->n + 1) * 2 > m->cap) {
        lm_status st = grow(m);
        if (st != LM_OK)
            return st;
    }
    uint32_t i = slot(key, m->cap);
    while (m->key[i] && m->key[i] != key)
        i = (i + 1) & (m->cap - 1);
    if (!m->key[i])
        m->n++;
    m->key[i] = key;
    m->val[i] = val;
    return LM_OK;
}

void co_geo_map_del(co_geo_map *m, uint64_t key)
{
    if (!m->cap)
        return;
    uint32_t i = slot(key, m->cap), mask = m->cap - 1;
    while (m->key[i] != key) {
        if (!m->key[i])
            return;
        i = (i + 1) & mask;
    }
    m->n--;
    for (uint32_t j = (i + 1) & mask; m->key[j]; j = (j + 1) & mask) {
        uint32_t home = slot(m->key[j], m->cap);
        /* j's entry may move into the hole at i if its home is not in (i, j] (cyclically) */
        if (((j - home) & mask) >= ((j - i) & mask)) {
            m->key[i] = m->key[j];
            m->val[i] = m->val[j];
            i = j;
        }
    }
    m->key[i] = 0;
}

void co_geo_set_free(co_geo_edge_set *s)
{
    free(s->item);
    co_geo_map_free(&s->where);
    memset(s, 0, sizeof *s);
}

void co_geo_set_clear(co_geo_edge_set *s)
{
    for (uint32_t i = 0; i < s->n; i++)
        co_geo_map_del(&s->where, s->item[i]);
    s->n = 0;
}

lm_status co_geo_set_add(co_geo_edge_set *s, uint64_t key)
{
    if (co_geo_map_get(&s->where, key) != UINT32_MAX)
        return LM_OK;
    if (s->n == s->cap) {
        uint32_t cap = s->cap * 2 + 256;
        uint64_t *it = realloc(s->item, (size_t)cap * sizeof *it);
        if (!it)
            return lm_fail(LM_E_NOMEM, "out of memory for the edge sets");
        s->item = it;
        s->cap = cap;
    }
    s->item[s->n] = key;
    return co_geo_map_put(&s->where, key, s->n++);
}

uint64_t co_geo_set_take(co_geo_edge_set *s, lm_rng *r)
{
    uint32_t i = (uint32_t)lm_rng_below(r, s->n);
    uint64_t key = s->item[i];
    co_geo_map_del(&s->where, key);
    if (i != --s->n) {
        s->item[i] = s->item[s->n];
        co_geo_map_put(&s->where, s->item[i], i);
    }
    return key;
}
