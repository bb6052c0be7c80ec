/* common/grow.h — the one growth rule of arrays that grow as they fill: the capacity doubles (from
 * a first size) until it holds what is needed, never past a most, with every byte count checked
 * for overflow. A failed growth changes nothing: the array and its capacity stay as they were, and
 * the caller reports it in its own words. */
#ifndef LM_COMMON_GROW_H
#define LM_COMMON_GROW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The capacity that holds `need` items: `cap` (`first` when cap is 0) doubled until it does,
 * never above `max`. `cap` itself when it already holds them; 0 when need > max. */
size_t lm_grow_cap(size_t cap, size_t need, size_t first, size_t max);

/* *items := realloc(*items, n * item_size); false (and *items unchanged) when the size overflows
 * or memory runs out. */
bool lm_resize(void **items, size_t n, size_t item_size);

/* Room for `need` items in *items, an array of *cap items of item_size bytes: grown to
 * lm_grow_cap(*cap, need, first, the most its size allows). false, with *items and *cap unchanged,
 * when the size overflows or memory runs out. lm_grow32 is the same for a uint32_t capacity, which
 * then never passes UINT32_MAX. */
bool lm_grow(void **items, size_t *cap, size_t need, size_t item_size, size_t first);
bool lm_grow32(void **items, uint32_t *cap, size_t need, size_t item_size, uint32_t first);

/* LM_GROW(&array, &cap, need, first) and LM_GROW32 (cap a uint32_t): lm_grow and lm_grow32 with
 * the item size of *array. LM_RESIZE(&array, n): lm_resize with it. */
#define LM_GROW(items, cap, need, first)                                                           \
    lm_grow((void **)(items), (cap), (need), sizeof **(items), (first))
#define LM_GROW32(items, cap, need, first)                                                         \
    lm_grow32((void **)(items), (cap), (need), sizeof **(items), (first))
#define LM_RESIZE(items, n) lm_resize((void **)(items), (n), sizeof **(items))

#endif
