/* coordinator/optimizer/idset.h — a small set of element ids (vertices or triangles) that keeps
 * insertion order and rejects duplicates in O(1) with generation stamps; clearing is O(1). Memory
 * grows only when the id range or the count grows, so the optimizer's hot loop does not allocate.
 */
#ifndef LM_COORDINATOR_IDSET_H
#define LM_COORDINATOR_IDSET_H

#include <stdint.h>

#include "common/error.h"

typedef struct co_idset {
    uint32_t *ids; /* members in insertion order */
    uint32_t n, cap;
    uint32_t *stamp; /* per id: generation in which it was added */
    uint32_t range;  /* ids < range are accepted without growing */
    uint32_t gen;
} co_idset;

void co_idset_init(co_idset *s);
void co_idset_free(co_idset *s);
void co_idset_clear(co_idset *s);
/* Adds id (no-op if present). */
lm_status co_idset_add(co_idset *s, uint32_t id);
int co_idset_has(const co_idset *s, uint32_t id);
/* Sort the member list ascending (membership unchanged). */
void co_idset_sort(co_idset *s);
/* Keep the first n members. */
void co_idset_truncate(co_idset *s, uint32_t n);

#endif
