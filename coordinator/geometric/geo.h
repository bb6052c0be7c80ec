/* coordinator/geometric/geo.h — Hoppe et al. 1993 mesh optimization (`optimize --energy
 * geometric`): E(K, V) = E_dist + E_rep + E_spring over points sampled from the original, vertex
 * positions by sparse linear least squares (CHOLMOD) for fixed connectivity, connectivity by legal
 * edge collapses, swaps and splits kept when they lower E, the spring constant lowered in steps;
 * with Özdal & Güdükbay's three improvements, each switchable. See GEOMETRIC.md. */
#ifndef LM_COORDINATOR_GEOMETRIC_GEO_H
#define LM_COORDINATOR_GEOMETRIC_GEO_H

#include <stdint.h>

#include "common/mesh.h"

/* Özdal & Güdükbay's improvements (bit set). */
enum {
    CO_GEO_COLLAPSE_ONLY = 1u << 0, /* 3.1: edge collapses only (no swaps, no splits) */
    CO_GEO_STORED = 1u << 1,        /* 3.2: later candidate sets from the stored ΔE of each edge */
    CO_GEO_DEFERRED = 1u << 2, /* 3.3: edges near an accepted collapse wait for the next pass */
    CO_GEO_ALL = 7u,
};

#define CO_GEO_DEFAULT_C_REP 1e-5 /* Hoppe's c_rep, in the units of GEOMETRIC.md */
#define CO_GEO_START_MULTIPLE 2   /* originals above this many times N start from QEM at it */
#define CO_GEO_POINTS_PER_VERT 20 /* points sampled per vertex of the target */
#define CO_GEO_MIN_POINTS 20000

typedef struct co_geo_state co_geo_state;

typedef struct co_geo_options {
    uint32_t target_verts; /* 0: none (c_rep alone decides) */
    double c_rep;          /* > 0 */
    uint32_t improvements; /* CO_GEO_* */
    uint64_t seed;
    uint32_t points; /* 0: CO_GEO_POINTS_PER_VERT per target vertex, at least CO_GEO_MIN_POINTS */
    /* Called with each phase's progress (may be NULL): what, done, total. */
    void (*on_progress)(void *ctx, const char *phase, uint64_t done, uint64_t total);
    /* Called after every accepted move with the energy tracked (tests; may be NULL). */
    void (*on_accept)(void *ctx, const co_geo_state *g);
    void *ctx;
} co_geo_options;

typedef struct co_geo_summary {
    uint32_t start_verts, verts;
    uint32_t points;
    double e_start, e_dist, e_spring, e_rep, e_total; /* at the end (spring with the last κ,
                                                         E_rep with the user's c_rep) */
    double c_rep_final;                               /* c_rep after the ramp to the target */
    uint64_t tried, accepted;                         /* moves */
    uint64_t collapses, swaps, splits;
    double seconds;
} co_geo_summary;

/* Optimize `start` (taken over: its connectivity and positions change) against points sampled
 * from `original`. `start` must have adjacency. */
lm_status co_geo_optimize(const lm_mesh *original, lm_mesh *start, const co_geo_options *o,
                          co_geo_summary *sum);

/* The start for `original` at target N: the original itself (a copy, Hoppe's start) up to
 * multiple * N vertices, else QEM at that many (multiple >= 1; 0 = CO_GEO_START_MULTIPLE). */
lm_status co_geo_make_start(const lm_mesh *original, uint32_t target_verts, uint32_t multiple,
                            lm_mesh **out);

/* The energy from scratch of g's current mesh with g's current projections (tests). */
double co_geo_energy_now(const co_geo_state *g);
/* The energy tracked incrementally. */
double co_geo_energy_tracked(const co_geo_state *g);
/* The mesh being optimized. */
const lm_mesh *co_geo_mesh(const co_geo_state *g);

/* "all", "none" or a comma list of collapse-only,stored,deferred into *bits. */
lm_status co_geo_parse_improvements(const char *list, uint32_t *bits);

#endif
