/* worker/render/shared/grow.h — how the renderers' growable tables grow: by doubling, from a first
 * capacity, until the need fits. */
#ifndef LM_WORKER_RENDER_SHARED_GROW_H
#define LM_WORKER_RENDER_SHARED_GROW_H

#include <stddef.h>

/* The capacity for need entries: cap (first when 0) doubled as often as it takes. */
static inline size_t wk_grown_cap(size_t cap, size_t need, size_t first)
{
    cap = cap ? cap : first;
    while (cap < need)
        cap *= 2;
    return cap;
}

#endif
