/* coordinator/simplify/work.h — what the image simplifier's users share (simplify, lod, tests,
 * benchmarks): the working mesh made ready (normals derived from the geometry unless the model
 * has its own, wedges that differ only in derived normals merged, compact, adjacency, checked),
 * the views each method prices with, and the stated rule for large originals (QEM first). */
#ifndef LM_COORDINATOR_SIMPLIFY_WORK_H
#define LM_COORDINATOR_SIMPLIFY_WORK_H

#include <stdint.h>

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"
#include "coordinator/simplify/pricer.h"

typedef struct co_pool co_pool;

/* Image-driven collapses start from at most this many times the target's vertices; a larger
 * original is brought there by QEM first (Lindstrom & Turk pre-simplify geometrically too). */
#define CO_SIMPLIFY_PRESIMPLIFY_FACTOR 10u

/* The vertex count QEM brings a model of `live` vertices to before image-driven collapses to
 * `target` (presimplify: a count the user chose, 0 = the factor's; live when no QEM is needed). */
uint32_t co_simplify_start_verts(uint32_t live, uint32_t target, uint32_t presimplify);

/* Make m ready for co_isimp_run; *derived_normals tells how normals behave. */
lm_status co_simplify_prepare(lm_mesh *m, int *derived_normals);

/* Views for `method`: image — the targets are original's images and `work` is the current mesh
 * (in process on `device`, or through `pool`'s workers when pool is not NULL); shard — in-process
 * views with no target images at all (their targets are always a shard's own render). */
lm_status co_simplify_make_views(co_price_method method, const lm_mesh *original,
                                 const lm_mesh *work, const lm_view_set *vs, const char *device,
                                 co_pool *pool, lm_views **out);

/* Where the image views render, as the user asked: lumesh-worker processes started here, and
 * workers that connect to listen (tcp://HOST:PORT, with CURVE keys from the folder keys, the
 * renderer pinned to renderer when given). */
typedef struct co_simplify_workers {
    uint32_t local;       /* processes started here; 0 = none */
    const char *listen;   /* NULL = only local ones */
    const char *keys;     /* NULL = no keys (loopback and ipc only) */
    const char *renderer; /* NULL = the first worker's */
} co_simplify_workers;

/* Local workers a pool waits for at the start before it gives up. */
#define CO_SIMPLIFY_WORKER_START_S 60.0

/* The pool for w's workers (their --device: device), local ones started and waited for; *out is
 * NULL (and nothing started) when w asks for none, the views then render in this process. With
 * listen, the pool says on stderr who joins and leaves, and the first request waits (saying so)
 * until a worker has joined. */
lm_status co_simplify_pool_start(const co_simplify_workers *w, const char *device, co_pool **out);

/* A compact copy of m (textures kept), the form every output is written in. */
lm_status co_simplify_output_copy(const lm_mesh *m, lm_mesh **out);

#endif
