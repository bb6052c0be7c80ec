/* common/bvh_internal.h — the hierarchy's layout, shared by its queries (common/bvh.c: build and
 * closest points; common/bvh_ray.c: lines). Not for other callers: use common/bvh.h.
 *
 * An inner node holds its two children's boxes (one 64-byte cache line), so a query tests both
 * children from the line it already has and loads a child's line only when it descends into it.
 * Inner nodes are in depth-first order, a left child right after its parent. */
#ifndef LM_COMMON_BVH_INTERNAL_H
#define LM_COMMON_BVH_INTERNAL_H

#include <stdint.h>

typedef struct bvh_box {
    float lo[3], hi[3];
} bvh_box;

/* A subtree: count > 0: a leaf, triangles [first, first + count); count 0: inner node `first`. */
typedef struct bvh_ref {
    uint32_t first, count;
} bvh_ref;

typedef struct bvh_node {
    float lo[3][2], hi[3][2]; /* [axis][child]: the left (0) and right (1) child's boxes, each
                                 axis's pair side by side for a two-wide box test */
    bvh_ref child[2];
} bvh_node;
_Static_assert(sizeof(bvh_node) == 64, "an inner node is one cache line");

/* Child c's box. */
static inline bvh_box bvh_child_box(const bvh_node *nd, int c)
{
    bvh_box bx;
    for (int k = 0; k < 3; k++)
        bx.lo[k] = nd->lo[k][c], bx.hi[k] = nd->hi[k][c];
    return bx;
}

struct lm_bvh {
    float (*tri)[3][3]; /* [n] corner positions (the mesh's floats), in leaf order */
    uint32_t *id;       /* [n] the mesh's triangle id of each slot */
    uint32_t n, n_nodes;
    bvh_box root_box;
    bvh_ref root;
    bvh_node *nodes; /* [n_nodes] inner nodes, 64-byte aligned */
};

#define LM_BVH_STACK 128 /* median splits: depth ~log2(n) + 1 */

#endif
