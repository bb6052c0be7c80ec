/* common/indexed_heap.h — an indexed binary min-heap: ids 0..cap-1, each in the heap or out of
 * it, each in it with a key (prio, tie), ordered by prio, then tie, both ascending. The heap knows
 * where every id sits, so a key changes, or an id leaves, from anywhere in O(log n). Callers that
 * give the ids in the heap distinct ties have a total order: the top is then the least key,
 * whatever the history of the heap. The struct is embedded by its owner; its fields are the heap's
 * own. */
#ifndef LM_COMMON_INDEXED_HEAP_H
#define LM_COMMON_INDEXED_HEAP_H

#include <stdbool.h>
#include <stdint.h>

#define LM_IHEAP_OUT UINT32_MAX /* the position of an id not in the heap */

typedef struct lm_iheap_key {
    int64_t prio;
    uint64_t tie;
} lm_iheap_key;

typedef struct lm_iheap {
    uint32_t *heap;    /* [n] ids, heap-ordered */
    uint32_t *pos;     /* [cap] per id: its index in heap, or LM_IHEAP_OUT */
    lm_iheap_key *key; /* [cap] per id: its key while in the heap */
    uint32_t n, cap;
} lm_iheap;

/* An empty heap with room for no id; lm_iheap_free releases its arrays (and leaves it empty). */
void lm_iheap_init(lm_iheap *h);
void lm_iheap_free(lm_iheap *h);
/* Room for ids 0..n_ids-1 (the capacity doubling as needed), the new ones out of the heap. false,
 * with nothing changed, when memory runs out. */
bool lm_iheap_reserve(lm_iheap *h, uint32_t n_ids);
/* Every id out of the heap. */
void lm_iheap_clear(lm_iheap *h);
/* dst becomes a copy of src (its ids, keys and layout); false, dst unchanged, when memory runs
 * out. */
bool lm_iheap_copy(lm_iheap *dst, const lm_iheap *src);

/* Id (< cap) into the heap with key (prio, tie), or moved to that key when it is in it. */
void lm_iheap_set(lm_iheap *h, uint32_t id, int64_t prio, uint64_t tie);
/* Id (< cap) out of the heap; nothing when it is not in it. */
void lm_iheap_remove(lm_iheap *h, uint32_t id);

/* The id with the lowest key, LM_IHEAP_OUT when the heap is empty. */
static inline uint32_t lm_iheap_top(const lm_iheap *h)
{
    return h->n ? h->heap[0] : LM_IHEAP_OUT;
}
static inline uint32_t lm_iheap_count(const lm_iheap *h)
{
    return h->n;
}
static inline bool lm_iheap_has(const lm_iheap *h, uint32_t id)
{
    return h->pos[id] != LM_IHEAP_OUT;
}

#endif
