/* common/optimizer/collapse_queue.h — the priority queue of edge-collapse energy estimates
 * used by the vertex teleport (paper §5.3). Each undirected edge (a < b) has an estimate and the
 * optimisation level it was obtained at (-1 = default state: energy 0, unknown). Entries are
 * ordered by (estimate, a, b), a total order, so the order in which entries come out depends only
 * on the set of entries, not on the history of the heap (a checkpoint can store the entries sorted
 * and a resumed run pops the same sequence). Entries whose edge disappeared are dropped lazily by
 * the caller (checked when popped). */
#ifndef LM_COMMON_OPTIMIZER_COLLAPSE_QUEUE_H
#define LM_COMMON_OPTIMIZER_COLLAPSE_QUEUE_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

typedef struct lm_cq_entry {
    uint32_t a, b;    /* a < b */
    int64_t est;      /* estimated ΔE of collapsing (INT64_MAX: illegal) */
    int32_t level;    /* -1..3 */
    uint32_t in_heap; /* 1 while it can be popped */
} lm_cq_entry;

typedef struct lm_cq lm_cq;

/* Told of every change (set, reset, remove, pop) with the entry as it is afterwards; present 0
 * when it was removed. */
typedef void (*lm_cq_observer)(void *ctx, const lm_cq_entry *e, int present);

lm_status lm_cq_create(lm_cq **out);
void lm_cq_destroy(lm_cq *q);
void lm_cq_clear(lm_cq *q);
/* dst's entries and heap become src's (dst's observer stays dst's); dst unchanged on failure. */
lm_status lm_cq_copy(lm_cq *dst, const lm_cq *src);
/* fn (NULL = none) is told of q's changes from now on (lanes.c's isolated lanes log them). */
void lm_cq_observe(lm_cq *q, lm_cq_observer fn, void *ctx);

/* Insert or update (a, b) (either order); in_heap decides whether it can be popped. */
lm_status lm_cq_set(lm_cq *q, uint32_t a, uint32_t b, int64_t est, int level, int in_heap);
/* Back to the default state (0, -1), poppable. */
lm_status lm_cq_reset(lm_cq *q, uint32_t a, uint32_t b);
void lm_cq_remove(lm_cq *q, uint32_t a, uint32_t b);
/* Look up (a, b); returns 0 if absent. */
int lm_cq_get(const lm_cq *q, uint32_t a, uint32_t b, lm_cq_entry *out);

/* The lowest poppable entry: peek leaves it, pop takes it out of the heap (it stays known with
 * in_heap = 0). Return 0 when none. */
int lm_cq_peek(const lm_cq *q, lm_cq_entry *out);
int lm_cq_pop(lm_cq *q, lm_cq_entry *out);

uint32_t lm_cq_count(const lm_cq *q);
/* All entries sorted by (a, b) into a new array (caller frees). */
lm_status lm_cq_export(const lm_cq *q, lm_cq_entry **out, uint32_t *n);

#endif
