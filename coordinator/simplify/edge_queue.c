/* coordinator/simplify/edge_queue.c — entries, an open-addressing hash (edge -> entry) and an
 * indexed binary min-heap (common/indexed_heap.h) over (cost, a, b). */
#include "coordinator/simplify/edge_queue.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/indexed_heap.h"

#define CO_EQ_EMPTY UINT32_MAX
#define CO_EQ_GONE (UINT32_MAX - 1) /* a hash slot whose entry was removed */

struct co_eq {
    uint32_t n_views;
    co_eq_entry *e;
    co_rect *rects; /* [cap * n_views] */
    uint32_t n, cap;
    uint32_t *slots; /* hash: entry index, CO_EQ_EMPTY or CO_EQ_GONE */
    uint32_t n_slots, used_slots;
    lm_iheap heap; /* the live entries by (cost, a, b) */
};

static uint64_t edge_hash(uint32_t a, uint32_t b)
{
    uint64_t x = ((uint64_t)a << 32 | b) * 0x9E3779B97F4A7C15ull;
    return x ^ (x >> 29);
}

lm_status co_eq_create(uint32_t n_views, co_eq **out)
{
    co_eq *q = calloc(1, sizeof *q);
    if (!q)
        return lm_fail(LM_E_NOMEM, "out of memory for the edge queue");
    q->n_views = n_views ? n_views : 1;
    lm_iheap_init(&q->heap);
    *out = q;
    return LM_OK;
}

void co_eq_destroy(co_eq *q)
{
    if (!q)
        return;
    for (uint32_t i = 0; i < q->n; i++)
        free(q->e[i].verts);
    free(q->e);
    free(q->rects);
    free(q->slots);
    lm_iheap_free(&q->heap);
    free(q);
}

co_eq_entry *co_eq_at(co_eq *q, uint32_t i)
{
    return &q->e[i];
}

co_rect *co_eq_rects(co_eq *q, uint32_t i)
{
    return q->rects + (size_t)i * q->n_views;
}

uint32_t co_eq_live(const co_eq *q)
{
    return lm_iheap_count(&q->heap);
}

uint32_t co_eq_size(const co_eq *q)
{
    return q->n;
}

/* ---- hash ---------------------------------------------------------------------------------- */

static uint32_t *slot_of(const co_eq *q, uint32_t a, uint32_t b, int for_insert)
{
    uint32_t mask = q->n_slots - 1, *gone = NULL;
    for (uint32_t s = (uint32_t)edge_hash(a, b) & mask;; s = (s + 1) & mask) {
        uint32_t x = q->slots[s];
        if (x == CO_EQ_EMPTY)
            return for_insert && gone ? gone : for_insert ? &q->slots[s] : NULL;
        if (x == CO_EQ_GONE) {
            gone = gone ? gone : &q->slots[s];
            continue;
        }
        if (q->e[x].a == a && q->e[x].b == b)
            return &q->slots[s];
    }
}

static lm_status rehash(co_eq *q, uint32_t n_slots)
{
    uint32_t *s = malloc((size_t)n_slots * sizeof *s);
    if (!s)
        return lm_fail(LM_E_NOMEM, "out of memory for the edge queue's hash");
    memset(s, 0xff, (size_t)n_slots * sizeof *s);
    free(q->slots);
    q->slots = s;
    q->n_slots = n_slots;
    q->used_slots = 0;
    for (uint32_t i = 0; i < q->n; i++)
        if (q->e[i].state != CO_EQ_DEAD) {
            *slot_of(q, q->e[i].a, q->e[i].b, 1) = i;
            q->used_slots++;
        }
    return LM_OK;
}

uint32_t co_eq_find(const co_eq *q, uint32_t a, uint32_t b)
{
    if (a > b) {
        uint32_t t = a;
        a = b;
        b = t;
    }
    if (!q->n_slots)
        return UINT32_MAX;
    uint32_t *s = slot_of(q, a, b, 0);
    return s ? *s : UINT32_MAX;
}

/* ---- heap ---------------------------------------------------------------------------------- */

/* Entry i into the heap at its cost, or moved to it. */
static void heap_set(co_eq *q, uint32_t i)
{
    const co_eq_entry *e = &q->e[i];
    lm_iheap_set(&q->heap, i, e->cost, (uint64_t)e->a << 32 | e->b);
}

uint32_t co_eq_top(const co_eq *q)
{
    uint32_t i = lm_iheap_top(&q->heap);
    return i == LM_IHEAP_OUT ? UINT32_MAX : i;
}

void co_eq_set_cost(co_eq *q, uint32_t i, int64_t cost)
{
    co_eq_entry *e = &q->e[i];
    LM_ASSERT(e->state != CO_EQ_DEAD);
    e->cost = cost;
    heap_set(q, i);
}

void co_eq_detach(co_eq *q, uint32_t i)
{
    if (q->e[i].state != CO_EQ_DEAD)
        lm_iheap_remove(&q->heap, i);
}

/* ---- insert / remove ----------------------------------------------------------------------- */

static lm_status grow(co_eq *q)
{
    if (q->n < q->cap)
        return LM_OK;
    uint32_t cap = (uint32_t)lm_grow_cap(q->cap, q->n + 1, 1024, UINT32_MAX);
    if (!cap || !LM_RESIZE(&q->e, cap) ||
        !lm_resize((void **)&q->rects, (size_t)cap * q->n_views, sizeof *q->rects) ||
        !lm_iheap_reserve(&q->heap, cap))
        return lm_fail(LM_E_NOMEM, "out of memory for %u edges", cap);
    q->cap = cap;
    return LM_OK;
}

lm_status co_eq_insert(co_eq *q, uint32_t a, uint32_t b, int64_t cost, uint32_t *out)
{
    if (a > b) {
        uint32_t t = a;
        a = b;
        b = t;
    }
    LM_ASSERT(co_eq_find(q, a, b) == UINT32_MAX);
    lm_status st = grow(q);
    if (st == LM_OK && 2 * (q->used_slots + 1) > q->n_slots)
        st = rehash(q, q->n_slots ? 2 * q->n_slots : 4096);
    if (st != LM_OK)
        return st;
    uint32_t i = q->n++;
    q->e[i] = (co_eq_entry){.a = a, .b = b, .cost = cost, .state = CO_EQ_DIRTY};
    co_fp_clear(co_eq_rects(q, i), q->n_views);
    uint32_t *s = slot_of(q, a, b, 1);
    q->used_slots += *s == CO_EQ_EMPTY;
    *s = i;
    heap_set(q, i);
    if (out)
        *out = i;
    return LM_OK;
}

void co_eq_remove(co_eq *q, uint32_t i)
{
    co_eq_entry *e = &q->e[i];
    if (e->state == CO_EQ_DEAD)
        return;
    *slot_of(q, e->a, e->b, 0) = CO_EQ_GONE;
    lm_iheap_remove(&q->heap, i);
    e->state = CO_EQ_DEAD;
    free(e->verts);
    e->verts = NULL;
    e->n_verts = e->cap_verts = 0;
}

lm_status co_eq_set_verts(co_eq *q, uint32_t i, const uint32_t *verts, uint32_t n)
{
    co_eq_entry *e = &q->e[i];
    if (n > e->cap_verts) {
        uint32_t *v = realloc(e->verts, (size_t)n * sizeof *v);
        if (!v)
            return lm_fail(LM_E_NOMEM, "out of memory for an edge's vertices");
        e->verts = v;
        e->cap_verts = n;
    }
    if (n)
        memcpy(e->verts, verts, (size_t)n * sizeof *verts);
    e->n_verts = n;
    return LM_OK;
}
