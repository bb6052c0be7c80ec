/* common/optimizer/oracle.h — choosing edges to optimise (paper §5.4). The oracle ranks edges
 * by their potential for improvement: the views' blurred difference images summed at the
 * projections of the edge's endpoints and midpoint (views->ops->potentials). Each iteration (64
 * edges) takes the highest-ranked edges (spread out: not sharing a vertex with one already taken,
 * while there are such) and interleaves them with uniformly random edges; the share of oracle edges
 * follows the progress per edge that each source made in the previous iteration. Edges tried
 * without progress are stale: the oracle skips them until a move changes their neighbourhood or
 * max_age iterations pass, so it does not propose the same hopeless set again and again. State is
 * plain values (checkpointable). */
#ifndef LM_COMMON_OPTIMIZER_ORACLE_H
#define LM_COMMON_OPTIMIZER_ORACLE_H

#include <stddef.h>
#include <stdint.h>

#include "common/mesh.h"
#include "common/optimizer/rng.h"
#include "common/views_api.h"

typedef struct lm_ranked_edge {
    uint32_t a, b;     /* a < b */
    int64_t potential; /* sum of the three point potentials */
} lm_ranked_edge;

typedef struct lm_planned_edge {
    uint32_t a, b;
    uint32_t from_oracle; /* 1: oracle, 0: random */
} lm_planned_edge;

typedef struct lm_stale_edge {
    uint64_t key;       /* a << 32 | b */
    uint64_t iteration; /* when it was last tried without progress */
} lm_stale_edge;

typedef struct lm_oracle {
    double share; /* fraction of an iteration's edges taken from the ranking */
    double min_share, max_share;
    uint32_t max_age;     /* iterations a stale edge stays skipped at most */
    lm_stale_edge *stale; /* sorted by key: edges the oracle skips */
    uint32_t n_stale, cap_stale;
} lm_oracle;

void lm_oracle_init(lm_oracle *o);
void lm_oracle_free(lm_oracle *o);

/* Potentials of all listed edges (a < b), sorted highest first (ties: by a, then b). The caller
 * owns *out (free()). */
lm_status lm_oracle_rank(lm_views *views, const lm_mesh *m, const uint32_t (*edges)[2], size_t n,
                         lm_ranked_edge **out);

/* Plan one iteration of `count` edges from the ranking (n_ranked > 0): round(share * count) best
 * edges not stale and vertex-disjoint (then the best remaining ones), the rest random distinct
 * edges of the ranking, interleaved evenly. out has
 * room for `count`; returns the number planned through *n_out. */
lm_status lm_oracle_plan(const lm_oracle *o, const lm_ranked_edge *ranked, size_t n_ranked,
                         lm_rng *rng, uint32_t count, lm_planned_edge *out, uint32_t *n_out);

/* After an iteration: gains (energy reductions, >= 0) and edge counts per source move the share. */
void lm_oracle_balance(lm_oracle *o, double gain_oracle, uint32_t n_oracle, double gain_random,
                       uint32_t n_random);

/* Edges tried without progress in `iteration` become stale; stale edges with an endpoint for which
 * touched(ctx, v) != 0, or last tried more than max_age iterations ago, are forgotten. */
lm_status lm_oracle_update_stale(lm_oracle *o, uint64_t iteration, const uint64_t *no_progress,
                                 uint32_t n, int (*touched)(const void *ctx, uint32_t v),
                                 const void *ctx);
/* Replace the stale set (checkpoint loading); entries are sorted here. */
lm_status lm_oracle_set_stale(lm_oracle *o, const lm_stale_edge *e, uint32_t n);

static inline uint64_t lm_edge_key(uint32_t a, uint32_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

#endif
