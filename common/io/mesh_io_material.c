/* common/io/mesh_io_material.c — assimp materials -> lm_material: name, diffuse colour (with
 * opacity), the diffuse (or glTF base colour) texture and the tangent-space normal map (glTF
 * normalTexture, OBJ `norm`: assimp's NORMALS), decoded through OpenImageIO. Textures
 * are embedded ("*N" or a name matching aiScene->mTextures) or files relative to the model's
 * folder. A texture that cannot be found or decoded is a warning, not an error: the material
 * keeps its path and no image. */
#include <assimp/material.h>
#include <assimp/scene.h>
#include <assimp/texture.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/io/mesh_io_internal.h"
#include "common/log.h"

/* An uncompressed embedded texture (BGRA texels) as an RGBA image. */
static lm_status texels_to_image(const struct aiTexture *t, lm_image **out)
{
    lm_image *img;
    lm_status s = lm_image_create((int)t->mWidth, (int)t->mHeight, &img);
    if (s)
        return s;
    size_t n = (size_t)t->mWidth * t->mHeight;
    for (size_t i = 0; i < n; i++) {
        uint8_t *p = img->pixels + 4 * i;
        p[0] = t->pcData[i].r, p[1] = t->pcData[i].g, p[2] = t->pcData[i].b, p[3] = t->pcData[i].a;
    }
    *out = img;
    return LM_OK;
}

static lm_status decode_embedded(const struct aiTexture *t, lm_image **out)
{
    if (!t || !t->pcData)
        return lm_fail(LM_E_FORMAT, "embedded texture has no data");
    if (t->mHeight == 0) {
        char hint[HINTMAXTEXTURELEN + 1] = {0};
        memcpy(hint, t->achFormatHint, HINTMAXTEXTURELEN);
        return lm_image_read_memory(t->pcData, t->mWidth, hint, out);
    }
    if (t->mWidth > LM_IMAGE_MAX_SIDE || t->mHeight > LM_IMAGE_MAX_SIDE)
        return lm_fail(LM_E_RANGE, "embedded texture of %ux%u texels is too large", t->mWidth,
                       t->mHeight);
    return texels_to_image(t, out);
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* The embedded texture `ref` names: "*N", or one whose file name matches. NULL if none. */
static const struct aiTexture *find_embedded(const struct aiScene *sc, const char *ref)
{
    if (ref[0] == '*') {
        char *end;
        unsigned long i = strtoul(ref + 1, &end, 10);
        return end != ref + 1 && !*end && i < sc->mNumTextures ? sc->mTextures[i] : NULL;
    }
    for (unsigned i = 0; i < sc->mNumTextures; i++) {
        const struct aiTexture *t = sc->mTextures[i];
        if (t && t->mFilename.length && !strcmp(base_name(t->mFilename.data), base_name(ref)))
            return t;
    }
    return NULL;
}

/* A texture file beside the model: the path as written (relative to dir), else its base name. */
static lm_status read_external(const char *dir, const char *ref, lm_image **out)
{
    size_t n = strlen(dir) + strlen(ref) + 2;
    char *path = malloc(n);
    if (!path)
        return lm_fail(LM_E_NOMEM, "out of memory loading a texture");
    if (ref[0] == '/')
        snprintf(path, n, "%s", ref);
    else
        snprintf(path, n, "%s/%s", dir, ref);
    if (access(path, R_OK) != 0)
        snprintf(path, n, "%s/%s", dir, base_name(ref));
    lm_status s = lm_image_read(path, out);
    free(path);
    return s;
}

/* Reference of `mat`'s texture of type `type`, else of type `other` (normalised to '/' separators)
 * into ref; 0 if none. */
static int texture_ref(const struct aiMaterial *mat, enum aiTextureType type,
                       enum aiTextureType other, char *ref, size_t cap)
{
    struct aiString p;
    if (aiGetMaterialTexture(mat, type, 0, &p, NULL, NULL, NULL, NULL, NULL, NULL) !=
            aiReturn_SUCCESS &&
        aiGetMaterialTexture(mat, other, 0, &p, NULL, NULL, NULL, NULL, NULL, NULL) !=
            aiReturn_SUCCESS)
        return 0;
    size_t len = p.length < cap - 1 ? p.length : cap - 1;
    memcpy(ref, p.data, len);
    ref[len] = '\0';
    for (char *c = ref; *c; c++)
        if (*c == '\\')
            *c = '/';
    return len > 0 && strlen(ref) == len;
}

static lm_image *load_texture(const struct aiScene *sc, const char *ref, const lm_scene_source *src)
{
    lm_image *img = NULL;
    const struct aiTexture *emb = find_embedded(sc, ref);
    lm_status s;
    if (emb)
        s = decode_embedded(emb, &img);
    else if (src->dir)
        s = read_external(src->dir, ref, &img);
    else
        s = lm_fail(LM_E_UNSUPPORTED, "external texture not opened when loading from memory");
    if (s)
        lm_warn("%s: texture '%s' not loaded: %s", src->name, ref, lm_last_error());
    return s ? NULL : img;
}

static void material_diffuse(const struct aiMaterial *mat, float d[4])
{
    struct aiColor4D c;
    if (aiGetMaterialColor(mat, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS ||
        aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &c) == aiReturn_SUCCESS) {
        d[0] = c.r, d[1] = c.g, d[2] = c.b, d[3] = c.a;
    }
    ai_real opacity;
    unsigned int one = 1;
    if (aiGetMaterialFloatArray(mat, AI_MATKEY_OPACITY, &opacity, &one) == aiReturn_SUCCESS)
        d[3] = (float)opacity;
    for (int k = 0; k < 4; k++)
        if (!isfinite(d[k]))
            d[k] = 1.0f;
}

lm_status lm_io_add_material(lm_mesh *m, const struct aiScene *sc, unsigned index,
                             const lm_scene_source *src, uint32_t *out_id)
{
    if (index >= sc->mNumMaterials || !sc->mMaterials[index])
        return lm_fail(LM_E_FORMAT, "%s: mesh refers to missing material %u", src->name, index);
    const struct aiMaterial *mat = sc->mMaterials[index];
    char name[64] = "";
    struct aiString s_name;
    if (aiGetMaterialString(mat, AI_MATKEY_NAME, &s_name) == aiReturn_SUCCESS)
        snprintf(name, sizeof name, "%.*s", (int)(s_name.length < 63 ? s_name.length : 63),
                 s_name.data);
    float diffuse[4] = {1, 1, 1, 1};
    material_diffuse(mat, diffuse);
    char ref[1024];
    lm_image *tex = NULL;
    int has_ref =
        texture_ref(mat, aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR, ref, sizeof ref);
    if (has_ref)
        tex = load_texture(sc, ref, src);
    uint32_t id;
    lm_status s = lm_mesh_add_material(m, name, diffuse, has_ref ? ref : NULL, tex, &id);
    if (s)
        lm_image_destroy(tex);
    if (!s && texture_ref(mat, aiTextureType_NORMALS, aiTextureType_NORMALS, ref, sizeof ref))
        s = lm_mesh_set_normal_map(m, id, ref, load_texture(sc, ref, src));
    if (!s && out_id)
        *out_id = id;
    return s;
}
