/* coordinator/optimizer/collapse_queue.c — an indexed binary min-heap over an open-addressing hash
 * map (linear probing with backward-shift deletion) of edge entries. */
#include "coordinator/optimizer/collapse_queue.h"

#include <stdlib.h>
#include <string.h>

typedef struct slot {
    co_cq_entry e;
    uint32_t heap_pos; /* index in heap, or UINT32_MAX */
} slot;

struct co_cq {
    uint64_t *keys; /* 0 = empty; else key of the edge */
    uint32_t *vals; /* index into slots */
    uint32_t cap;   /* power of two */
    uint32_t count;
    slot *slots;
    uint32_t n_slots, cap_slots;
    uint32_t *free_slots;
    uint32_t n_free;
    uint32_t *heap;
    uint32_t n_heap;
};

static uint64_t key_of(uint32_t a, uint32_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

static uint32_t hash(uint64_t k, uint32_t cap)
{
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    return (uint32_t)k & (cap - 1);
}

lm_status co_cq_create(co_cq **out)
{
    co_cq *q = calloc(1, sizeof *q);
    if (!q)
        return lm_fail(LM_E_NOMEM, "out of memory creating the collapse queue");
    *out = q;
    return LM_OK;
}

void co_cq_destroy(co_cq *q)
{
    if (!q)
        return;
    free(q->keys);
    free(q->vals);
    free(q->slots);
    free(q->free_slots);
    free(q->heap);
    free(q);
}

void co_cq_clear(co_cq *q)
{
    if (q->keys)
        memset(q->keys, 0, (size_t)q->cap * sizeof *q->keys);
    q->count = q->n_slots = q->n_free = q->n_heap = 0;
}

static int find(const co_cq *q, uint64_t k, uint32_t *pos)
{
    if (!q->cap)
        return 0;
    for (uint32_t i = hash(k, q->cap);; i = (i + 1) & (q->cap - 1)) {
        if (q->keys[i] == 0)
            return 0;
        if (q->keys[i] == k) {
            *pos = i;
            return 1;
        }
    }
}

static lm_status rehash(co_cq *q, uint32_t cap)
{
    uint64_t *keys = calloc(cap, sizeof *keys);
    uint32_t *vals = malloc((size_t)cap * sizeof *vals);
    if (!keys || !vals) {
        free(keys);
        free(vals);
        return lm_fail(LM_E_NOMEM, "out of memory growing the collapse queue to %u", cap);
    }
    for (uint32_t i = 0; i < q->cap; i++) {
        if (!q->keys[i])
            continue;
        uint32_t j = hash(q->keys[i], cap);
        while (keys[j])
            j = (j + 1) & (cap - 1);
        keys[j] = q->keys[i];
        vals[j] = q->vals[i];
    }
    free(q->keys);
    free(q->vals);
    q->keys = keys;
    q->vals = vals;
    q->cap = cap;
    return LM_OK;
}

static lm_status reserve(co_cq *q)
{
    if ((uint64_t)(q->count + 1) * 4 > (uint64_t)q->cap * 3) {
        lm_status s = rehash(q, q->cap ? q->cap * 2 : 1024);
        if (s)
            return s;
    }
    if (q->n_free == 0 && q->n_slots == q->cap_slots) {
        uint32_t c = q->cap_slots ? q->cap_slots * 2 : 1024;
        slot *s = realloc(q->slots, (size_t)c * sizeof *s);
        uint32_t *f = s ? realloc(q->free_slots, (size_t)c * sizeof *f) : NULL;
        uint32_t *h = f ? realloc(q->heap, (size_t)c * sizeof *h) : NULL;
        if (s)
            q->slots = s;
        if (f)
            q->free_slots = f;
        if (h)
            q->heap = h;
        if (!h)
            return lm_fail(LM_E_NOMEM, "out of memory growing the collapse queue");
        q->cap_slots = c;
    }
    return LM_OK;
}

/* ---- heap -------------------------------------------------------------------------------- */

static int less(const co_cq *q, uint32_t x, uint32_t y)
{
    const co_cq_entry *a = &q->slots[x].e, *b = &q->slots[y].e;
    if (a->est != b->est)
        return a->est < b->est;
    if (a->a != b->a)
        return a->a < b->a;
    return a->b < b->b;
}

static void place(co_cq *q, uint32_t pos, uint32_t s)
{
    q->heap[pos] = s;
    q->slots[s].heap_pos = pos;
}

static void sift_up(co_cq *q, uint32_t pos)
{
    uint32_t s = q->heap[pos];
    while (pos > 0) {
        uint32_t parent = (pos - 1) / 2;
        if (!less(q, s, q->heap[parent]))
            break;
        place(q, pos, q->heap[parent]);
        pos = parent;
    }
    place(q, pos, s);
}

static void sift_down(co_cq *q, uint32_t pos)
{
    uint32_t s = q->heap[pos];
    for (;;) {
        uint32_t c = 2 * pos + 1;
        if (c >= q->n_heap)
            break;
        if (c + 1 < q->n_heap && less(q, q->heap[c + 1], q->heap[c]))
            c++;
        if (!less(q, q->heap[c], s))
            break;
        place(q, pos, q->heap[c]);
        pos = c;
    }
    place(q, pos, s);
}

static void heap_remove(co_cq *q, uint32_t s)
{
    uint32_t pos = q->slots[s].heap_pos;
    if (pos == UINT32_MAX)
        return;
    q->slots[s].heap_pos = UINT32_MAX;
    uint32_t last = q->heap[--q->n_heap];
    if (pos == q->n_heap)
        return;
    place(q, pos, last);
    sift_down(q, pos);
    sift_up(q, q->slots[last].heap_pos);
}

static void heap_update(co_cq *q, uint32_t s, int in_heap)
{
    if (!in_heap) {
        heap_remove(q, s);
        return;
    }
    if (q->slots[s].heap_pos == UINT32_MAX) {
        q->slots[s].heap_pos = q->n_heap;
        q->heap[q->n_heap++] = s;
    }
    sift_up(q, q->slots[s].heap_pos);
    sift_down(q, q->slots[s].heap_pos);
}

/* ---- map ----------------------------------------------------------------------------------- */

lm_status co_cq_set(co_cq *q, uint32_t a, uint32_t b, int64_t est, int level, int in_heap)
{
    uint64_t k = key_of(a, b);
    uint32_t pos, s;
    if (find(q, k, &pos)) {
        s = q->vals[pos];
    } else {
        lm_status st = reserve(q);
        if (st)
            return st;
        s = q->n_free ? q->free_slots[--q->n_free] : q->n_slots++;
        uint32_t i = hash(k, q->cap);
        while (q->keys[i])
            i = (i + 1) & (q->cap - 1);
        q->keys[i] = k;
        q->vals[i] = s;
        q->count++;
        q->slots[s].heap_pos = UINT32_MAX;
    }
    co_cq_entry *e = &q->slots[s].e;
    e->a = (uint32_t)(k >> 32);
    e->b = (uint32_t)k;
    e->est = est;
    e->level = level;
    e->in_heap = in_heap ? 1 : 0;
    heap_update(q, s, in_heap);
    return LM_OK;
}

lm_status co_cq_reset(co_cq *q, uint32_t a, uint32_t b)
{
    return co_cq_set(q, a, b, 0, -1, 1);
}

void co_cq_remove(co_cq *q, uint32_t a, uint32_t b)
{
    uint32_t pos;
    if (!find(q, key_of(a, b), &pos))
        return;
    uint32_t s = q->vals[pos];
    heap_remove(q, s);
    q->free_slots[q->n_free++] = s;
    q->count--;
    /* backward-shift deletion keeps probe chains intact */
    uint32_t i = pos;
    for (uint32_t j = (i + 1) & (q->cap - 1); q->keys[j]; j = (j + 1) & (q->cap - 1)) {
        uint32_t h = hash(q->keys[j], q->cap);
        int movable = i <= j ? (h <= i || h > j) : (h <= i && h > j);
        if (movable) {
            q->keys[i] = q->keys[j];
            q->vals[i] = q->vals[j];
            i = j;
        }
    }
    q->keys[i] = 0;
}

int co_cq_get(const co_cq *q, uint32_t a, uint32_t b, co_cq_entry *out)
{
    uint32_t pos;
    if (!find(q, key_of(a, b), &pos))
        return 0;
    *out = q->slots[q->vals[pos]].e;
    return 1;
}

int co_cq_peek(const co_cq *q, co_cq_entry *out)
{
    if (!q->n_heap)
        return 0;
    *out = q->slots[q->heap[0]].e;
    return 1;
}

int co_cq_pop(co_cq *q, co_cq_entry *out)
{
    if (!q->n_heap)
        return 0;
    uint32_t s = q->heap[0];
    *out = q->slots[s].e;
    heap_remove(q, s);
    q->slots[s].e.in_heap = 0;
    out->in_heap = 0;
    return 1;
}

uint32_t co_cq_count(const co_cq *q)
{
    return q->count;
}

static int cmp_entry(const void *x, const void *y)
{
    const co_cq_entry *a = x, *b = y;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

lm_status co_cq_export(const co_cq *q, co_cq_entry **out, uint32_t *n)
{
    co_cq_entry *e = malloc(((size_t)q->count + 1) * sizeof *e);
    if (!e)
        return lm_fail(LM_E_NOMEM, "out of memory exporting %u queue entries", q->count);
    uint32_t k = 0;
    for (uint32_t i = 0; i < q->cap; i++)
        if (q->keys[i])
            e[k++] = q->slots[q->vals[i]].e;
    qsort(e, k, sizeof *e, cmp_entry);
    *out = e;
    *n = k;
    return LM_OK;
}
