/* worker/render/cpu/cpu_setups.h — the subs drawn during one (patch, view) pass of an evaluation,
 * each with the record that shades it and its shading constants (made on first use). A sub is used
 * where it lies: in the table of the current triangles (worker/render/cpu/cpu_subcache.h) or in
 * this list's own pool, whose chunks never move until the next reset. */
#ifndef LM_WORKER_CPU_SETUPS_H
#define LM_WORKER_CPU_SETUPS_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/patch.h"
#include "worker/render/cpu/cpu_raster.h"
#include "worker/render/cpu/cpu_shade.h"

#define WK_CPU_POOL_CHUNK 512

typedef struct wk_cpu_setups {
    const wk_cpu_sub **sub;  /* [cap] */
    const lm_tri_data **tri; /* [cap] the record each sub shades with */
    wk_cpu_shade *shade;     /* [cap] valid where shade_ready */
    uint8_t *shade_ready;
    size_t n, cap;
    wk_cpu_sub **chunks; /* the pool: chunks of WK_CPU_POOL_CHUNK subs */
    size_t n_chunks, used;
} wk_cpu_setups;

/* Forget every setup (the pool's space is reused). */
void wk_cpu_setups_reset(wk_cpu_setups *s);
void wk_cpu_setups_free(wk_cpu_setups *s);
/* Room in the pool for k <= WK_CPU_MAX_SUBS consecutive subs, valid until the next reset. */
lm_status wk_cpu_setups_pool(wk_cpu_setups *s, int k, wk_cpu_sub **out);
/* Append subs[0..k) (used in place: valid until the next reset) shaded with record t. */
lm_status wk_cpu_setups_push(wk_cpu_setups *s, const wk_cpu_sub *subs, int k, const lm_tri_data *t);

#endif
