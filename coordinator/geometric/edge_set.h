/* coordinator/geometric/edge_set.h — sets of edges (a < b) for the outer loop: the candidate set
 * (random removal drawn from the seed) and the memo of each edge's last collapse ΔE (Özdal &
 * Güdükbay 3.2), both over one open-addressing map from the edge's 64-bit key. */
#ifndef LM_COORDINATOR_GEOMETRIC_EDGE_SET_H
#define LM_COORDINATOR_GEOMETRIC_EDGE_SET_H

#include <stdint.h>

#include "common/error.h"
#include "common/optimizer/rng.h"

typedef struct co_geo_map {
    uint64_t *key; /* 0: empty (no edge has key 0: a < b) */
    uint32_t *val;
    uint32_t cap, n; /* cap a power of two */
} co_geo_map;

static inline uint64_t co_geo_edge_key(uint32_t a, uint32_t b)
{
    return a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
}

void co_geo_map_free(co_geo_map *m);
/* Value of key or UINT32_MAX. */
uint32_t co_geo_map_get(const co_geo_map *m, uint64_t key);
lm_status co_geo_map_put(co_geo_map *m, uint64_t key, uint32_t val);
void co_geo_map_del(co_geo_map *m, uint64_t key);

typedef struct co_geo_edge_set {
    uint64_t *item;
    uint32_t n, cap;
    co_geo_map where; /* key -> index in item */
} co_geo_edge_set;

void co_geo_set_free(co_geo_edge_set *s);
void co_geo_set_clear(co_geo_edge_set *s);
/* Adds the edge unless present. */
lm_status co_geo_set_add(co_geo_edge_set *s, uint64_t key);
/* Removes and returns a uniformly drawn edge (the set must not be empty). */
uint64_t co_geo_set_take(co_geo_edge_set *s, lm_rng *r);

#endif
