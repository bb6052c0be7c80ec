/* coordinator/simplify/placement.h — where an edge collapse puts the vertex it keeps, the
 * candidates Lindstrom & Turk and Hoppe try: either endpoint (a half-edge collapse: the kept
 * vertex and its attributes stay as they are), the midpoint, and the point that minimises the
 * memoryless quadric of the edge's neighbourhood (Garland–Heckbert planes of the triangles around
 * both endpoints, area weighted, with perpendicular planes holding open borders). The attributes
 * of the wedges merged across the edge are blended towards the removed vertex's by t: 0 at the
 * kept endpoint, 1/2 at the midpoint, the projection onto the edge for the quadric's point. */
#ifndef LM_COORDINATOR_SIMPLIFY_PLACEMENT_H
#define LM_COORDINATOR_SIMPLIFY_PLACEMENT_H

#include <stdint.h>

#include "common/mesh.h"

typedef enum co_place_kind {
    CO_PLACE_KEEP_A, /* collapse onto a: a stays where it is */
    CO_PLACE_KEEP_B, /* collapse onto b */
    CO_PLACE_MID,    /* a kept, at the midpoint */
    CO_PLACE_QEM,    /* a kept, at the quadric's minimum */
    CO_PLACE_KINDS
} co_place_kind;

typedef struct co_place {
    co_place_kind kind;
    int valid;           /* 0: nothing to try (the quadric's point is no new place) */
    uint32_t keep, drop; /* the surviving and the removed vertex */
    float pos[3];        /* where keep goes */
    float t;             /* merged attributes: (1 - t) keep's + t drop's */
} co_place;

/* The candidates of edge (a, b), indexed by co_place_kind. */
void co_place_all(const lm_mesh *m, uint32_t a, uint32_t b, co_place out[CO_PLACE_KINDS]);

/* Short names for reports ("keep_a", "keep_b", "mid", "qem"). */
const char *co_place_name(co_place_kind k);

#endif
