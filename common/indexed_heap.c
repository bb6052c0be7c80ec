/* common/indexed_heap.c — the indexed binary min-heap (common/indexed_heap.h): sift up and down
 * over the ids' keys, the positions kept as ids move. */
#include "common/indexed_heap.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

void lm_iheap_init(lm_iheap *h)
{
    memset(h, 0, sizeof *h);
}

void lm_iheap_free(lm_iheap *h)
{
    free(h->heap);
    free(h->pos);
    free(h->key);
    lm_iheap_init(h);
}

bool lm_iheap_reserve(lm_iheap *h, uint32_t n_ids)
{
    if (n_ids <= h->cap)
        return true;
    size_t cap = lm_grow_cap(h->cap, n_ids, 1024, UINT32_MAX);
    if (!cap || !LM_RESIZE(&h->heap, cap) || !LM_RESIZE(&h->pos, cap) || !LM_RESIZE(&h->key, cap))
        return false;
    for (size_t i = h->cap; i < cap; i++)
        h->pos[i] = LM_IHEAP_OUT;
    h->cap = (uint32_t)cap;
    return true;
}

void lm_iheap_clear(lm_iheap *h)
{
    for (uint32_t i = 0; i < h->n; i++)
        h->pos[h->heap[i]] = LM_IHEAP_OUT;
    h->n = 0;
}

bool lm_iheap_copy(lm_iheap *dst, const lm_iheap *src)
{
    if (!lm_iheap_reserve(dst, src->cap))
        return false;
    if (src->cap) {
        memcpy(dst->heap, src->heap, (size_t)src->n * sizeof *src->heap);
        memcpy(dst->pos, src->pos, (size_t)src->cap * sizeof *src->pos);
        memcpy(dst->key, src->key, (size_t)src->cap * sizeof *src->key);
    }
    for (uint32_t i = src->cap; i < dst->cap; i++)
        dst->pos[i] = LM_IHEAP_OUT;
    dst->n = src->n;
    return true;
}

static bool less(const lm_iheap *h, uint32_t x, uint32_t y)
{
    const lm_iheap_key *a = &h->key[x], *b = &h->key[y];
    if (a->prio != b->prio)
        return a->prio < b->prio;
    return a->tie < b->tie;
}

static void place(lm_iheap *h, uint32_t at, uint32_t id)
{
    h->heap[at] = id;
    h->pos[id] = at;
}

static void sift_up(lm_iheap *h, uint32_t at)
{
    uint32_t id = h->heap[at];
    while (at > 0) {
        uint32_t parent = (at - 1) / 2;
        if (!less(h, id, h->heap[parent]))
            break;
        place(h, at, h->heap[parent]);
        at = parent;
    }
    place(h, at, id);
}

static void sift_down(lm_iheap *h, uint32_t at)
{
    uint32_t id = h->heap[at];
    for (;;) {
        uint32_t c = 2 * at + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && less(h, h->heap[c + 1], h->heap[c]))
            c++;
        if (!less(h, h->heap[c], id))
            break;
        place(h, at, h->heap[c]);
        at = c;
    }
    place(h, at, id);
}

void lm_iheap_set(lm_iheap *h, uint32_t id, int64_t prio, uint64_t tie)
{
    h->key[id] = (lm_iheap_key){prio, tie};
    if (h->pos[id] == LM_IHEAP_OUT) {
        place(h, h->n++, id);
        sift_up(h, h->n - 1);
        return;
    }
    sift_up(h, h->pos[id]);
    sift_down(h, h->pos[id]);
}

void lm_iheap_remove(lm_iheap *h, uint32_t id)
{
    uint32_t at = h->pos[id];
    if (at == LM_IHEAP_OUT)
        return;
    h->pos[id] = LM_IHEAP_OUT;
    uint32_t last = h->heap[--h->n];
    if (at == h->n)
        return;
    place(h, at, last);
    sift_up(h, at);
    sift_down(h, h->pos[last]);
}
