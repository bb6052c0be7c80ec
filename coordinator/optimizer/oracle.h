/* coordinator/optimizer/oracle.h — choosing edges to optimise (paper §5.4). The oracle ranks edges
 * by their potential for improvement: the views' blurred difference images summed at the
 * projections of the edge's endpoints and midpoint (views->ops->potentials). Each iteration (64
 * edges) takes the highest-ranked edges (spread out: not sharing a vertex with one already taken,
 * while there are such) and interleaves them with uniformly random edges; the share of oracle edges
 * follows the progress per edge that each source made in the previous iteration. Edges tried
 * without progress are stale: the oracle skips them until a move changes their neighbourhood or
 * max_age iterations pass, so it does not propose the same hopeless set again and again. State is
 * plain values (checkpointable). */
#ifndef LM_COORDINATOR_ORACLE_H
#define LM_COORDINATOR_ORACLE_H

#include <stddef.h>
#include <stdint.h>

#include "common/mesh.h"
#include "common/views_api.h"
#include "coordinator/optimizer/rng.h"

typedef struct co_ranked_edge {
    uint32_t a, b;     /* a < b */
    int64_t potential; /* sum of the three point potentials */
} co_ranked_edge;

typedef struct co_planned_edge {
    uint32_t a, b;
    uint32_t from_oracle; /* 1: oracle, 0: random */
} co_planned_edge;

typedef struct co_stale_edge {
    uint64_t key;       /* a << 32 | b */
    uint64_t iteration; /* when it was last tried without progress */
} co_stale_edge;

typedef struct co_oracle {
    double share; /* fraction of an iteration's edges taken from the ranking */
    double min_share, max_share;
    uint32_t max_age;     /* iterations a stale edge stays skipped at most */
    co_stale_edge *stale; /* sorted by key: edges the oracle skips */
    uint32_t n_stale, cap_stale;
} co_oracle;

void co_oracle_init(co_oracle *o);
void co_oracle_free(co_oracle *o);

/* Potentials of all listed edges (a < b), sorted highest first (ties: by a, then b). The caller
 * owns *out (free()). */
lm_status co_oracle_rank(lm_views *views, const lm_mesh *m, const uint32_t (*edges)[2], size_t n,
                         co_ranked_edge **out);

/* Plan one iteration of `count` edges from the ranking (n_ranked > 0): round(share * count) best
 * edges not stale and vertex-disjoint (then the best remaining ones), the rest random distinct
 * edges of the ranking, interleaved evenly. out has
 * room for `count`; returns the number planned through *n_out. */
lm_status co_oracle_plan(const co_oracle *o, const co_ranked_edge *ranked, size_t n_ranked,
                         co_rng *rng, uint32_t count, co_planned_edge *out, uint32_t *n_out);

/* After an iteration: gains (energy reductions, >= 0) and edge counts per source move the share. */
void co_oracle_balance(co_oracle *o, double gain_oracle, uint32_t n_oracle, double gain_random,
                       uint32_t n_random);

/* Edges tried without progress in `iteration` become stale; stale edges with an endpoint for which
 * touched(ctx, v) != 0, or last tried more than max_age iterations ago, are forgotten. */
lm_status co_oracle_update_stale(co_oracle *o, uint64_t iteration, const uint64_t *no_progress,
                                 uint32_t n, int (*touched)(const void *ctx, uint32_t v),
                                 const void *ctx);
/* Replace the stale set (checkpoint loading); entries are sorted here. */
lm_status co_oracle_set_stale(co_oracle *o, const co_stale_edge *e, uint32_t n);

static inline uint64_t co_edge_key(uint32_t a, uint32_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

#endif
