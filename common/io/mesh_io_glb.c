/* common/io/mesh_io_glb.c — glTF 2.0 binary (GLB) writer: one node and one mesh per part, both with
 * the part's name (none for the unnamed part), one primitive per material of the part (POSITION
 * with min/max, NORMAL, TEXCOORD_0, COLOR_0 as the mesh has them; uint32 indices),
 * pbrMetallicRoughness materials (baseColorFactor = diffuse, not metallic) whose textures are
 * embedded as PNG; a material's normal map as its normalTexture, and then TANGENT
 * (common/tangents.h, the frames lumesh's renderers shade with) in its primitives, where the mesh
 * has normals and UVs. glTF puts the UV origin at the image's top left, lumesh (like OBJ and
 * assimp) at the bottom left, so v is written as 1 - v. Written atomically. A chain of levels of
 * detail goes into one file the same way, each level's part nodes under a node "LODk", the first
 * level's node in the scene and the others named by its MSFT_lod extension. */
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "common/bytes.h"
#include "common/io/mesh_io_internal.h"
#include "common/tangents.h"

#define LM_GLB_MAX_LODS LM_MESH_MAX_LODS

static void b_printf(lm_bytes *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void b_printf(lm_bytes *b, const char *fmt, ...)
{
    char small[512];
    va_list ap, ap2;
    va_start(ap, fmt);
    va_copy(ap2, ap);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n >= 0 && (size_t)n < sizeof small) {
        lm_bytes_put(b, small, (size_t)n);
    } else if (n >= 0) {
        char *big = malloc((size_t)n + 1);
        if (big)
            vsnprintf(big, (size_t)n + 1, fmt, ap2);
        if (big)
            lm_bytes_put(b, big, (size_t)n);
        b->failed |= !big;
        free(big);
    } else {
        b->failed = 1;
    }
    va_end(ap2);
}

static void b_align(lm_bytes *b, uint8_t fill)
{
    while (b->n % 4)
        lm_bytes_put(b, &fill, 1);
}

typedef struct glb {
    const lm_mesh *m;
    const lm_out_groups *groups;
    lm_bytes bin, views, accessors, meshes, nodes;
    uint32_t n_views, n_accessors, n_prims, n_meshes;
    uint32_t *local; /* [n_wedges] index in the current primitive, LM_NONE if absent */
    uint32_t *order; /* wedges of the current primitive */
    uint32_t *index; /* indices of the current primitive */
    float (*tan)[4]; /* [n_wedges] tangents of the current mesh where it has normal maps, or NULL */
    uint32_t n_levels;
    uint32_t level_first[LM_GLB_MAX_LODS + 1]; /* part nodes of level k: [first[k], first[k+1]) */
    const float *coverage;                     /* MSFT_screencoverage, one per level */
} glb;

/* Append data to the binary chunk as a new buffer view; returns its index. */
static uint32_t add_view(glb *g, const void *data, size_t len, int target)
{
    b_align(&g->bin, 0);
    b_printf(&g->views, "%s{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu",
             g->n_views ? "," : "", g->bin.n, len);
    if (target)
        b_printf(&g->views, ",\"target\":%d", target);
    b_printf(&g->views, "}");
    lm_bytes_put(&g->bin, data, len);
    return g->n_views++;
}

static uint32_t add_accessor(glb *g, uint32_t view, int comp, uint32_t count, const char *type,
                             const char *minmax)
{
    b_printf(&g->accessors,
             "%s{\"bufferView\":%u,\"componentType\":%d,\"count\":%u,\"type\":\"%s\"%s}",
             g->n_accessors ? "," : "", view, comp, count, type, minmax ? minmax : "");
    return g->n_accessors++;
}

/* Float attribute of the current primitive: ncomp floats per wedge from get(). */
static uint32_t float_attr(glb *g, uint32_t n, int ncomp, const char *type,
                           void (*get)(const glb *, uint32_t, float *), int minmax)
{
    float *v = malloc((size_t)n * (size_t)ncomp * sizeof *v + 1);
    if (!v) {
        g->bin.failed = 1;
        return 0;
    }
    float lo[4] = {0}, hi[4] = {0};
    for (uint32_t i = 0; i < n; i++) {
        get(g, g->order[i], v + (size_t)i * (size_t)ncomp);
        for (int k = 0; k < ncomp; k++) {
            float x = v[(size_t)i * (size_t)ncomp + (size_t)k];
            lo[k] = i == 0 || x < lo[k] ? x : lo[k];
            hi[k] = i == 0 || x > hi[k] ? x : hi[k];
        }
    }
    char mm[256] = "";
    if (minmax)
        snprintf(mm, sizeof mm, ",\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]", lo[0], lo[1],
                 lo[2], hi[0], hi[1], hi[2]);
    uint32_t view = add_view(g, v, (size_t)n * (size_t)ncomp * sizeof *v, 34962);
    free(v);
    return add_accessor(g, view, 5126, n, type, minmax ? mm : NULL);
}

static void get_pos(const glb *g, uint32_t w, float *out)
{
    memcpy(out, g->m->pos[g->m->wedges[w].vertex], 3 * sizeof *out);
}
/* glTF wants unit normals (the Khronos validator's ACCESSOR_VECTOR3_NON_UNIT); lumesh's may be
 * scaled (interpolated by the image-driven collapses, scaled by the optimizer). One already unit
 * within 1e-5 is written as it is, the others divided by their length (a zero one stays). */
static void get_normal(const glb *g, uint32_t w, float *out)
{
    const float *n = g->m->wedges[w].normal;
    double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
    for (int k = 0; k < 3; k++)
        out[k] = fabs(len - 1.0) > 1e-5 && len > 0.0 ? (float)(n[k] / len) : n[k];
}
static void get_uv(const glb *g, uint32_t w, float *out)
{
    out[0] = g->m->wedges[w].uv[0];
    out[1] = 1.0f - g->m->wedges[w].uv[1];
}
static void get_color(const glb *g, uint32_t w, float *out)
{
    memcpy(out, g->m->wedges[w].color, 4 * sizeof *out);
}
static void get_tangent(const glb *g, uint32_t w, float *out)
{
    memcpy(out, g->tan[w], 4 * sizeof *out);
}

/* Whether m's normal maps go into the file: they need normals and texture coordinates. */
static int writes_normal_maps(const lm_mesh *m)
{
    int any = 0;
    for (uint32_t i = 0; i < m->n_materials; i++)
        any |= m->materials[i].normal_map != NULL;
    return any && (m->attrs & LM_ATTR_NORMAL) && (m->attrs & LM_ATTR_UV);
}

/* The primitive of one group (a part's triangles of one material). */
static void add_primitive(glb *g, const lm_out_group *grp)
{
    const lm_mesh *m = g->m;
    uint32_t nv = 0, ni = 0, mat = grp->material;
    for (uint32_t i = grp->first; i < grp->first + grp->count; i++) {
        uint32_t t = g->groups->tris[i];
        for (int k = 0; k < 3; k++) {
            uint32_t w = m->tris[t].w[k];
            if (g->local[w] == LM_NONE) {
                g->local[w] = nv;
                g->order[nv++] = w;
            }
            g->index[ni++] = g->local[w];
        }
    }
    b_printf(&g->meshes, "%s{\"attributes\":{\"POSITION\":%u", g->n_prims++ ? "," : "",
             float_attr(g, nv, 3, "VEC3", get_pos, 1));
    if (m->attrs & LM_ATTR_NORMAL)
        b_printf(&g->meshes, ",\"NORMAL\":%u", float_attr(g, nv, 3, "VEC3", get_normal, 0));
    if (m->attrs & LM_ATTR_UV)
        b_printf(&g->meshes, ",\"TEXCOORD_0\":%u", float_attr(g, nv, 2, "VEC2", get_uv, 0));
    if (m->attrs & LM_ATTR_COLOR)
        b_printf(&g->meshes, ",\"COLOR_0\":%u", float_attr(g, nv, 4, "VEC4", get_color, 0));
    if (g->tan && mat < m->n_materials && m->materials[mat].normal_map)
        b_printf(&g->meshes, ",\"TANGENT\":%u", float_attr(g, nv, 4, "VEC4", get_tangent, 0));
    uint32_t view = add_view(g, g->index, (size_t)ni * sizeof *g->index, 34963);
    b_printf(&g->meshes, "},\"indices\":%u", add_accessor(g, view, 5125, ni, "SCALAR", NULL));
    if (m->n_materials)
        b_printf(&g->meshes, ",\"material\":%u", mat);
    b_printf(&g->meshes, ",\"mode\":4}");
    for (uint32_t i = 0; i < nv; i++)
        g->local[g->order[i]] = LM_NONE;
}

/* Length of the valid UTF-8 sequence at s (1..4), or 0 (RFC 3629: no over-long forms, no
 * surrogates, nothing above U+10FFFF; names from FBX files may be Latin-1). */
static int utf8_length(const unsigned char *s)
{
    unsigned c = s[0], lo = 0x80, hi = 0xbf;
    int n = c < 0x80                 ? 1
            : c >= 0xc2 && c <= 0xdf ? 2
            : c >= 0xe0 && c <= 0xef ? 3
            : c >= 0xf0 && c <= 0xf4 ? 4
                                     : 0;
    if (c == 0xe0)
        lo = 0xa0;
    else if (c == 0xed)
        hi = 0x9f;
    else if (c == 0xf0)
        lo = 0x90;
    else if (c == 0xf4)
        hi = 0x8f;
    for (int i = 1; i < n; i++)
        if (s[i] < (i == 1 ? lo : 0x80) || s[i] > (i == 1 ? hi : 0xbf))
            return 0;
    return n;
}

/* A JSON string; bytes that are not UTF-8 become U+FFFD (a strict reader refuses them). */
static void json_string(lm_bytes *b, const char *s)
{
    lm_bytes_put(b, "\"", 1);
    for (const unsigned char *c = (const unsigned char *)s; *c;) {
        int n = utf8_length(c);
        if (*c == '"' || *c == '\\')
            b_printf(b, "\\%c", *c);
        else if (*c < 0x20)
            b_printf(b, "\\u%04x", *c);
        else if (n == 0)
            b_printf(b, "\\ufffd");
        else
            lm_bytes_put(b, c, (size_t)n);
        c += n ? n : 1;
    }
    lm_bytes_put(b, "\"", 1);
}

/* One mesh and its node for the part of the groups [first, end), which share one part. */
static void add_part(glb *g, uint32_t first, uint32_t end)
{
    uint32_t part = g->groups->groups[first].part;
    const char *name = part < g->m->n_parts ? g->m->parts[part].name : "";
    for (int k = 0; k < 2; k++) {
        lm_bytes *b = k ? &g->nodes : &g->meshes;
        b_printf(b, "%s{", g->n_meshes ? "," : "");
        if (name[0]) {
            b_printf(b, "\"name\":");
            json_string(b, name);
            b_printf(b, ",");
        }
    }
    b_printf(&g->nodes, "\"mesh\":%u}", g->n_meshes++);
    b_printf(&g->meshes, "\"primitives\":[");
    g->n_prims = 0;
    for (uint32_t i = first; i < end; i++)
        add_primitive(g, &g->groups->groups[i]);
    b_printf(&g->meshes, "]}");
}

/* Every part: groups come part by part. */
static void add_parts(glb *g)
{
    const lm_out_groups *gr = g->groups;
    for (uint32_t i = 0, j; i < gr->n_groups; i = j) {
        for (j = i; j < gr->n_groups && gr->groups[j].part == gr->groups[i].part; j++)
            ;
        add_part(g, i, j);
    }
}

static void material_json(lm_bytes *js, const lm_material *mat, uint32_t i, uint32_t tex,
                          uint32_t nrm)
{
    b_printf(js, "%s{\"name\":", i ? "," : "");
    json_string(js, mat->name);
    b_printf(js, ",\"pbrMetallicRoughness\":{\"baseColorFactor\":[%.9g,%.9g,%.9g,%.9g]",
             mat->diffuse[0], mat->diffuse[1], mat->diffuse[2], mat->diffuse[3]);
    b_printf(js, ",\"metallicFactor\":0,\"roughnessFactor\":1");
    if (tex != LM_NONE)
        b_printf(js, ",\"baseColorTexture\":{\"index\":%u}", tex);
    b_printf(js, "}");
    if (nrm != LM_NONE)
        b_printf(js, ",\"normalTexture\":{\"index\":%u}", nrm);
    b_printf(js, "%s}", mat->diffuse[3] < 1.0f ? ",\"alphaMode\":\"BLEND\"" : "");
}

static void textures_json(lm_bytes *js, const uint32_t *views, uint32_t n)
{
    b_printf(js, ",\"samplers\":[{\"magFilter\":9729,\"minFilter\":9987,\"wrapS\":10497,"
                 "\"wrapT\":10497}],\"textures\":[");
    for (uint32_t i = 0; i < n; i++)
        b_printf(js, "%s{\"sampler\":0,\"source\":%u}", i ? "," : "", i);
    b_printf(js, "],\"images\":[");
    for (uint32_t i = 0; i < n; i++)
        b_printf(js, "%s{\"bufferView\":%u,\"mimeType\":\"image/png\"}", i ? "," : "", views[i]);
    b_printf(js, "]");
}

/* Materials, and their textures as PNG images in the binary chunk. */
static lm_status add_materials(glb *g, lm_bytes *js)
{
    const lm_mesh *m = g->m;
    uint32_t *views = malloc(((size_t)m->n_materials * 2 + 1) * sizeof *views), n_tex = 0;
    if (!views)
        return lm_fail(LM_E_NOMEM, "out of memory writing materials");
    lm_status s = LM_OK;
    if (m->n_materials)
        b_printf(js, ",\"materials\":[");
    for (uint32_t i = 0; i < m->n_materials && !s; i++) {
        const lm_material *mat = &m->materials[i];
        uint32_t tex = LM_NONE;
        uint8_t *png = NULL;
        size_t len = 0;
        if (mat->texture && !(s = lm_image_encode_png_memory(mat->texture, &png, &len))) {
            views[n_tex] = add_view(g, png, len, 0);
            tex = n_tex++;
            free(png);
        }
        uint32_t nrm = LM_NONE;
        if (!s && mat->normal_map && writes_normal_maps(m) &&
            !(s = lm_image_encode_png_memory(mat->normal_map, &png, &len))) {
            views[n_tex] = add_view(g, png, len, 0);
            nrm = n_tex++;
            free(png);
        }
        material_json(js, mat, i, tex, nrm);
    }
    if (m->n_materials)
        b_printf(js, "]");
    if (n_tex)
        textures_json(js, views, n_tex);
    free(views);
    return s;
}

/* The whole JSON chunk; primitives and materials must have filled the binary chunk. */
/* The node "LODk" over level k's part nodes; the first names the others (MSFT_lod). */
static void lod_roots(glb *g)
{
    for (uint32_t k = 0; k < g->n_levels; k++) {
        b_printf(&g->nodes, ",{\"name\":\"LOD%u\",\"children\":[", k);
        for (uint32_t i = g->level_first[k]; i < g->level_first[k + 1]; i++)
            b_printf(&g->nodes, "%s%u", i > g->level_first[k] ? "," : "", i);
        b_printf(&g->nodes, "]");
        if (k == 0 && g->n_levels > 1) {
            b_printf(&g->nodes, ",\"extensions\":{\"MSFT_lod\":{\"ids\":[");
            for (uint32_t i = 1; i < g->n_levels; i++)
                b_printf(&g->nodes, "%s%u", i > 1 ? "," : "", g->n_meshes + i);
            b_printf(&g->nodes, "]}},\"extras\":{\"MSFT_screencoverage\":[");
            for (uint32_t i = 0; i < g->n_levels; i++)
                b_printf(&g->nodes, "%s%.6g", i ? "," : "", g->coverage[i]);
            b_printf(&g->nodes, "]}");
        }
        b_printf(&g->nodes, "}");
    }
}

static void assemble_json(glb *g, lm_bytes *js, const lm_bytes *mats)
{
    b_printf(js, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"lumesh\"},\"scene\":0,"
                 "\"scenes\":[{\"nodes\":[");
    if (g->n_levels)
        b_printf(js, "%u", g->n_meshes);
    for (uint32_t i = 0; !g->n_levels && i < g->n_meshes; i++)
        b_printf(js, "%s%u", i ? "," : "", i);
    b_printf(js, "]}],");
    if (g->n_levels > 1)
        b_printf(js, "\"extensionsUsed\":[\"MSFT_lod\"],");
    b_printf(js, "\"nodes\":[");
    lm_bytes_put(js, g->nodes.d, g->nodes.n);
    b_printf(js, "],\"meshes\":[");
    lm_bytes_put(js, g->meshes.d, g->meshes.n);
    b_printf(js, "]");
    lm_bytes_put(js, mats->d, mats->n);
    b_printf(js, ",\"accessors\":[");
    lm_bytes_put(js, g->accessors.d, g->accessors.n);
    b_printf(js, "],\"bufferViews\":[");
    lm_bytes_put(js, g->views.d, g->views.n);
    b_align(&g->bin, 0);
    b_printf(js, "],\"buffers\":[{\"byteLength\":%zu}]}", g->bin.n);
    b_align(js, ' ');
}

static void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16),
    p[3] = (uint8_t)(v >> 24);
}

static lm_status write_container(const char *path, const lm_bytes *js, const lm_bytes *bin)
{
    uint8_t head[20];
    if ((uint64_t)js->n + bin->n + 28 > UINT32_MAX)
        return lm_fail(LM_E_RANGE, "cannot write %s: the mesh exceeds GLB's 4 GiB", path);
    memcpy(head, "glTF", 4);
    put_u32(head + 4, 2);
    put_u32(head + 8, (uint32_t)(12 + 8 + js->n + 8 + bin->n));
    put_u32(head + 12, (uint32_t)js->n);
    put_u32(head + 16, 0x4E4F534Au); /* JSON */
    lm_atomic_file f;
    lm_status s = lm_atomic_open(&f, path);
    if (s)
        return s;
    fwrite(head, 1, 20, f.fp);
    fwrite(js->d, 1, js->n, f.fp);
    put_u32(head, (uint32_t)bin->n);
    put_u32(head + 4, 0x004E4942u); /* BIN */
    fwrite(head, 1, 8, f.fp);
    fwrite(bin->d, 1, bin->n, f.fp);
    return lm_atomic_commit(&f);
}

static void glb_free(glb *g)
{
    free(g->bin.d);
    free(g->views.d);
    free(g->accessors.d);
    free(g->meshes.d);
    free(g->nodes.d);
    free(g->local);
    free(g->order);
    free(g->index);
    free(g->tan);
}

/* Buffers for the wedges of m; the groups of m in *groups. */
static lm_status begin_mesh(glb *g, const lm_mesh *m, lm_out_groups *groups)
{
    lm_status s = lm_out_groups_build(m, groups);
    if (s)
        return s;
    free(g->local);
    free(g->order);
    free(g->index);
    free(g->tan);
    g->tan = NULL;
    g->m = m;
    g->groups = groups;
    g->local = malloc(((size_t)m->n_wedges + 1) * sizeof *g->local);
    g->order = malloc(((size_t)m->n_wedges + 1) * sizeof *g->order);
    g->index = malloc(((size_t)m->n_tris * 3 + 1) * sizeof *g->index);
    if (!g->local || !g->order || !g->index)
        return lm_fail(LM_E_NOMEM, "out of memory writing a GLB");
    memset(g->local, 0xff, ((size_t)m->n_wedges + 1) * sizeof *g->local);
    return writes_normal_maps(m) ? lm_mesh_tangents(m, &g->tan) : LM_OK;
}

/* Every mesh's parts, the first mesh's materials, the JSON, the file. */
static lm_status write_glb(glb *g, const char *path, const lm_mesh *const *meshes, uint32_t n)
{
    lm_bytes mats = {0}, js = {0};
    lm_status s = LM_OK;
    for (uint32_t k = 0; k < n && !s; k++) {
        lm_out_groups groups;
        s = begin_mesh(g, meshes[k], &groups);
        if (!s) {
            g->level_first[k] = g->n_meshes;
            add_parts(g);
            g->level_first[k + 1] = g->n_meshes;
        }
        lm_out_groups_free(&groups);
    }
    g->m = meshes[0];
    if (!s && g->n_levels)
        lod_roots(g);
    if (!s)
        s = add_materials(g, &mats);
    if (!s) {
        assemble_json(g, &js, &mats);
        if (g->bin.failed || g->views.failed || g->accessors.failed || g->meshes.failed ||
            g->nodes.failed || mats.failed || js.failed)
            s = lm_fail(LM_E_NOMEM, "out of memory writing %s", path);
    }
    if (!s)
        s = write_container(path, &js, &g->bin);
    glb_free(g);
    free(mats.d);
    free(js.d);
    return s;
}

lm_status lm_io_save_glb(const char *path, const lm_mesh *m)
{
    glb g = {0};
    const lm_mesh *const one[1] = {m};
    return write_glb(&g, path, one, 1);
}

lm_status lm_mesh_save_glb_lods(const char *path, const lm_mesh *const *levels, uint32_t n,
                                const float *coverage)
{
    if (n < 1 || n > LM_MESH_MAX_LODS)
        return lm_fail(LM_E_RANGE, "%u levels of detail (1..%u)", n, LM_MESH_MAX_LODS);
    for (uint32_t k = 1; k < n; k++)
        if (levels[k]->n_materials != levels[0]->n_materials)
            return lm_fail(LM_E_INVALID,
                           "level %u has %u materials, level 0 %u: levels share "
                           "their materials",
                           k, levels[k]->n_materials, levels[0]->n_materials);
    glb g = {.n_levels = n, .coverage = coverage};
    return write_glb(&g, path, levels, n);
}
