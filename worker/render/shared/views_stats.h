/* worker/render/shared/views_stats.h — what an in-process views backend counts (both the GL and
 * the CPU backend keep these; wk_views_local_get_stats reads them). */
#ifndef LM_WORKER_RENDER_SHARED_VIEWS_STATS_H
#define LM_WORKER_RENDER_SHARED_VIEWS_STATS_H

#include <stdint.h>

/* Introspection for tests and benchmarks. */
typedef struct wk_views_local_stats {
    uint64_t evaluations;    /* patches evaluated */
    uint64_t batches;        /* readback synchronisations in evaluate/commit */
    uint64_t tris_drawn;     /* triangles sent in evaluate/commit */
    uint64_t regions;        /* view regions redrawn in evaluate/commit */
    uint64_t region_pixels;  /* their pixels */
    uint64_t commits_cached; /* commits that reused an evaluation's pixels */
    uint64_t views_skipped;  /* (patch, view) pairs not drawn: change hidden or off-screen */
} wk_views_local_stats;

#endif
