/* common/io/mesh_io_internal.h — private interfaces between the mesh_io_*.c files: the pre-checks
 * of hostile bytes, the file system handed to assimp, the aiScene -> lm_mesh conversion, material
 * and texture import, and the writers. Not for other folders. */
#ifndef LM_COMMON_MESH_IO_INTERNAL_H
#define LM_COMMON_MESH_IO_INTERNAL_H

#include <stdio.h>

#include "common/io/atomic_file.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"

/* Largest model file (and file it refers to) we read into memory. */
#define LM_IO_MAX_FILE_BYTES ((size_t)2 << 30)
/* Deepest node hierarchy we follow. */
#define LM_IO_MAX_NODE_DEPTH 256

struct aiScene;
struct aiFileIO;

/* ---- mesh_io_guard.c: checks done on the raw bytes before assimp sees them ------------------- */

/* 1 when `ext` (lower case, no dot) names a model format lm_mesh_load accepts. */
int lm_io_known_ext(const char *ext);
/* Lower-case extension of `path` (after the last dot of the last component) into buf. */
void lm_io_path_ext(const char *path, char *buf, size_t cap);
/* Refuse inputs assimp would mis-handle: absurd element counts (vs file size and max_tris),
 * out-of-range OFF indices (assimp clamps them silently), over-long OFF lines, bad GLB headers.
 * `name` is used in messages. */
lm_status lm_io_guard(const uint8_t *data, size_t size, const char *ext, const char *name,
                      uint32_t max_tris);
lm_status lm_io_guard_off(const uint8_t *data, size_t size, const char *name, uint32_t max_tris);
lm_status lm_io_guard_stl(const uint8_t *data, size_t size, const char *name, uint32_t max_tris);
lm_status lm_io_guard_dae(const uint8_t *data, size_t size, const char *name);
/* The JSON of a .gltf file or of a .glb's first chunk. */
lm_status lm_io_guard_gltf_json(const uint8_t *json, size_t size, const char *name);
/* LM_E_UNSUPPORTED: "NAME: WHAT glTF 1.0 file (...); lumesh reads glTF 2.0: convert it ...". */
lm_status lm_io_gltf1_refusal(const char *name, const char *what);

/* ---- mesh_io_ply_header.c, mesh_io_ply_read.c: lumesh's own PLY reader --------------------- */

/* A whole PLY file (ASCII, binary little or big endian) as a new scene in assimp's C layout: one
 * mesh of triangles (polygons split, strips unrolled), one root node, one material (its diffuse
 * texture the file's "comment TextureFile", if any). Not an assimp scene: release it with
 * lm_io_ply_scene_destroy, never aiReleaseImport, and apply no assimp post-processing to it.
 * Counts are checked against max_tris, LM_MESH_MAX_VERTS and the bytes present before anything is
 * allocated for them. Errors: LM_E_FORMAT (malformed, truncated), LM_E_RANGE (over a limit, a
 * vertex index out of range), LM_E_NOMEM; one line naming `name`; *out is then NULL. */
lm_status lm_io_ply_read(const uint8_t *data, size_t size, const char *name, uint32_t max_tris,
                         struct aiScene **out);
void lm_io_ply_scene_destroy(struct aiScene *sc);

/* ---- mesh_io_load.c, mesh_io_isolate.c: where a model is read ------------------------------ */

/* Import, convert, validate bytes that passed lm_io_guard, in this process (data[size] is a NUL:
 * assimp's text readers need it); `name` gives the format and the messages, `dir` is the folder
 * of the files the model refers to (NULL for memory loads: then none is opened). */
lm_status lm_io_load_bytes_here(const uint8_t *data, size_t size, const char *name, const char *dir,
                                const lm_load_options *opts, lm_mesh **out);
/* 1 for the formats read in a process of their own (their assimp readers are not proven safe:
 * glTF, GLB, FBX, COLLADA). */
int lm_io_isolated_format(const char *ext);
/* lm_io_load_bytes_here in a reader process (this program afresh) that writes the mesh as GLB to a
 * private temporary folder; that GLB is read back here with opts. Blocks until the reader is done.
 * A crash, abort or CPU limit in the reader is an LM_E_FORMAT error naming `name`; the reader's
 * own errors come back with their status and message. */
lm_status lm_io_load_isolated(const uint8_t *data, size_t size, const char *name, const char *dir,
                              const lm_load_options *opts, lm_mesh **out);

/* ---- mesh_io_aifs.c: the only file system assimp gets -------------------------------------- */

/* Serves `main_name` from memory; with allow_disk, other names are read from regular files only
 * (no devices, FIFOs or directories) up to LM_IO_MAX_FILE_BYTES; without it they do not exist. */
typedef struct lm_aifs lm_aifs;
lm_status lm_aifs_create(const char *main_name, const void *data, size_t size, int allow_disk,
                         lm_aifs **out);
struct aiFileIO *lm_aifs_io(lm_aifs *fs);
void lm_aifs_destroy(lm_aifs *fs);

/* Read a whole regular file (at most LM_IO_MAX_FILE_BYTES) into a malloc'ed buffer with one
 * extra NUL byte after the data. */
lm_status lm_io_read_file(const char *path, uint8_t **out, size_t *size);

/* ---- mesh_io_scene.c / mesh_io_material.c: aiScene -> lm_mesh ------------------------------ */

/* A run of faces of a single-mesh file (a PLY written by lumesh) that form one named part. */
typedef struct lm_face_part {
    uint64_t first, count;
    char name[LM_PART_NAME_MAX];
} lm_face_part;

typedef struct lm_scene_source {
    const char *name; /* for messages */
    const char *dir;  /* folder for relative texture paths; NULL = do not open files */
    uint32_t max_tris;
    int keep_degenerate;
    const lm_face_part *face_parts; /* parts by face index of the scene's only mesh, or NULL */
    uint32_t n_face_parts;
} lm_scene_source;

/* Refuse scenes assimp's post-processing would crash on (run before it): faces without
 * indices, polygon flags without polygons, non-finite vertex data. */
lm_status lm_io_check_scene(const struct aiScene *sc, const char *name);
/* Convert the whole scene (node transforms applied) into a new mesh: not yet validated. Each node
 * holding triangles is a part, named by the node (or, where the node's name is one assimp made
 * up, by its mesh); nodes of one name make one part. */
lm_status lm_mesh_from_scene(const struct aiScene *sc, const lm_scene_source *src, lm_mesh **out);
/* Add scene material `index` to m (diffuse colour, decoded diffuse texture). */
lm_status lm_io_add_material(lm_mesh *m, const struct aiScene *sc, unsigned index,
                             const lm_scene_source *src, uint32_t *out_id);

/* ---- mesh_io_save.c and the writers -----------------------------------------------------------
 */

/* Output numbering of a mesh with dead elements skipped. */
typedef struct lm_out_map {
    uint32_t *vert;  /* [n_verts] output index of each alive vertex (LM_NONE if dead) */
    uint32_t *wedge; /* [n_wedges] output index of each alive wedge used by an alive tri */
    uint32_t n_verts, n_wedges, n_tris;
} lm_out_map;
lm_status lm_out_map_build(const lm_mesh *m, lm_out_map *map);
void lm_out_map_free(lm_out_map *map);

/* Alive triangles grouped by part (in part-id order), then by material; ids ascending within a
 * group. Every writer puts triangles in this order. */
typedef struct lm_out_group {
    uint32_t part, material;
    uint32_t first, count; /* a range of lm_out_groups.tris */
} lm_out_group;
typedef struct lm_out_groups {
    uint32_t *tris; /* [live triangles] */
    lm_out_group *groups;
    uint32_t n_groups;
    int named; /* some part with triangles has a name: the writers name the parts */
} lm_out_groups;
lm_status lm_out_groups_build(const lm_mesh *m, lm_out_groups *g);
void lm_out_groups_free(lm_out_groups *g);

/* ---- mesh_io_ply_parts.c: the part names a PLY can carry -------------------------------------
 * PLY has no groups: lumesh's writer puts the faces of each part together and names the runs in
 * header comments, "comment lumesh part FIRST COUNT NAME", which other readers ignore. */

/* The part runs named in a PLY header (malloc'ed into *out, *n of them; none: NULL, 0). */
lm_status lm_io_ply_read_parts(const uint8_t *data, size_t size, lm_face_part **out, uint32_t *n);
/* The header comment naming faces [first, first + count) part `name`. */
void lm_io_ply_write_part(FILE *fp, uint64_t first, uint64_t count, const char *name);

lm_status lm_io_save_obj(const char *path, const lm_mesh *m);
lm_status lm_io_save_ply(const char *path, const lm_mesh *m);
lm_status lm_io_save_glb(const char *path, const lm_mesh *m);

#endif
