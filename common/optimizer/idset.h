/* common/optimizer/idset.h — a small set of element ids (vertices or triangles) that keeps
 * insertion order and rejects duplicates in O(1) with generation stamps; clearing is O(1). Memory
 * grows only when the id range or the count grows, so the optimizer's hot loop does not allocate.
 */
#ifndef LM_COMMON_OPTIMIZER_IDSET_H
#define LM_COMMON_OPTIMIZER_IDSET_H

#include <stdint.h>

#include "common/error.h"

typedef struct lm_idset {
    uint32_t *ids; /* members in insertion order */
    uint32_t n, cap;
    uint32_t *stamp; /* per id: generation in which it was added */
    uint32_t range;  /* ids < range are accepted without growing */
    uint32_t gen;
} lm_idset;

void lm_idset_init(lm_idset *s);
void lm_idset_free(lm_idset *s);
void lm_idset_clear(lm_idset *s);
/* Adds id (no-op if present). */
lm_status lm_idset_add(lm_idset *s, uint32_t id);
int lm_idset_has(const lm_idset *s, uint32_t id);
/* Sort the member list ascending (membership unchanged). */
void lm_idset_sort(lm_idset *s);
/* Keep the first n members. */
void lm_idset_truncate(lm_idset *s, uint32_t n);

#endif
