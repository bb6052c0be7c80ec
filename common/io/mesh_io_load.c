/* common/io/mesh_io_load.c — lm_mesh_load / lm_mesh_load_memory: read the bytes, refuse hostile
 * input assimp would mis-handle (mesh_io_guard*.c), import through assimp's C API with our own file
 * system (mesh_io_aifs.c) or, for PLY, through lumesh's own reader (mesh_io_ply_read.c), convert
 * the scene (mesh_io_scene.c), validate, build adjacency; glTF, GLB, FBX and COLLADA in a process
 * of their own (mesh_io_isolate.c). Which input is read how, and why:
 * common/io/INPUT_SAFETY.md.
 *
 * assimp runs in two steps: import with ValidateDataStructure only; then, once our own checks of
 * the raw scene pass (lm_io_check_scene: faces without indices make assimp's Triangulate abort),
 * Triangulate. Deliberately not used: JoinIdenticalVertices (its epsilon comparison merges
 * vertices with NaN coordinates into their neighbours, hiding them; we weld exactly ourselves),
 * GenNormals (normals are derived by lm_mesh_compute_normals when the model has none),
 * FindDegenerates (we drop and count degenerate triangles ourselves) and SortByPType (points and
 * lines are skipped face by face). */
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "common/io/mesh_io_internal.h"
#include "common/mesh_topology.h"

/* Prefix the current error message with the model's name (one line). */
static lm_status fail_named(lm_status s, const char *name)
{
    char msg[400];
    snprintf(msg, sizeof msg, "%s", lm_last_error());
    return lm_fail(s, "%s: %s", name, msg);
}

/* assimp's message, one line, mapped to a status. */
static lm_status import_error(const char *name)
{
    const char *e = aiGetErrorString();
    char msg[300];
    snprintf(msg, sizeof msg, "%s", e && *e ? e : "unknown assimp error");
    char *nl = strpbrk(msg, "\r\n");
    if (nl)
        *nl = '\0';
    if (strstr(msg, "bad_alloc"))
        return lm_fail(LM_E_NOMEM, "%s: out of memory while importing (%s)", name, msg);
    if (strstr(msg, "out of range") && (strstr(msg, "ndex") || strstr(msg, "mIndices")))
        return lm_fail(LM_E_RANGE, "%s: cannot import: %s", name, msg);
    return lm_fail(LM_E_FORMAT, "%s: cannot import: %s", name, msg);
}

/* Import, check, triangulate. */
static lm_status import_scene(lm_aifs *fs, const char *name, const struct aiScene **out)
{
    const struct aiScene *sc =
        aiImportFileEx(name, aiProcess_ValidateDataStructure, lm_aifs_io(fs));
    if (!sc)
        return import_error(name);
    lm_status s = lm_io_check_scene(sc, name);
    if (s) {
        aiReleaseImport(sc);
        return s;
    }
    /* On failure assimp has already freed the scene (its importer object then leaks); only its
     * validation step can fail, and it is not requested here. */
    *out = aiApplyPostProcessing(sc, aiProcess_Triangulate);
    return *out ? LM_OK : import_error(name);
}

static uint32_t max_tris_of(const lm_load_options *opts)
{
    uint32_t max_tris = opts && opts->max_tris ? opts->max_tris : LM_MESH_MAX_TRIS;
    return max_tris < LM_MESH_MAX_TRIS ? max_tris : LM_MESH_MAX_TRIS;
}

/* The scene of bytes that passed lm_io_guard: lumesh's own reader for PLY (*ours set: release
 * with lm_io_ply_scene_destroy), assimp for the rest (*fs is then its file system). */
static lm_status read_scene(const uint8_t *data, size_t size, const char *name, const char *ext,
                            const char *dir, uint32_t max_tris, lm_aifs **fs,
                            const struct aiScene **sc, int *ours)
{
    *fs = NULL;
    *ours = !strcmp(ext, "ply");
    if (*ours) {
        struct aiScene *ply = NULL;
        lm_status s = lm_io_ply_read(data, size, name, max_tris, &ply);
        if (!s && (s = lm_io_check_scene(ply, name)) != LM_OK)
            lm_io_ply_scene_destroy(ply);
        *sc = s ? NULL : ply;
        return s;
    }
    lm_status s = lm_aifs_create(name, data, size, dir != NULL, fs);
    if (!s && (s = import_scene(*fs, name, sc)) != LM_OK) {
        lm_aifs_destroy(*fs);
        *fs = NULL;
    }
    return s;
}

static void release_scene(const struct aiScene *sc, lm_aifs *fs, int ours)
{
    if (ours)
        lm_io_ply_scene_destroy((struct aiScene *)sc);
    else
        aiReleaseImport(sc);
    lm_aifs_destroy(fs);
}

lm_status lm_io_load_bytes_here(const uint8_t *data, size_t size, const char *name, const char *dir,
                                const lm_load_options *opts, lm_mesh **out)
{
    uint32_t max_tris = max_tris_of(opts);
    char ext[16];
    lm_io_path_ext(name, ext, sizeof ext);
    lm_aifs *fs = NULL;
    const struct aiScene *sc = NULL;
    int ours = 0;
    lm_status s = read_scene(data, size, name, ext, dir, max_tris, &fs, &sc, &ours);
    if (s)
        return s;
    lm_scene_source src = {.name = name,
                           .dir = dir,
                           .max_tris = max_tris,
                           .keep_degenerate = opts ? opts->keep_degenerate : 0};
    lm_face_part *parts = NULL;
    if (ours)
        s = lm_io_ply_read_parts(data, size, &parts, &src.n_face_parts);
    src.face_parts = parts;
    lm_mesh *m = NULL;
    if (!s)
        s = lm_mesh_from_scene(sc, &src, &m);
    free(parts);
    release_scene(sc, fs, ours);
    if (!s && (s = lm_mesh_validate(m)) != LM_OK)
        s = fail_named(s, name);
    if (!s)
        s = lm_mesh_build_adjacency(m);
    if (s) {
        lm_mesh_destroy(m);
        return s;
    }
    *out = m;
    return LM_OK;
}

/* The byte guards here, then the reader here or, for the formats whose assimp reader is not
 * proven safe, in a process of its own (mesh_io_isolate.c). */
static lm_status load_bytes(const uint8_t *data, size_t size, const char *ext, const char *name,
                            const char *dir, const lm_load_options *opts, lm_mesh **out)
{
    lm_status s = lm_io_guard(data, size, ext, name, max_tris_of(opts));
    if (s)
        return s;
    if (!lm_io_isolated_format(ext))
        return lm_io_load_bytes_here(data, size, name, dir, opts, out);
    return lm_io_load_isolated(data, size, name, dir, opts, out);
}

lm_status lm_mesh_load(const char *path, const lm_load_options *opts, lm_mesh **out)
{
    LM_ASSERT(path != NULL && out != NULL);
    struct stat st;
    if (stat(path, &st) != 0)
        return lm_fail(LM_E_IO, "cannot read %s: %s", path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return lm_fail(LM_E_IO, "cannot read %s: not a regular file", path);
    char ext[16];
    lm_io_path_ext(path, ext, sizeof ext);
    if (!lm_io_known_ext(ext))
        return lm_fail(
            LM_E_FORMAT,
            "%s: unsupported model format '%s' (obj, ply, off, stl, gltf, glb, fbx, dae)", path,
            ext);
    uint8_t *data;
    size_t size;
    lm_status s = lm_io_read_file(path, &data, &size);
    if (s)
        return s;
    const char *slash = strrchr(path, '/');
    char *dir = slash ? strndup(path, (size_t)(slash - path) + (slash == path)) : strdup(".");
    if (!dir)
        s = lm_fail(LM_E_NOMEM, "out of memory loading %s", path);
    else
        s = load_bytes(data, size, ext, path, dir, opts, out);
    free(dir);
    free(data);
    return s;
}

lm_status lm_mesh_load_memory(const void *data, size_t size, const char *ext_hint,
                              const lm_load_options *opts, lm_mesh **out)
{
    LM_ASSERT(out != NULL && (data != NULL || size == 0));
    char ext[16], name[32];
    const char *dot = ext_hint ? strrchr(ext_hint, '.') : NULL;
    snprintf(ext, sizeof ext, "%s", dot ? dot + 1 : ext_hint ? ext_hint : "");
    for (char *c = ext; *c; c++)
        *c = (char)tolower((unsigned char)*c);
    if (!lm_io_known_ext(ext))
        return lm_fail(LM_E_FORMAT, "unsupported model format '%s'", ext);
    if (size > LM_IO_MAX_FILE_BYTES)
        return lm_fail(LM_E_RANGE, "model of %zu bytes exceeds the limit of %zu", size,
                       LM_IO_MAX_FILE_BYTES);
    snprintf(name, sizeof name, "memory.%s", ext);
    /* Text readers in assimp expect a terminating NUL beyond the data: give them a copy. */
    uint8_t *copy = malloc(size + 1);
    if (!copy)
        return lm_fail(LM_E_NOMEM, "out of memory loading a %zu-byte model", size);
    memcpy(copy, data, size);
    copy[size] = 0;
    lm_status s = load_bytes(copy, size, ext, name, NULL, opts, out);
    free(copy);
    return s;
}
