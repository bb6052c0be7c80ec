/* common/io/mesh_io_guard_gltf.c — checks the JSON of a glTF (.gltf, or a .glb's first chunk)
 * before assimp 5.2 sees it. assimp picks its glTF importer only if the JSON parses and names a
 * version; otherwise it falls back to guessing the format from the bytes and hands them to
 * whichever of its forty readers claims them (MD5, MD2, X...), several of which read out of bounds
 * on hostile input. So the JSON must parse under a strict parser (jansson: no NaN, comments,
 * trailing commas, NUL or invalid UTF-8, duplicate keys — all of which assimp's RapidJSON refuses
 * or tolerates), and its "asset" must say version 2.x. glTF 1.0 (obsolete since 2017: version "1.0"
 * or the number 1, or no version and its dictionaries where 2.0 has arrays) is named as such, with
 * what to do. */
#include <jansson.h>
#include <string.h>

#include "common/io/mesh_io_internal.h"

/* glTF 1.0 keeps accessors, meshes and nodes in objects keyed by id; 2.0 in arrays. */
static int looks_like_gltf1(const json_t *root, const json_t *version)
{
    if (json_is_integer(version) || json_is_real(version))
        return json_number_value(version) < 2;
    if (json_is_string(version))
        return json_string_value(version)[0] == '1';
    static const char *const keys[] = {"accessors", "meshes", "nodes", "buffers"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (json_is_object(json_object_get(root, keys[i])))
            return 1;
    return 0;
}

lm_status lm_io_gltf1_refusal(const char *name, const char *what)
{
    return lm_fail(LM_E_UNSUPPORTED,
                   "%s: %s glTF 1.0 file (the 2015 format, replaced by glTF 2.0 in 2017); lumesh "
                   "reads glTF 2.0: convert it (e.g. Khronos glTF-Pipeline: gltf-pipeline -i IN -o "
                   "OUT.glb) or "
                   "export glTF 2.0 from the authoring tool",
                   name, what);
}

lm_status lm_io_guard_gltf_json(const uint8_t *json, size_t size, const char *name)
{
    json_error_t err;
    json_t *root = json_loadb((const char *)json, size, JSON_REJECT_DUPLICATES, &err);
    if (!root)
        return lm_fail(LM_E_FORMAT, "%s: not a glTF file: JSON error at line %d: %s", name,
                       err.line, err.text);
    json_t *asset = json_is_object(root) ? json_object_get(root, "asset") : NULL;
    json_t *version = json_is_object(asset) ? json_object_get(asset, "version") : NULL;
    const char *v = json_is_string(version) ? json_string_value(version) : NULL;
    lm_status st = LM_OK;
    if (json_is_object(root) && looks_like_gltf1(root, version))
        st = lm_io_gltf1_refusal(name, "a");
    else if (!v)
        st = lm_fail(LM_E_FORMAT, "%s: not a glTF file (no asset.version)", name);
    else if (v[0] != '2')
        st = lm_fail(LM_E_UNSUPPORTED, "%s: glTF version '%.16s' is not supported (2.x is)", name,
                     v);
    json_decref(root);
    return st;
}
