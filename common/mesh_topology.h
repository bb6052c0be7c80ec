/* common/mesh_topology.h — adjacency and the legal edge operations of Hoppe et al. 1993
 * (edge collapse with the link condition and boundary rules, edge split, edge swap), all undoable.
 *
 * Adjacency is kept inside the mesh (vertex -> incident triangles) and updated by every operation
 * here. It tolerates boundaries and non-manifold edges (edges with > 2 triangles); operations on
 * non-manifold edges are refused with LM_E_ILLEGAL.
 *
 * Undo: every mutating call takes an lm_journal (may be NULL = not undoable). A journal records
 * inverse steps; lm_journal_mark() returns a position and lm_journal_rollback() restores the mesh
 * exactly (ids, attributes, adjacency, free lists) to that position. */
#ifndef LM_COMMON_MESH_TOPOLOGY_H
#define LM_COMMON_MESH_TOPOLOGY_H

#include "common/mesh.h"

typedef struct lm_journal lm_journal;

lm_status lm_journal_create(lm_journal **out);
void lm_journal_destroy(lm_journal *j);
size_t lm_journal_mark(const lm_journal *j);
/* Undo every step recorded after `mark`, newest first. */
void lm_journal_rollback(lm_mesh *m, lm_journal *j, size_t mark);
/* Forget all steps (the changes are kept). */
void lm_journal_clear(lm_journal *j);

/* What the steps recorded after `mark` touched, oldest first (an id may come several times):
 * a vertex (position changed, added or killed), a wedge (attributes changed, added or killed), a
 * triangle (wedges or material changed), a triangle killed, a triangle added. */
enum {
    LM_TOUCH_VERTEX,
    LM_TOUCH_WEDGE,
    LM_TOUCH_TRI,
    LM_TOUCH_TRI_KILLED,
    LM_TOUCH_TRI_ADDED,
};
typedef void (*lm_journal_visit_fn)(void *ctx, int what, uint32_t id);
void lm_journal_scan(const lm_journal *j, size_t mark, lm_journal_visit_fn fn, void *ctx);

/* Build (or rebuild) adjacency. Called by loaders; operations keep it current afterwards. */
lm_status lm_mesh_build_adjacency(lm_mesh *m);

/* Triangles incident to vertex v (alive), in no particular but deterministic order.
 * Returns the count; writes at most cap ids into out. */
uint32_t lm_mesh_vertex_tris(const lm_mesh *m, uint32_t v, uint32_t *out, uint32_t cap);
/* Distinct neighbour vertices of v, sorted ascending. Returns the count (writes at most cap). */
uint32_t lm_mesh_vertex_neighbors(const lm_mesh *m, uint32_t v, uint32_t *out, uint32_t cap);
/* Triangles containing both a and b. Returns the count (writes at most cap). */
uint32_t lm_mesh_edge_tris(const lm_mesh *m, uint32_t a, uint32_t b, uint32_t *out, uint32_t cap);

/* Edge classification. */
int lm_mesh_edge_exists(const lm_mesh *m, uint32_t a, uint32_t b);
int lm_mesh_edge_is_boundary(const lm_mesh *m, uint32_t a, uint32_t b);  /* exactly 1 tri */
int lm_mesh_edge_is_manifold(const lm_mesh *m, uint32_t a, uint32_t b);  /* 1 or 2 tris */
int lm_mesh_edge_is_attr_seam(const lm_mesh *m, uint32_t a, uint32_t b); /* wedges differ across */
int lm_mesh_vertex_is_boundary(const lm_mesh *m, uint32_t v);

/* Undirected edges (a < b) of alive triangles, sorted by (a, b). Caller frees *out with free(). */
lm_status lm_mesh_list_edges(const lm_mesh *m, uint32_t (**out)[2], size_t *count);

/* Set position / wedge attributes (journaled). */
void lm_mesh_set_pos(lm_mesh *m, uint32_t v, const float p[3], lm_journal *j);
void lm_mesh_set_wedge(lm_mesh *m, uint32_t w, const lm_wedge *value, lm_journal *j);

/* Edge collapse (a, b) -> a survives at position `p` (b and its wedges merged into a's; the one or
 * two triangles on the edge die). Refused (LM_E_ILLEGAL, mesh untouched) when: the edge is absent
 * or non-manifold; the link condition fails (link(a) ∩ link(b) != link(ab)); both a and b are on a
 * boundary but ab is not a boundary edge; the collapse would leave a tetrahedron-like degenerate
 * (fewer than 4 vertices in the component) or a duplicate triangle. Merged wedges across the
 * collapsed edge take the mean of the two attribute sets. */
lm_status lm_mesh_collapse_edge(lm_mesh *m, uint32_t a, uint32_t b, const float p[3],
                                lm_journal *j);

/* Edge split at the midpoint: new vertex (attributes interpolated per side), each incident triangle
 * split in two. Refused on non-manifold edges. New vertex id through out_v (may be NULL). */
lm_status lm_mesh_split_edge(lm_mesh *m, uint32_t a, uint32_t b, uint32_t *out_v, lm_journal *j);

/* Edge swap: edge ab shared by triangles (a,b,c) and (b,a,d) becomes cd. Refused when ab is a
 * boundary or non-manifold edge, an attribute seam, when cd already exists, or when the two
 * triangles use different materials. The two triangle ids are kept (reused for the new ones). */
lm_status lm_mesh_swap_edge(lm_mesh *m, uint32_t a, uint32_t b, lm_journal *j);

/* Merge wedges of the same vertex whose attributes selected by `compare_attrs` (LM_ATTR_* bits)
 * are equal (bitwise), e.g. LM_ATTR_UV|LM_ATTR_COLOR when normals are derived from geometry and so
 * must not create seams. Not journaled (a set-up step). Returns the number of wedges merged. */
uint32_t lm_mesh_merge_wedges(lm_mesh *m, uint32_t compare_attrs);

/* Euler characteristic V - E + F over alive elements (for tests). */
long lm_mesh_euler_characteristic(const lm_mesh *m);

#endif
