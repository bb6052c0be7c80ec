/* coordinator/simplify/edge_queue.h — the image simplifier's edges: one entry per undirected edge
 * (a < b) with its collapse cost (the least ΔE of its placements), the placement that gave it,
 * whether that cost is still exact (clean) or may be stale (dirty), the commit count it was priced
 * at, the vertices its priced changes touched and, per view, their footprint. A binary heap orders
 * the live entries by (cost, a, b) — a total order, so the pops depend only on the entries, never
 * on the history of the heap — and a hash finds an edge's entry. Entries are never moved: an index
 * stays valid until co_eq_destroy (a removed edge's entry is dead). */
#ifndef LM_COORDINATOR_SIMPLIFY_EDGE_QUEUE_H
#define LM_COORDINATOR_SIMPLIFY_EDGE_QUEUE_H

#include <stdint.h>

#include "common/error.h"
#include "coordinator/simplify/footprint.h"

enum { CO_EQ_CLEAN, CO_EQ_DIRTY, CO_EQ_DEAD };

typedef struct co_eq_entry {
    uint32_t a, b;      /* a < b */
    int64_t cost;       /* the heap key: the last price (INT64_MAX: no legal placement) */
    uint8_t place;      /* co_place_kind that gave cost */
    uint8_t state;      /* CO_EQ_CLEAN / DIRTY / DEAD */
    uint8_t priced;     /* priced at least once */
    uint32_t priced_at; /* commits done when it was priced */
    uint32_t *verts;    /* vertices of the triangles its changes removed (owned) */
    uint32_t n_verts, cap_verts;
} co_eq_entry;

typedef struct co_eq co_eq;

/* n_views: footprint rectangles kept per entry. */
lm_status co_eq_create(uint32_t n_views, co_eq **out);
void co_eq_destroy(co_eq *q);

/* Index of edge (a, b)'s live entry (either order), or UINT32_MAX. */
uint32_t co_eq_find(const co_eq *q, uint32_t a, uint32_t b);
/* A new dirty entry for an edge without one, in the heap with key `cost`; its index in *out. */
lm_status co_eq_insert(co_eq *q, uint32_t a, uint32_t b, int64_t cost, uint32_t *out);
/* The entry leaves the heap and the hash for good (state DEAD). */
void co_eq_remove(co_eq *q, uint32_t i);
/* Change the key of a live entry: re-ordered in the heap, or put back into it when detached. */
void co_eq_set_cost(co_eq *q, uint32_t i, int64_t cost);
/* Take a live entry out of the heap (it stays findable; co_eq_set_cost puts it back). */
void co_eq_detach(co_eq *q, uint32_t i);

co_eq_entry *co_eq_at(co_eq *q, uint32_t i);
/* The footprint of entry i (n_views rectangles). */
co_rect *co_eq_rects(co_eq *q, uint32_t i);
/* Entry i's touched vertices := verts[0..n). */
lm_status co_eq_set_verts(co_eq *q, uint32_t i, const uint32_t *verts, uint32_t n);

/* The lowest live entry, UINT32_MAX when none. */
uint32_t co_eq_top(const co_eq *q);
/* Entries in the heap, and all entries ever made (indices 0..co_eq_size-1, dead ones included). */
uint32_t co_eq_live(const co_eq *q);
uint32_t co_eq_size(const co_eq *q);

#endif
