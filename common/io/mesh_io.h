/* common/io/mesh_io.h — model files. Loading goes through assimp (OBJ+MTL, PLY, OFF, STL, glTF/GLB,
 * FBX, DAE, ...) keeping UVs, normals, colours and diffuse textures (read through OpenImageIO);
 * writing supports OBJ+MTL (textures copied beside it as PNG), PLY and GLB (chosen by extension).
 * Hostile input (NaN/Inf, out-of-range indices, truncated files, absurd counts, empty meshes) is
 * refused with a one-line message; degenerate triangles are dropped with a warning count.
 * Writes are atomic: temp file in the same folder, fsync, rename.
 * UVs follow assimp's (OpenGL's) convention for every format: v = 0 is the bottom row of the
 * texture, i.e. the last row of lm_image (whose rows are stored top to bottom). */
#ifndef LM_COMMON_MESH_IO_H
#define LM_COMMON_MESH_IO_H

#include "common/mesh.h"

typedef struct lm_load_options {
    uint32_t max_tris;   /* 0 = default limit (LM_MESH_MAX_TRIS) */
    int keep_degenerate; /* 0 = drop zero-area / repeated-index triangles */
} lm_load_options;

/* opts may be NULL. On success *out is a validated mesh with adjacency built. */
lm_status lm_mesh_load(const char *path, const lm_load_options *opts, lm_mesh **out);

/* Same from bytes in memory (fuzzing, network). ext_hint ("obj", "ply", "glb", ...) picks the
 * reader; files the model refers to (MTL, textures, .bin buffers) are not opened: only textures
 * embedded in the bytes are decoded. */
lm_status lm_mesh_load_memory(const void *data, size_t size, const char *ext_hint,
                              const lm_load_options *opts, lm_mesh **out);

/* Format from the extension: .obj, .ply, .glb. Dead elements are skipped (written compacted). */
lm_status lm_mesh_save(const char *path, const lm_mesh *m);

/* Levels of detail (finest first) in one GLB: level k's part nodes under a node "LODk"; LOD0 is
 * the scene's node and names the others through the MSFT_lod extension, with coverage[k] in
 * extras.MSFT_screencoverage. Readers without the extension (assimp, so lm_mesh_load) see LOD0.
 * The levels share LOD0's materials (same count). Written atomically. */
#define LM_MESH_MAX_LODS 32
lm_status lm_mesh_save_glb_lods(const char *path, const lm_mesh *const *levels, uint32_t n,
                                const float *coverage);

#endif
