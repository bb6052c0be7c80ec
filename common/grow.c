/* common/grow.c — the growth rule of growing arrays (common/grow.h). */
#include "common/grow.h"

#include <stdlib.h>

#include "common/error.h"

size_t lm_grow_cap(size_t cap, size_t need, size_t first, size_t max)
{
    if (need <= cap)
        return cap;
    if (need > max)
        return 0;
    size_t c = cap ? cap : first ? first : 1;
    if (c > max)
        c = max;
    while (c < need)
        c = c > max / 2 ? max : c * 2;
    return c;
}

bool lm_resize(void **items, size_t n, size_t item_size)
{
    LM_ASSERT(item_size > 0);
    if (n > SIZE_MAX / item_size)
        return false;
    void *p = realloc(*items, n ? n * item_size : 1);
    if (!p)
        return false;
    *items = p;
    return true;
}

/* lm_grow with the capacity never above `most`. */
static bool grow_at_most(void **items, size_t *cap, size_t need, size_t item_size, size_t first,
                         size_t most)
{
    if (need <= *cap)
        return true;
    LM_ASSERT(item_size > 0);
    if (most > SIZE_MAX / item_size)
        most = SIZE_MAX / item_size;
    size_t c = lm_grow_cap(*cap, need, first, most);
    if (!c || !lm_resize(items, c, item_size))
        return false;
    *cap = c;
    return true;
}

bool lm_grow(void **items, size_t *cap, size_t need, size_t item_size, size_t first)
{
    return grow_at_most(items, cap, need, item_size, first, SIZE_MAX);
}

bool lm_grow32(void **items, uint32_t *cap, size_t need, size_t item_size, uint32_t first)
{
    size_t c = *cap;
    if (!grow_at_most(items, &c, need, item_size, first, UINT32_MAX))
        return false;
    *cap = (uint32_t)c;
    return true;
}
