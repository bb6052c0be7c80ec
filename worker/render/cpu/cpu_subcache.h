/* worker/render/cpu/cpu_subcache.h — the subs of the current mesh's triangles, per view, set up
 * once and kept until the triangle changes: evaluations search and draw the same kept triangles
 * (and the twins, whose corners do not move) again and again. A triangle's entry is forgotten when
 * a commit removes it and all are when set_mesh replaces the mesh. Only triangles of one sub are
 * kept (clipped ones are set up each time); the table is off when it would need more than
 * WK_CPU_SUBCACHE_BYTES. A setup is a pure function of the corners and the view, so a kept sub
 * is bit for bit the one a new setup would make. */
#ifndef LM_WORKER_CPU_SUBCACHE_H
#define LM_WORKER_CPU_SUBCACHE_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/view.h"
#include "worker/render/cpu/cpu_raster.h"

#define WK_CPU_SUBCACHE_BYTES ((size_t)256 << 20)

typedef struct wk_cpu_subcache {
    uint32_t n_views;
    size_t cap; /* ids */
    int enabled;
    wk_cpu_sub *sub[LM_MAX_VIEWS]; /* [cap] per view, made on first use */
    uint8_t *state[LM_MAX_VIEWS];  /* [cap]: 0 unknown, 1 one sub, 2 none, 3 several */
} wk_cpu_subcache;

void wk_cpu_subcache_init(wk_cpu_subcache *c, uint32_t n_views);
void wk_cpu_subcache_free(wk_cpu_subcache *c);
/* Room for ids below need (turns the table off, not an error, when it would be too large). */
lm_status wk_cpu_subcache_reserve(wk_cpu_subcache *c, size_t need);
/* Forget triangle id in every view / every triangle. */
void wk_cpu_subcache_forget(wk_cpu_subcache *c, uint32_t id);
void wk_cpu_subcache_clear(wk_cpu_subcache *c);
/* The subs of current triangle t in view h (v), as wk_cpu_tri_setup(v, t, ...) makes them: *n
 * of them at the returned address, the table's own copy (valid until the triangle is forgotten
 * or the table grows) or else `scratch` (WK_CPU_MAX_SUBS). */
const wk_cpu_sub *wk_cpu_subcache_get(wk_cpu_subcache *c, const wk_cpu_view *v, uint32_t h,
                                      const lm_tri_data *t, wk_cpu_sub *scratch, int *n);

/* Ask for the memory of triangle id's entry in view h (a hint). */
void wk_cpu_subcache_prefetch(const wk_cpu_subcache *c, uint32_t h, uint32_t id);
/* The kept sub of triangle id in view h when the table holds exactly one for it, else NULL (none,
 * several or not set up yet); sets nothing up. */
const wk_cpu_sub *wk_cpu_subcache_peek(const wk_cpu_subcache *c, uint32_t h, uint32_t id);

#endif
