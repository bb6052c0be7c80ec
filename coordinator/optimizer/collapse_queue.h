/* coordinator/optimizer/collapse_queue.h — the priority queue of edge-collapse energy estimates
 * used by the vertex teleport (paper §5.3). Each undirected edge (a < b) has an estimate and the
 * optimisation level it was obtained at (-1 = default state: energy 0, unknown). Entries are
 * ordered by (estimate, a, b), a total order, so the order in which entries come out depends only
 * on the set of entries, not on the history of the heap (a checkpoint can store the entries sorted
 * and a resumed run pops the same sequence). Entries whose edge disappeared are dropped lazily by
 * the caller (checked when popped). */
#ifndef LM_COORDINATOR_COLLAPSE_QUEUE_H
#define LM_COORDINATOR_COLLAPSE_QUEUE_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

typedef struct co_cq_entry {
    uint32_t a, b;    /* a < b */
    int64_t est;      /* estimated ΔE of collapsing (INT64_MAX: illegal) */
    int32_t level;    /* -1..3 */
    uint32_t in_heap; /* 1 while it can be popped */
} co_cq_entry;

typedef struct co_cq co_cq;

lm_status co_cq_create(co_cq **out);
void co_cq_destroy(co_cq *q);
void co_cq_clear(co_cq *q);

/* Insert or update (a, b) (either order); in_heap decides whether it can be popped. */
lm_status co_cq_set(co_cq *q, uint32_t a, uint32_t b, int64_t est, int level, int in_heap);
/* Back to the default state (0, -1), poppable. */
lm_status co_cq_reset(co_cq *q, uint32_t a, uint32_t b);
void co_cq_remove(co_cq *q, uint32_t a, uint32_t b);
/* Look up (a, b); returns 0 if absent. */
int co_cq_get(const co_cq *q, uint32_t a, uint32_t b, co_cq_entry *out);

/* The lowest poppable entry: peek leaves it, pop takes it out of the heap (it stays known with
 * in_heap = 0). Return 0 when none. */
int co_cq_peek(const co_cq *q, co_cq_entry *out);
int co_cq_pop(co_cq *q, co_cq_entry *out);

uint32_t co_cq_count(const co_cq *q);
/* All entries sorted by (a, b) into a new array (caller frees). */
lm_status co_cq_export(const co_cq *q, co_cq_entry **out, uint32_t *n);

#endif
