/* common/optimizer/collapse_queue.c — an indexed binary min-heap (common/indexed_heap.h) over
 * an open-addressing hash map (linear probing with backward-shift deletion) of edge entries. */
#include "common/optimizer/collapse_queue.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/indexed_heap.h"

struct lm_cq {
    uint64_t *keys; /* 0 = empty; else key of the edge */
    uint32_t *vals; /* index into slots */
    uint32_t cap;   /* power of two */
    uint32_t count;
    lm_cq_entry *slots;
    uint32_t n_slots, cap_slots;
    uint32_t *free_slots;
    uint32_t n_free;
    lm_iheap heap; /* slots by (est, a, b) */
    lm_cq_observer observer;
    void *observer_ctx;
};

static void told(const lm_cq *q, const lm_cq_entry *e, int present)
{
    if (q->observer)
        q->observer(q->observer_ctx, e, present);
}

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

lm_status lm_cq_create(lm_cq **out)
{
    lm_cq *q = calloc(1, sizeof *q);
    if (!q)
        return lm_fail(LM_E_NOMEM, "out of memory creating the collapse queue");
    lm_iheap_init(&q->heap);
    *out = q;
    return LM_OK;
}

void lm_cq_destroy(lm_cq *q)
{
    if (!q)
        return;
    free(q->keys);
    free(q->vals);
    free(q->slots);
    free(q->free_slots);
    lm_iheap_free(&q->heap);
    free(q);
}

void lm_cq_clear(lm_cq *q)
{
    if (q->keys)
        memset(q->keys, 0, (size_t)q->cap * sizeof *q->keys);
    q->count = q->n_slots = q->n_free = 0;
    lm_iheap_clear(&q->heap);
}

void lm_cq_observe(lm_cq *q, lm_cq_observer fn, void *ctx)
{
    q->observer = fn;
    q->observer_ctx = ctx;
}

/* Room in dst for src's map and slots. */
static lm_status reserve_copy(lm_cq *dst, const lm_cq *src)
{
    if (dst->cap < src->cap &&
        (!LM_RESIZE(&dst->keys, src->cap) || !LM_RESIZE(&dst->vals, src->cap)))
        return lm_fail(LM_E_NOMEM, "out of memory copying the collapse queue");
    if (dst->cap < src->cap)
        dst->cap = src->cap;
    if (dst->cap_slots < src->cap_slots &&
        (!LM_RESIZE(&dst->slots, src->cap_slots) || !LM_RESIZE(&dst->free_slots, src->cap_slots)))
        return lm_fail(LM_E_NOMEM, "out of memory copying the collapse queue");
    if (dst->cap_slots < src->cap_slots)
        dst->cap_slots = src->cap_slots;
    if (!lm_iheap_copy(&dst->heap, &src->heap))
        return lm_fail(LM_E_NOMEM, "out of memory copying the collapse queue");
    return LM_OK;
}

lm_status lm_cq_copy(lm_cq *dst, const lm_cq *src)
{
    lm_status st = reserve_copy(dst, src);
    if (st)
        return st;
    dst->cap = src->cap; /* the map's size decides where keys sit: exactly src's */
    if (src->cap) {
        memcpy(dst->keys, src->keys, (size_t)src->cap * sizeof *src->keys);
        memcpy(dst->vals, src->vals, (size_t)src->cap * sizeof *src->vals);
    }
    if (src->n_slots)
        memcpy(dst->slots, src->slots, (size_t)src->n_slots * sizeof *src->slots);
    if (src->n_free)
        memcpy(dst->free_slots, src->free_slots, (size_t)src->n_free * sizeof *src->free_slots);
    dst->count = src->count;
    dst->n_slots = src->n_slots;
    dst->n_free = src->n_free;
    return LM_OK;
}

static int find(const lm_cq *q, uint64_t k, uint32_t *pos)
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

static lm_status rehash(lm_cq *q, uint32_t cap)
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

static lm_status reserve(lm_cq *q)
{
    if ((uint64_t)(q->count + 1) * 4 > (uint64_t)q->cap * 3) {
        lm_status s = rehash(q, q->cap ? q->cap * 2 : 1024);
        if (s)
            return s;
    }
    if (q->n_free == 0 && q->n_slots == q->cap_slots) {
        size_t c = lm_grow_cap(q->cap_slots, q->n_slots + 1, 1024, UINT32_MAX);
        if (!c || !LM_RESIZE(&q->slots, c) || !LM_RESIZE(&q->free_slots, c) ||
            !lm_iheap_reserve(&q->heap, (uint32_t)c))
            return lm_fail(LM_E_NOMEM, "out of memory growing the collapse queue");
        q->cap_slots = (uint32_t)c;
    }
    return LM_OK;
}

/* An entry's place in the heap: by (est, a, b), in it while poppable. */
static void heap_update(lm_cq *q, uint32_t s)
{
    const lm_cq_entry *e = &q->slots[s];
    if (e->in_heap)
        lm_iheap_set(&q->heap, s, e->est, (uint64_t)e->a << 32 | e->b);
    else
        lm_iheap_remove(&q->heap, s);
}

/* ---- map ----------------------------------------------------------------------------------- */

lm_status lm_cq_set(lm_cq *q, uint32_t a, uint32_t b, int64_t est, int level, int in_heap)
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
    }
    lm_cq_entry *e = &q->slots[s];
    e->a = (uint32_t)(k >> 32);
    e->b = (uint32_t)k;
    e->est = est;
    e->level = level;
    e->in_heap = in_heap ? 1 : 0;
    heap_update(q, s);
    told(q, e, 1);
    return LM_OK;
}

lm_status lm_cq_reset(lm_cq *q, uint32_t a, uint32_t b)
{
    return lm_cq_set(q, a, b, 0, -1, 1);
}

void lm_cq_remove(lm_cq *q, uint32_t a, uint32_t b)
{
    uint32_t pos;
    if (!find(q, key_of(a, b), &pos))
        return;
    uint32_t s = q->vals[pos];
    told(q, &q->slots[s], 0);
    lm_iheap_remove(&q->heap, s);
    q->slots[s].a = q->slots[s].b = UINT32_MAX; /* free (lm_cq_export skips it) */
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

int lm_cq_get(const lm_cq *q, uint32_t a, uint32_t b, lm_cq_entry *out)
{
    uint32_t pos;
    if (!find(q, key_of(a, b), &pos))
        return 0;
    *out = q->slots[q->vals[pos]];
    return 1;
}

int lm_cq_peek(const lm_cq *q, lm_cq_entry *out)
{
    uint32_t s = lm_iheap_top(&q->heap);
    if (s == LM_IHEAP_OUT)
        return 0;
    *out = q->slots[s];
    return 1;
}

int lm_cq_pop(lm_cq *q, lm_cq_entry *out)
{
    uint32_t s = lm_iheap_top(&q->heap);
    if (s == LM_IHEAP_OUT)
        return 0;
    lm_iheap_remove(&q->heap, s);
    q->slots[s].in_heap = 0;
    *out = q->slots[s];
    told(q, out, 1);
    return 1;
}

uint32_t lm_cq_count(const lm_cq *q)
{
    return q->count;
}

static int cmp_entry(const void *x, const void *y)
{
    const lm_cq_entry *a = x, *b = y;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

static int slot_free(const lm_cq_entry *e)
{
    return e->a == UINT32_MAX && e->b == UINT32_MAX;
}

/* A run of entries of one a, by b: insertion for the usual few edges of a vertex, qsort for a
 * fan's many (a hostile or CAD model's vertex of 10^5 edges must not cost 10^10 steps). */
static void sort_run(lm_cq_entry *r, uint32_t n)
{
    if (n > 32) {
        qsort(r, n, sizeof *r, cmp_entry);
        return;
    }
    for (uint32_t i = 1; i < n; i++) {
        lm_cq_entry x = r[i];
        uint32_t j = i;
        for (; j > 0 && cmp_entry(&r[j - 1], &x) > 0; j--)
            r[j] = r[j - 1];
        r[j] = x;
    }
}

/* e[0..n) into out in (a, b) order, as qsort with cmp_entry orders them (the pairs are
 * distinct): counted by a (stable), then each run of one a by b (sort_run); where the ids are
 * sparse, by qsort. 0 when out of memory for the counts. */
static int sort_entries(const lm_cq_entry *e, uint32_t n, lm_cq_entry *out)
{
    uint32_t max_a = 0;
    for (uint32_t i = 0; i < n; i++)
        max_a = e[i].a > max_a ? e[i].a : max_a;
    if ((uint64_t)max_a > 4u * (uint64_t)n + 1024u) { /* sparse ids (e.g. a hostile checkpoint's
                                                         queue): counts would cost O(max id) */
        memcpy(out, e, (size_t)n * sizeof *e);
        qsort(out, n, sizeof *out, cmp_entry);
        return 1;
    }
    uint32_t *at = calloc((size_t)max_a + 2, sizeof *at);
    if (!at)
        return 0;
    for (uint32_t i = 0; i < n; i++)
        at[e[i].a + 1]++;
    for (uint32_t a = 0; a <= max_a; a++)
        at[a + 1] += at[a];
    for (uint32_t i = 0; i < n; i++)
        out[at[e[i].a]++] = e[i];
    free(at);
    for (uint32_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && out[j].a == out[i].a;)
            j++;
        sort_run(out + i, j - i);
    }
    return 1;
}

lm_status lm_cq_export(const lm_cq *q, lm_cq_entry **out, uint32_t *n)
{
    lm_cq_entry *e = malloc(((size_t)q->count + 1) * sizeof *e);
    lm_cq_entry *s = malloc(((size_t)q->count + 1) * sizeof *s);
    uint32_t k = 0, live = 0;
    for (uint32_t i = 0; i < q->n_slots; i++) /* free slots are marked (lm_cq_remove) */
        live += !slot_free(&q->slots[i]);
    for (uint32_t i = 0; e && live == q->count && i < q->n_slots; i++) /* in slot order */
        if (!slot_free(&q->slots[i]))
            e[k++] = q->slots[i];
    for (uint32_t i = 0; e && live != q->count && i < q->cap; i++) /* else from the table */
        if (q->keys[i])
            e[k++] = q->slots[q->vals[i]];
    if (!e || !s || !sort_entries(e, k, s)) {
        free(e);
        free(s);
        return lm_fail(LM_E_NOMEM, "out of memory exporting %u queue entries", q->count);
    }
    free(e);
    *out = s;
    *n = k;
    return LM_OK;
}
