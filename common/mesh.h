/* common/mesh.h — the indexed triangle mesh every part of lumesh works on.
 *
 * Layout (public, like meshoptimizer's: plain arrays callers may read):
 *   vertices  — positions; a vertex is the topological entity (v in the paper).
 *   wedges    — attribute sets (normal, uv, colour) bound to a vertex; corners of triangles around
 * a vertex that share attributes share a wedge; a vertex with >1 wedge lies on an attribute seam
 * (Hoppe's wedges). Per-corner attributes = tri.w[k] -> wedge. triangles — three wedge ids
 * (counter-clockwise), a material id. Ids are stable while the element is alive: deleting marks it
 * dead (alive = 0) and never moves other elements, so the renderer's buckets can index triangles by
 * id. Dead slots may be reused by later insertions (deterministically, LIFO free list).
 * lm_mesh_compact() renumbers for output. Parts — the named pieces of a model (a node or group of
 * the file, a leg of the frog) that asset pipelines address by name — are a table of names; each
 * triangle names its part as it names its material, and every output format keeps them.
 *
 * Topology (adjacency, legal edge operations with undo) is in common/mesh_topology.h.
 * Ownership: lm_mesh_create/destroy; the mesh owns all arrays and materials' textures. */
#ifndef LM_COMMON_MESH_H
#define LM_COMMON_MESH_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/image.h"

#define LM_MESH_MAX_VERTS (1u << 28)
#define LM_MESH_MAX_TRIS (1u << 28)
#define LM_NONE UINT32_MAX

/* Which attributes a mesh carries (bit set). Positions are always present. */
enum {
    LM_ATTR_NORMAL = 1u << 0,
    LM_ATTR_UV = 1u << 1,
    LM_ATTR_COLOR = 1u << 2,
};

typedef struct lm_wedge {
    uint32_t vertex; /* owning vertex id */
    float normal[3]; /* not forced to unit length (the optimizer may scale it) */
    float uv[2];
    float color[4]; /* linear RGBA in [0,1]; (1,1,1,1) when the model has none */
} lm_wedge;

typedef struct lm_tri {
    uint32_t w[3];     /* wedge ids, counter-clockwise seen from the front */
    uint32_t material; /* index into mesh->materials */
    uint32_t part;     /* index into mesh->parts (0 when the mesh has none) */
} lm_tri;

#define LM_PART_NAME_MAX 128

/* A named part of the model. Names are unique within a mesh; "" is the unnamed part. */
typedef struct lm_part {
    char name[LM_PART_NAME_MAX];
} lm_part;

typedef struct lm_material {
    char name[64];
    float diffuse[4];   /* multiplies texture and vertex colour */
    char *texture_path; /* as referenced by the model (may be NULL); owned */
    lm_image *texture;  /* decoded diffuse texture or NULL; owned */
    /* Tangent-space normal map (glTF normalTexture, scale 1: RGB -> [-1,1], +Y along increasing
     * v; tangents from common/tangents.h) or NULL, and its path as referenced (may be NULL);
     * owned. Set with lm_mesh_set_normal_map. */
    char *normal_path;
    lm_image *normal_map;
} lm_material;

typedef struct lm_mesh {
    uint32_t n_verts; /* slots in use (alive or dead) */
    uint32_t n_wedges;
    uint32_t n_tris;
    uint32_t cap_verts, cap_wedges, cap_tris;
    float (*pos)[3];                /* [n_verts] */
    uint8_t *vert_alive;            /* [n_verts] */
    lm_wedge *wedges;               /* [n_wedges] */
    uint8_t *wedge_alive;           /* [n_wedges] */
    lm_tri *tris;                   /* [n_tris] */
    uint8_t *tri_alive;             /* [n_tris] */
    uint32_t live_verts, live_tris; /* counts of alive elements */
    uint32_t n_materials;
    lm_material *materials; /* [n_materials]; at least one after loading */
    uint32_t n_parts;
    lm_part *parts;                    /* [n_parts]; 0 parts = one unnamed part */
    uint32_t attrs;                    /* LM_ATTR_* the model really has (others hold defaults) */
    struct lm_mesh_internal *internal; /* adjacency and free lists; owned, may be NULL */
} lm_mesh;

lm_status lm_mesh_create(lm_mesh **out);
void lm_mesh_destroy(lm_mesh *m);
/* Deep copy (textures shared by reference count is not done: textures are cloned). */
lm_status lm_mesh_clone(const lm_mesh *src, lm_mesh **out);

/* dst becomes a copy of src's geometry, attributes and adjacency, with its materials' names and
 * colours but no textures (a working copy for topology and attribute changes; dst's memory is
 * reused). Afterwards the same operations give the same ids and results on both. */
lm_status lm_mesh_copy_geometry(lm_mesh *dst, const lm_mesh *src);

/* Building. Ids returned through out (may be NULL). */
lm_status lm_mesh_add_vertex(lm_mesh *m, const float p[3], uint32_t *out_id);
lm_status lm_mesh_add_wedge(lm_mesh *m, const lm_wedge *w, uint32_t *out_id);
lm_status lm_mesh_add_tri(lm_mesh *m, const uint32_t w[3], uint32_t material, uint32_t *out_id);
/* Adds a material; takes ownership of tex (may be NULL) and copies name/path. */
lm_status lm_mesh_add_material(lm_mesh *m, const char *name, const float diffuse[4],
                               const char *texture_path, lm_image *tex, uint32_t *out_id);

/* Appends deep copies of src's materials (textures and normal maps cloned) to dst's. */
lm_status lm_mesh_copy_materials(const lm_mesh *src, lm_mesh *dst);

/* Gives material mat the normal map img (ownership taken, also on failure; may be NULL) and a
 * copy of path (may be NULL), replacing any it had. */
lm_status lm_mesh_set_normal_map(lm_mesh *m, uint32_t mat, const char *path, lm_image *img);

/* Adds a part named `name` (cut to LM_PART_NAME_MAX - 1 bytes; NULL = ""), its id in *out_id.
 * Names must be unique: callers look first (lm_mesh_find_part). Triangles are put in a part by
 * setting tris[t].part. */
lm_status lm_mesh_add_part(lm_mesh *m, const char *name, uint32_t *out_id);
/* Id of the part named `name` (cut as above), or LM_NONE. Linear in the number of parts. */
uint32_t lm_mesh_find_part(const lm_mesh *m, const char *name);
/* Copies every part of src into dst (dst has none yet), ids unchanged. */
lm_status lm_mesh_copy_parts(const lm_mesh *src, lm_mesh *dst);
/* Parts that hold at least one live triangle (1 for a mesh with triangles and no part table). */
uint32_t lm_mesh_count_parts(const lm_mesh *m);
/* Name of triangle t's part ("" when unnamed or the mesh has no parts). */
const char *lm_mesh_part_name(const lm_mesh *m, uint32_t t);

/* Vertex of corner k of triangle t. */
static inline uint32_t lm_tri_vertex(const lm_mesh *m, uint32_t t, int k)
{
    return m->wedges[m->tris[t].w[k]].vertex;
}

/* Checks ranges, finite coordinates, alive references, non-degenerate index triples.
 * Returns LM_E_RANGE/LM_E_FORMAT with a message naming the first problem. */
lm_status lm_mesh_validate(const lm_mesh *m);

/* Removes dead elements and renumbers (ids change!). Keeps relative order. */
lm_status lm_mesh_compact(lm_mesh *m);

/* Axis-aligned bounds and bounding sphere (centre of bounds, max distance) over alive vertices. */
void lm_mesh_bounds(const lm_mesh *m, float lo[3], float hi[3]);
void lm_mesh_bounding_sphere(const lm_mesh *m, float centre[3], float *radius);

/* Area-weighted smooth normals per vertex written into every wedge of that vertex
 * (used when the model has none and when normals are derived from geometry). */
void lm_mesh_compute_normals(lm_mesh *m);
/* Triangle t's normal scaled by twice its area, in double from the float positions: the one
 * definition lm_mesh_compute_normals and the optimizer's normal moves share (their results must
 * agree to the bit). */
void lm_mesh_face_normal(const lm_mesh *m, uint32_t t, double n[3]);

/* Number of connected components (through shared vertices) over alive triangles. */
uint32_t lm_mesh_count_components(const lm_mesh *m);

/* 64-bit hash of the live mesh content (positions, wedges, tris in id order, each record mixed in
 * 8 bytes at a time); for tests and the lanes' checks that two processes hold the same mesh. */
uint64_t lm_mesh_hash(const lm_mesh *m);

#endif
