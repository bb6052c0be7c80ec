/* common/io/mesh_io_ply_read.c — lumesh's own PLY reader (ASCII, binary little and big endian):
 * the body of a file whose header mesh_io_ply_header.c parsed, into a scene in assimp's C layout
 * (one mesh, one root node, one material) that lm_mesh_from_scene converts like any other.
 * assimp's PLY reader is not used: it corrupted the heap on a header that repeats its lines.
 *
 * Every value is read through one bounded cursor; a list's length is checked against the bytes
 * left before its items are read, and the triangles it makes against max_tris, so no count in the
 * file is allocated before the file shows it. Faces are split as assimp's Triangulate did for
 * triangles and quads (a quad from its concave corner); larger polygons as a fan from their first
 * corner. Triangle strips restart at -1 and alternate their winding. Colours are normalised by
 * their type as assimp's reader did (uchar /255, ushort /65535, floats as they are). */
#include <assimp/material.h>
#include <assimp/mesh.h>
#include <assimp/scene.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/io/mesh_io_ply_header.h"

typedef struct ply_cursor {
    const uint8_t *d;
    size_t size, at;
    ply_format format;
} ply_cursor;

/* Polygons as read: their corners one after another, and each one's corner count. */
typedef struct ply_polys {
    uint32_t *idx, *n;
    uint64_t n_idx, cap_idx, count, cap, tris;
} ply_polys;

typedef struct ply_reader {
    ply_cursor c;
    const ply_header *h;
    const char *name;
    uint32_t max_tris;
    struct aiMesh *am;
    uint32_t n_verts;
    ply_polys polys;
    uint32_t *buf; /* one list's items */
    uint64_t cap_buf;
} ply_reader;

/* ---- values --------------------------------------------------------------------------------- */

static double binary_value(const uint8_t *p, ply_type t, int big)
{
    size_t n = lm_ply_type_size(t);
    uint64_t v = 0;
    for (size_t i = 0; i < n; i++)
        v |= (uint64_t)p[big ? n - 1 - i : i] << (8 * i);
    switch (t) {
    case PLY_I8:
        return (int8_t)v;
    case PLY_U8:
        return (uint8_t)v;
    case PLY_I16:
        return (int16_t)v;
    case PLY_U16:
        return (uint16_t)v;
    case PLY_I32:
        return (int32_t)v;
    case PLY_U32:
        return (uint32_t)v;
    case PLY_F32: {
        uint32_t u = (uint32_t)v;
        float f;
        memcpy(&f, &u, 4);
        return f;
    }
    default: {
        double f;
        memcpy(&f, &v, 8);
        return f;
    }
    }
}

/* The next ASCII token as a number of type t: integers in decimal, floats as strtod reads them. */
static int ascii_value(ply_cursor *c, ply_type t, double *out)
{
    while (c->at < c->size && c->d[c->at] <= ' ')
        c->at++;
    char tok[64];
    size_t n = 0;
    for (; c->at < c->size && c->d[c->at] > ' '; c->at++)
        if (n + 1 < sizeof tok)
            tok[n++] = (char)c->d[c->at];
        else
            return 0;
    tok[n] = '\0';
    char *end;
    if (n == 0)
        return 0;
    if (t >= PLY_F32)
        *out = strtod(tok, &end);
    else
        *out = (double)strtoll(tok, &end, 10);
    return *end == '\0';
}

/* The next value of type t; 0 when the file ends first or an ASCII token is not a number. */
static int read_value(ply_cursor *c, ply_type t, double *out)
{
    if (c->format == PLY_ASCII)
        return ascii_value(c, t, out);
    size_t n = lm_ply_type_size(t);
    if (c->size - c->at < n)
        return 0;
    *out = binary_value(c->d + c->at, t, c->format == PLY_BINARY_BE);
    c->at += n;
    return 1;
}

static lm_status truncated(const ply_reader *r, const ply_elem *e, uint64_t j)
{
    return lm_fail(LM_E_FORMAT, "%s: truncated or malformed PLY body in %s %llu of %llu", r->name,
                   e->name, (unsigned long long)j, (unsigned long long)e->count);
}

/* ---- vertices ------------------------------------------------------------------------------- */

static float color_value(double v, ply_type t)
{
    switch (t) {
    case PLY_U8:
        return (float)v / 255.0f;
    case PLY_I8:
        return (float)(v + 127) / 255.0f;
    case PLY_U16:
    case PLY_U32:
        return (float)v / 65535.0f;
    case PLY_I16:
        return (float)(v + 32767) / 65535.0f;
    case PLY_I32:
        return (float)v / 255.0f + 0.5f;
    default:
        return (float)v;
    }
}

static void store_vertex_value(struct aiMesh *am, uint32_t i, ply_role role, ply_type t, double v)
{
    float f = (float)v;
    struct aiVector3D *p = &am->mVertices[i];
    struct aiVector3D *n = am->mNormals ? &am->mNormals[i] : NULL;
    struct aiVector3D *uv = am->mTextureCoords[0] ? &am->mTextureCoords[0][i] : NULL;
    struct aiColor4D *c = am->mColors[0] ? &am->mColors[0][i] : NULL;
    switch (role) {
    case PLY_ROLE_X:
        p->x = f;
        break;
    case PLY_ROLE_Y:
        p->y = f;
        break;
    case PLY_ROLE_Z:
        p->z = f;
        break;
    case PLY_ROLE_NX:
        n->x = f;
        break;
    case PLY_ROLE_NY:
        n->y = f;
        break;
    case PLY_ROLE_NZ:
        n->z = f;
        break;
    case PLY_ROLE_RED:
        c->r = color_value(v, t);
        break;
    case PLY_ROLE_GREEN:
        c->g = color_value(v, t);
        break;
    case PLY_ROLE_BLUE:
        c->b = color_value(v, t);
        break;
    case PLY_ROLE_ALPHA:
        c->a = color_value(v, t);
        break;
    case PLY_ROLE_U:
        uv->x = f;
        break;
    case PLY_ROLE_V:
        uv->y = f;
        break;
    default:
        break;
    }
}

/* ---- faces ---------------------------------------------------------------------------------- */

static lm_status grow(void **p, uint64_t *cap, uint64_t need, size_t elem, const char *name)
{
    if (need <= *cap)
        return LM_OK;
    size_t n = need <= SIZE_MAX ? lm_grow_cap(*cap, need, 64, SIZE_MAX / elem) : 0;
    if (!n || !lm_resize(p, n, elem))
        return lm_fail(LM_E_NOMEM, "%s: out of memory reading PLY faces", name);
    *cap = n;
    return LM_OK;
}

/* Keep polygon v[0, n) (n >= 3) for triangulation once every vertex is known. */
static lm_status push_poly(ply_reader *r, const uint32_t *v, uint64_t n)
{
    ply_polys *p = &r->polys;
    if ((p->tris += n - 2) > r->max_tris)
        return lm_fail(LM_E_RANGE, "%s: more than %u triangles (the limit)", r->name, r->max_tris);
    lm_status s = grow((void **)&p->idx, &p->cap_idx, p->n_idx + n, sizeof *p->idx, r->name);
    if (!s)
        s = grow((void **)&p->n, &p->cap, p->count + 1, sizeof *p->n, r->name);
    if (s)
        return s;
    memcpy(p->idx + p->n_idx, v, (size_t)n * sizeof *v);
    p->n_idx += n;
    p->n[p->count++] = (uint32_t)n;
    return LM_OK;
}

/* A strip's items: each new corner makes a triangle with the two before it, every second one
 * turned; -1 restarts. */
static lm_status push_strip(ply_reader *r, const uint32_t *v, uint64_t n)
{
    uint32_t tri[3];
    int have = 0, flip = 0;
    lm_status s = LM_OK;
    for (uint64_t i = 0; !s && i < n; i++) {
        if (v[i] == UINT32_MAX) {
            have = flip = 0;
            continue;
        }
        if (have < 2) {
            tri[have++] = v[i];
            continue;
        }
        uint32_t t[3] = {flip ? tri[1] : tri[0], flip ? tri[0] : tri[1], v[i]};
        s = push_poly(r, t, 3);
        tri[0] = tri[1];
        tri[1] = v[i];
        flip = !flip;
    }
    return s;
}

/* A list property: its length, then its items (kept in r->buf when it holds vertex indices). */
static lm_status read_list(ply_reader *r, const ply_elem *e, const ply_prop *p, uint64_t j)
{
    double len = 0;
    if (!read_value(&r->c, (ply_type)p->count_type, &len) || len < 0)
        return len < 0 ? lm_fail(LM_E_FORMAT, "%s: negative PLY list length in %s %llu", r->name,
                                 e->name, (unsigned long long)j)
                       : truncated(r, e, j);
    uint64_t n = (uint64_t)len, min = r->c.format == PLY_ASCII ? 2 : lm_ply_type_size(p->type);
    if (n > (r->c.size - r->c.at) / min + 1)
        return lm_fail(LM_E_RANGE, "%s: PLY list of %llu values in %s %llu exceeds the file",
                       r->name, (unsigned long long)n, e->name, (unsigned long long)j);
    int keep = p->role == PLY_ROLE_INDICES;
    if (keep && e->kind == PLY_ELEM_FACE && n >= 3 && r->polys.tris + n - 2 > r->max_tris)
        return lm_fail(LM_E_RANGE, "%s: more than %u triangles (the limit)", r->name, r->max_tris);
    lm_status s = keep ? grow((void **)&r->buf, &r->cap_buf, n, sizeof *r->buf, r->name) : LM_OK;
    for (uint64_t i = 0; !s && i < n; i++) {
        double v;
        if (!read_value(&r->c, (ply_type)p->type, &v))
            return truncated(r, e, j);
        int restart = e->kind == PLY_ELEM_STRIP && v == -1;
        if (keep && !restart && !(v >= 0 && v < r->n_verts && v == floor(v)))
            return lm_fail(LM_E_RANGE, "%s: PLY %s %llu refers to vertex %.17g of %u", r->name,
                           e->name, (unsigned long long)j, v, r->n_verts);
        if (keep)
            r->buf[i] = restart ? UINT32_MAX : (uint32_t)v;
    }
    if (s || !keep)
        return s;
    if (e->kind == PLY_ELEM_STRIP)
        return push_strip(r, r->buf, n);
    return n >= 3 ? push_poly(r, r->buf, n) : LM_OK; /* points and lines are not faces */
}

/* ---- elements ------------------------------------------------------------------------------- */

static lm_status read_element(ply_reader *r, const ply_elem *e)
{
    for (uint64_t j = 0; j < e->count; j++) {
        for (uint32_t k = 0; k < e->n_props; k++) {
            const ply_prop *p = &e->props[k];
            if (p->is_list) {
                lm_status s = read_list(r, e, p, j);
                if (s)
                    return s;
                continue;
            }
            double v;
            if (!read_value(&r->c, (ply_type)p->type, &v))
                return truncated(r, e, j);
            if (e->kind == PLY_ELEM_VERTEX)
                store_vertex_value(r->am, (uint32_t)j, (ply_role)p->role, (ply_type)p->type, v);
        }
    }
    return LM_OK;
}

/* ---- the scene ------------------------------------------------------------------------------ */

static int has_role(const ply_elem *e, ply_role lo, ply_role hi)
{
    for (uint32_t k = 0; k < e->n_props; k++)
        if (!e->props[k].is_list && e->props[k].role >= lo && e->props[k].role <= hi)
            return 1;
    return 0;
}

/* The mesh's vertex arrays for the vertex element (zeroed; alpha 1 where colours exist). */
static lm_status make_vertices(ply_reader *r, const ply_elem *v)
{
    struct aiMesh *am = r->am;
    size_t n = (size_t)v->count;
    if (!has_role(v, PLY_ROLE_X, PLY_ROLE_X) || !has_role(v, PLY_ROLE_Y, PLY_ROLE_Y) ||
        !has_role(v, PLY_ROLE_Z, PLY_ROLE_Z))
        return lm_fail(LM_E_FORMAT, "%s: the PLY vertices have no x, y and z", r->name);
    r->n_verts = am->mNumVertices = (unsigned)n;
    int ok = (am->mVertices = calloc(n + 1, sizeof *am->mVertices)) != NULL;
    if (ok && has_role(v, PLY_ROLE_NX, PLY_ROLE_NZ))
        ok = (am->mNormals = calloc(n + 1, sizeof *am->mNormals)) != NULL;
    if (ok && has_role(v, PLY_ROLE_U, PLY_ROLE_V)) {
        am->mNumUVComponents[0] = 2;
        ok = (am->mTextureCoords[0] = calloc(n + 1, sizeof *am->mTextureCoords[0])) != NULL;
    }
    if (ok && has_role(v, PLY_ROLE_RED, PLY_ROLE_ALPHA)) {
        ok = (am->mColors[0] = calloc(n + 1, sizeof *am->mColors[0])) != NULL;
        for (size_t i = 0; ok && i < n; i++)
            am->mColors[0][i].a = 1.0f;
    }
    return ok ? LM_OK : lm_fail(LM_E_NOMEM, "%s: out of memory for %zu vertices", r->name, n);
}

/* Quad q split as assimp's Triangulate did: the fan starts at a concave corner, if any. */
static int quad_start(const struct aiVector3D *p, const uint32_t *q)
{
    for (int i = 0; i < 4; i++) {
        const struct aiVector3D *v = &p[q[i]], *a = &p[q[(i + 3) % 4]], *d = &p[q[(i + 2) % 4]],
                                *b = &p[q[(i + 1) % 4]];
        float l[3] = {a->x - v->x, a->y - v->y, a->z - v->z};
        float g[3] = {d->x - v->x, d->y - v->y, d->z - v->z};
        float rr[3] = {b->x - v->x, b->y - v->y, b->z - v->z};
        float nl = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]),
              ng = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]),
              nr = sqrtf(rr[0] * rr[0] + rr[1] * rr[1] + rr[2] * rr[2]);
        if (nl == 0 || ng == 0 || nr == 0)
            continue;
        float cl = (l[0] * g[0] + l[1] * g[1] + l[2] * g[2]) / (nl * ng);
        float cr = (rr[0] * g[0] + rr[1] * g[1] + rr[2] * g[2]) / (nr * ng);
        if (acosf(fmaxf(-1, fminf(1, cl))) + acosf(fmaxf(-1, fminf(1, cr))) >
            3.1415926538f) /* assimp's AI_MATH_PI_F */
            return i;
    }
    return 0;
}

/* The triangles of every polygon, as the mesh's faces (their indices in one block). */
static lm_status make_faces(ply_reader *r)
{
    struct aiMesh *am = r->am;
    const ply_polys *p = &r->polys;
    if (p->tris == 0)
        return LM_OK;
    unsigned *block = malloc((size_t)p->tris * 3 * sizeof *block);
    am->mFaces = calloc((size_t)p->tris, sizeof *am->mFaces);
    if (!block || !am->mFaces) {
        free(block);
        return lm_fail(LM_E_NOMEM, "%s: out of memory for %llu triangles", r->name,
                       (unsigned long long)p->tris);
    }
    uint64_t t = 0, at = 0;
    for (uint64_t i = 0; i < p->count; at += p->n[i++]) {
        const uint32_t *v = p->idx + at;
        uint32_t n = p->n[i], s = n == 4 ? (uint32_t)quad_start(am->mVertices, v) : 0;
        for (uint32_t k = 1; k + 1 < n; k++, t++) {
            unsigned *f = block + 3 * t;
            f[0] = v[s], f[1] = v[(s + k) % n], f[2] = v[(s + k + 1) % n];
            am->mFaces[t].mNumIndices = 3;
            am->mFaces[t].mIndices = f;
        }
    }
    am->mNumFaces = (unsigned)t;
    am->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    return LM_OK;
}

/* A material with the diffuse texture `tex` (none when ""): assimp's "$tex.file" property. */
static struct aiMaterial *make_material(const char *tex)
{
    struct aiMaterial *mat = calloc(1, sizeof *mat);
    if (!mat || !tex[0])
        return mat;
    struct aiMaterialProperty *p = calloc(1, sizeof *p);
    uint32_t len = (uint32_t)strlen(tex);
    char *data = malloc(4 + (size_t)len + 1);
    mat->mProperties = calloc(1, sizeof *mat->mProperties);
    if (!p || !data || !mat->mProperties) {
        free(p), free(data), free(mat->mProperties), free(mat);
        return NULL;
    }
    snprintf(p->mKey.data, sizeof p->mKey.data, "%s", _AI_MATKEY_TEXTURE_BASE);
    p->mKey.length = (ai_uint32)strlen(p->mKey.data);
    p->mSemantic = aiTextureType_DIFFUSE;
    p->mType = aiPTI_String;
    p->mDataLength = 4 + len + 1;
    memcpy(data, &len, 4);
    memcpy(data + 4, tex, (size_t)len + 1);
    p->mData = data;
    mat->mProperties[0] = p;
    mat->mNumProperties = mat->mNumAllocated = 1;
    return mat;
}

void lm_io_ply_scene_destroy(struct aiScene *sc)
{
    if (!sc)
        return;
    struct aiMesh *am = sc->mMeshes ? sc->mMeshes[0] : NULL;
    if (am) {
        free(am->mFaces ? am->mFaces[0].mIndices : NULL);
        free(am->mFaces), free(am->mVertices), free(am->mNormals);
        free(am->mTextureCoords[0]), free(am->mColors[0]), free(am);
    }
    struct aiMaterial *mat = sc->mMaterials ? sc->mMaterials[0] : NULL;
    if (mat && mat->mProperties) {
        free(mat->mProperties[0]->mData);
        free(mat->mProperties[0]);
        free(mat->mProperties);
    }
    free(mat);
    if (sc->mRootNode)
        free(sc->mRootNode->mMeshes);
    free(sc->mRootNode), free(sc->mMeshes), free(sc->mMaterials), free(sc);
}

/* The scene's frame: a root node holding mesh 0, under the identity. */
static struct aiScene *make_scene(const char *tex)
{
    struct aiScene *sc = calloc(1, sizeof *sc);
    if (!sc)
        return NULL;
    sc->mRootNode = calloc(1, sizeof *sc->mRootNode);
    sc->mMeshes = calloc(1, sizeof *sc->mMeshes);
    sc->mMaterials = calloc(1, sizeof *sc->mMaterials);
    if (sc->mMeshes)
        sc->mMeshes[0] = calloc(1, sizeof *sc->mMeshes[0]);
    if (sc->mMaterials)
        sc->mMaterials[0] = make_material(tex);
    struct aiNode *root = sc->mRootNode;
    if (root && (root->mMeshes = calloc(1, sizeof *root->mMeshes)) != NULL) {
        root->mNumMeshes = 1;
        root->mTransformation.a1 = root->mTransformation.b2 = 1;
        root->mTransformation.c3 = root->mTransformation.d4 = 1;
    }
    sc->mNumMeshes = sc->mNumMaterials = 1;
    if (!root || !root->mMeshes || !sc->mMeshes || !sc->mMeshes[0] || !sc->mMaterials ||
        !sc->mMaterials[0]) {
        lm_io_ply_scene_destroy(sc);
        return NULL;
    }
    return sc;
}

static lm_status read_body(ply_reader *r)
{
    const ply_header *h = r->h;
    lm_status s = LM_OK;
    for (uint32_t i = 0; !s && i < h->n_elems; i++)
        if (h->elems[i].kind == PLY_ELEM_VERTEX)
            s = make_vertices(r, &h->elems[i]);
    if (!s && !r->am->mVertices)
        s = lm_fail(LM_E_FORMAT, "%s: the PLY file has no vertex element", r->name);
    for (uint32_t i = 0; !s && i < h->n_elems; i++)
        s = read_element(r, &h->elems[i]);
    return s ? s : make_faces(r);
}

lm_status lm_io_ply_read(const uint8_t *data, size_t size, const char *name, uint32_t max_tris,
                         struct aiScene **out)
{
    *out = NULL;
    ply_header *h = malloc(sizeof *h);
    if (!h)
        return lm_fail(LM_E_NOMEM, "out of memory reading %s", name);
    lm_status s = lm_ply_header_parse(data, size, name, max_tris, h);
    struct aiScene *sc = s ? NULL : make_scene(h->texture);
    if (!s && !sc)
        s = lm_fail(LM_E_NOMEM, "out of memory reading %s", name);
    ply_reader r = {.c = {data, size, h->body, h->format},
                    .h = h,
                    .name = name,
                    .max_tris = max_tris,
                    .am = sc ? sc->mMeshes[0] : NULL};
    if (!s)
        s = read_body(&r);
    free(r.polys.idx), free(r.polys.n), free(r.buf), free(h);
    if (s) {
        lm_io_ply_scene_destroy(sc);
        return s;
    }
    *out = sc;
    return LM_OK;
}
