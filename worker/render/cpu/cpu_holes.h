/* worker/render/cpu/cpu_holes.h — step A of a view's evaluation pass (cpu_eval.c: the pixels where
 * the patch's removed triangles are the visible surface, logged and made background, or logged for
 * shading where a removed triangle is a twin) remembered per view, so that the next pass with the
 * same removed triangles and twins, against the same keys, replays the log instead of rasterising
 * those triangles again. The optimizer's downhill simplex evaluates one edge's neighbourhood
 * dozens of times in a row: every evaluation removes the same triangles and adds them moved. The
 * replay writes exactly what the rasterising wrote, in the same order. */
#ifndef LM_WORKER_CPU_HOLES_H
#define LM_WORKER_CPU_HOLES_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "worker/render/cpu/cpu_raster.h"

/* A step A of more logged pixels than this is not kept (a rare large patch: the memory is not
 * worth it, and its rasterising is mostly work, not set-up). */
#define WK_CPU_HOLES_MAX_PIXELS 65536u

typedef struct wk_cpu_holes {
    int valid;
    uint64_t seq;  /* the views' state (changes of keys) it was found against */
    int occlusion; /* and their occlusion setting */
    uint32_t *removed, n_removed, cap_removed; /* the patch's removed ids, in order */
    uint8_t *twin;                             /* [n_removed] 1 where that id was a twin */
    uint32_t *idx, *xy;                        /* the log entries step A made, in order */
    uint64_t *old;
    uint8_t *flag;
    size_t n, cap;
    uint32_t *tiles; /* the tiles whose maxima it raised, in order */
    size_t n_tiles, cap_tiles;
} wk_cpu_holes;

/* Whether c holds step A of a pass with these removed ids and twin flags against state seq with
 * this occlusion setting. */
int wk_cpu_holes_match(const wk_cpu_holes *c, uint64_t seq, int occlusion, const uint32_t *removed,
                       const uint8_t *twin, uint32_t n_removed);

/* Remember step A: the first n entries of log and the tiles raised. Too many pixels, or no
 * memory for them, leaves c empty (not an error: the next pass rasterises). */
void wk_cpu_holes_keep(wk_cpu_holes *c, uint64_t seq, int occlusion, const uint32_t *removed,
                       const uint8_t *twin, uint32_t n_removed, const wk_cpu_log *log, size_t n,
                       const uint32_t *tiles, size_t n_tiles);

static inline void wk_cpu_holes_forget(wk_cpu_holes *c)
{
    c->valid = 0;
}

void wk_cpu_holes_free(wk_cpu_holes *c);

#endif
