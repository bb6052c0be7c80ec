/* common/io/mesh_io_guard.c — checks on the raw bytes of a model before assimp sees them, for the
 * input classes assimp 5.2 mis-handles: header counts far beyond what the file holds (assimp
 * allocates them up front), truncated GLB containers. OFF and STL have their own walkers
 * (mesh_io_guard_{off,stl,dae,gltf}.c); PLY is read by lumesh's own reader, which checks its
 * counts itself (mesh_io_ply_header.c). Also the list of formats lm_mesh_load accepts. */
#include <ctype.h>
#include <string.h>

#include "common/bytes.h"
#include "common/io/mesh_io_internal.h"

static const char *const known_exts[] = {"obj", "ply", "off", "stl", "gltf", "glb", "fbx", "dae"};

int lm_io_known_ext(const char *ext)
{
    for (size_t i = 0; i < sizeof known_exts / sizeof known_exts[0]; i++)
        if (!strcmp(ext, known_exts[i]))
            return 1;
    return 0;
}

void lm_io_path_ext(const char *path, char *buf, size_t cap)
{
    LM_ASSERT(cap > 0);
    buf[0] = '\0';
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash + 1 : path, '.');
    if (!dot)
        return;
    size_t i = 0;
    for (dot++; *dot && i + 1 < cap; dot++)
        buf[i++] = (char)tolower((unsigned char)*dot);
    buf[i] = '\0';
}

/* GLB container: header and chunk lengths must stay inside the file. */
static lm_status guard_glb(const uint8_t *d, size_t size, const char *name)
{
    if (size < 12 || memcmp(d, "glTF", 4) != 0)
        return lm_fail(LM_E_FORMAT, "%s: not a GLB file (no glTF header)", name);
    uint32_t version = lm_le32(d + 4), length = lm_le32(d + 8);
    if (version == 1)
        return lm_io_gltf1_refusal(name, "a binary (KHR_binary_glTF)");
    if (version != 2)
        return lm_fail(LM_E_UNSUPPORTED, "%s: GLB version %u is not supported (2 is)", name,
                       version);
    if (length > size)
        return lm_fail(LM_E_FORMAT, "%s: truncated GLB (header says %u bytes, file has %zu)", name,
                       length, size);
    uint64_t at = 12;
    for (int chunk = 0; at + 8 <= length; chunk++) {
        uint32_t clen = lm_le32(d + at), ctype = lm_le32(d + at + 4);
        if (chunk == 0 && ctype != 0x4E4F534Au) /* "JSON" */
            return lm_fail(LM_E_FORMAT, "%s: GLB does not start with a JSON chunk", name);
        if (at + 8 + (uint64_t)clen > length)
            return lm_fail(LM_E_FORMAT, "%s: truncated GLB (chunk %d of %u bytes at offset %llu)",
                           name, chunk, clen, (unsigned long long)at);
        at += 8 + (uint64_t)clen;
    }
    if (at == 12)
        return lm_fail(LM_E_FORMAT, "%s: GLB has no JSON chunk", name);
    return lm_io_guard_gltf_json(d + 20, lm_le32(d + 12), name);
}

lm_status lm_io_guard(const uint8_t *data, size_t size, const char *ext, const char *name,
                      uint32_t max_tris)
{
    if (size == 0)
        return lm_fail(LM_E_FORMAT, "%s: the file is empty", name);
    if (!strcmp(ext, "off"))
        return lm_io_guard_off(data, size, name, max_tris);
    if (!strcmp(ext, "stl"))
        return lm_io_guard_stl(data, size, name, max_tris);
    if (!strcmp(ext, "glb"))
        return guard_glb(data, size, name);
    if (!strcmp(ext, "dae"))
        return lm_io_guard_dae(data, size, name);
    if (!strcmp(ext, "gltf"))
        return lm_io_guard_gltf_json(data, size, name);
    return LM_OK;
}
