/* common/mesh_internal.h — private state of lm_mesh shared by common/mesh.c and
 * common/mesh_topology.c: per-vertex incident-triangle lists (adjacency). Not for other folders. */
#ifndef LM_COMMON_MESH_INTERNAL_H
#define LM_COMMON_MESH_INTERNAL_H

#include "common/mesh.h"

typedef struct lm_u32vec {
    uint32_t *data;
    uint32_t n, cap;
} lm_u32vec;

lm_status lm_u32vec_push(lm_u32vec *v, uint32_t x);
/* Remove the first occurrence of x, keeping order (deterministic). Returns 1 if found. */
int lm_u32vec_remove(lm_u32vec *v, uint32_t x);
void lm_u32vec_free(lm_u32vec *v);

struct lm_mesh_internal {
    int adjacency_built;
    uint32_t cap_vtris;
    lm_u32vec *vtris; /* [cap_vtris] alive triangles incident to each vertex, ascending ids */
};

/* Ensure m->internal exists. */
lm_status lm_mesh_internal_ensure(lm_mesh *m);
/* Make room for adjacency lists of n_verts vertices (new lists empty). Lists of vertices beyond
 * cap_vtris are implicitly empty: always check v < cap_vtris before reading vtris[v]. */
lm_status lm_mesh_adj_reserve(lm_mesh *m, uint32_t n_verts);
/* Adjacency maintenance used by mesh.c and mesh_topology.c (no-ops when adjacency is not built). */
lm_status lm_mesh_adj_link_tri(lm_mesh *m, uint32_t t);
void lm_mesh_adj_unlink_tri(lm_mesh *m, uint32_t t);

#endif
