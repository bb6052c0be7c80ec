/* common/bvh_internal.h — the hierarchy's layout, shared by its queries (common/bvh.c: build and
 * closest points; common/bvh_ray.c: lines). Not for other callers: use common/bvh.h. */
#ifndef LM_COMMON_BVH_INTERNAL_H
#define LM_COMMON_BVH_INTERNAL_H

#include <stdint.h>

typedef struct bvh_node {
    float lo[3], hi[3];
    uint32_t first; /* leaf: triangles [first, first + count); inner: the right child (the left
                       one is the next node) */
    uint32_t count; /* 0: inner */
} bvh_node;

struct lm_bvh {
    float (*tri)[3][3]; /* [n] corner positions (the mesh's floats), in leaf order */
    uint32_t *id;       /* [n] the mesh's triangle id of each slot */
    uint32_t n, n_nodes;
    bvh_node *nodes; /* [2n] at most */
};

#define LM_BVH_STACK 128 /* median splits: depth ~log2(n) + 1 */

#endif
