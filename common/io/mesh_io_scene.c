/* common/io/mesh_io_scene.c — an assimp scene -> one lm_mesh. Every mesh instance reachable from
 * the root node is placed with its node's accumulated transform (normals by the inverse transpose,
 * winding flipped under mirroring). Vertices are welded by exact position across the whole scene;
 * each distinct attribute set (normal, uv channel 0, colour channel 0) of a vertex within one mesh
 * instance becomes a wedge. Triangles whose corners share a position are dropped, and so are
 * zero-area ones unless asked to keep them. Materials are added in order of first use, and so are
 * parts: one per node holding triangles, named by the node (by its mesh where assimp made the
 * node's name up), nodes of one name sharing the part; a lumesh PLY names runs of faces instead. */
#include <assimp/mesh.h>
#include <assimp/scene.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io_internal.h"
#include "common/log.h"

typedef struct hash_table {
    uint32_t *slots; /* element ids, LM_NONE = empty */
    size_t mask;
} hash_table;

typedef struct scene_build {
    const struct aiScene *sc;
    const lm_scene_source *src;
    lm_mesh *m;
    hash_table verts, wedges, parts;
    uint32_t *mat_map;         /* [mNumMaterials] lm material id or LM_NONE */
    uint32_t first_wedge;      /* wedges of the current instance start here */
    const struct aiNode *node; /* the node being walked */
    uint64_t tris, dropped, instances;
    int all_normals, any_uv, any_color;
    lm_status (*visit)(struct scene_build *b, const struct aiMesh *am, const double xf[16]);
} scene_build;

/* ---- small helpers ----------------------------------------------------------------------------
 */

static lm_status table_init(hash_table *t, uint64_t n, const char *name)
{
    uint64_t cap = 64;
    while (cap < 2 * n)
        cap *= 2;
    t->slots = cap <= SIZE_MAX / sizeof *t->slots ? malloc((size_t)cap * sizeof *t->slots) : NULL;
    if (!t->slots)
        return lm_fail(LM_E_NOMEM, "%s: out of memory for %llu vertices", name,
                       (unsigned long long)n);
    memset(t->slots, 0xff, (size_t)cap * sizeof *t->slots);
    t->mask = (size_t)cap - 1;
    return LM_OK;
}

static uint64_t hash_bytes(const void *data, size_t n)
{
    const uint8_t *p = data;
    uint64_t h = 14695981039346656037ull;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 1099511628211ull;
    return h ^ (h >> 31);
}

static int triangle_mesh(const struct aiMesh *am)
{
    return am && am->mVertices && am->mNumVertices && am->mFaces &&
           (am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE);
}

/* 4x4 row-major product r = a * b (r may not alias). */
static void mat_mul(const double a[16], const double b[16], double r[16])
{
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] +
                           a[4 * i + 3] * b[12 + j];
}

static void node_matrix(const struct aiNode *node, double r[16])
{
    const struct aiMatrix4x4 *t = &node->mTransformation;
    const ai_real v[16] = {t->a1, t->a2, t->a3, t->a4, t->b1, t->b2, t->b3, t->b4,
                           t->c1, t->c2, t->c3, t->c4, t->d1, t->d2, t->d3, t->d4};
    for (int i = 0; i < 16; i++)
        r[i] = v[i];
}

/* Depth-first over nodes, calling b->visit for every mesh instance. */
static lm_status walk(scene_build *b, const struct aiNode *node, const double parent[16], int depth)
{
    if (depth > LM_IO_MAX_NODE_DEPTH)
        return lm_fail(LM_E_FORMAT, "%s: node hierarchy deeper than %d", b->src->name,
                       LM_IO_MAX_NODE_DEPTH);
    double local[16], xf[16];
    node_matrix(node, local);
    mat_mul(parent, local, xf);
    b->node = node;
    for (unsigned i = 0; i < node->mNumMeshes; i++) {
        unsigned mi = node->mMeshes[i];
        if (mi >= b->sc->mNumMeshes)
            return lm_fail(LM_E_FORMAT, "%s: node refers to missing mesh %u", b->src->name, mi);
        lm_status s = b->visit(b, b->sc->mMeshes[mi], xf);
        if (s)
            return s;
    }
    for (unsigned i = 0; i < node->mNumChildren; i++) {
        if (!node->mChildren || !node->mChildren[i])
            return lm_fail(LM_E_FORMAT, "%s: missing child node", b->src->name);
        lm_status s = walk(b, node->mChildren[i], xf, depth + 1);
        if (s)
            return s;
    }
    return LM_OK;
}

static lm_status walk_scene(scene_build *b)
{
    static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    if (!b->sc->mRootNode)
        return lm_fail(LM_E_FORMAT, "%s: the scene has no root node", b->src->name);
    return walk(b, b->sc->mRootNode, identity, 0);
}

/* ---- pass 1: count, check positions, find which attributes exist ------------------------------
 */

static int finite_vec(const struct aiVector3D *v, unsigned i)
{
    return !v || (isfinite(v[i].x) && isfinite(v[i].y) && isfinite(v[i].z));
}

/* Name of the first non-finite attribute of vertex i, or NULL. */
static const char *bad_attribute(const struct aiMesh *am, unsigned i)
{
    const struct aiColor4D *c = am->mColors[0] ? &am->mColors[0][i] : NULL;
    if (!finite_vec(am->mVertices, i))
        return "coordinate";
    if (!finite_vec(am->mNormals, i))
        return "normal";
    if (!finite_vec(am->mTextureCoords[0], i))
        return "texture coordinate";
    if (c && !(isfinite(c->r) && isfinite(c->g) && isfinite(c->b) && isfinite(c->a)))
        return "colour";
    return NULL;
}

/* Faces assimp's own post-processing would trip over: no indices (TriangulateProcess asserts
 * when a mesh flagged as having polygons has none), and non-finite vertex data. */
static lm_status check_mesh(const struct aiMesh *am, const char *name)
{
    if (!am)
        return lm_fail(LM_E_FORMAT, "%s: missing mesh", name);
    unsigned polygons = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        if (!am->mFaces || am->mFaces[f].mNumIndices == 0 || !am->mFaces[f].mIndices)
            return lm_fail(LM_E_FORMAT, "%s: face %u of mesh '%s' has no vertices", name, f,
                           am->mName.data);
        polygons += am->mFaces[f].mNumIndices > 3;
    }
    if ((am->mPrimitiveTypes & aiPrimitiveType_POLYGON) && !polygons)
        return lm_fail(LM_E_FORMAT, "%s: mesh '%s' claims polygons it does not have", name,
                       am->mName.data);
    for (unsigned i = 0; am->mVertices && i < am->mNumVertices; i++) {
        const char *bad = bad_attribute(am, i);
        if (bad)
            return lm_fail(LM_E_RANGE,
                           "%s: vertex %u of mesh '%s' has a %s that is not a finite "
                           "number",
                           name, i, am->mName.data, bad);
    }
    return LM_OK;
}

lm_status lm_io_check_scene(const struct aiScene *sc, const char *name)
{
    if (sc->mNumMeshes && !sc->mMeshes)
        return lm_fail(LM_E_FORMAT, "%s: missing meshes", name);
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        lm_status s = check_mesh(sc->mMeshes[i], name);
        if (s)
            return s;
    }
    return LM_OK;
}

static lm_status count_instance(scene_build *b, const struct aiMesh *am, const double xf[16])
{
    (void)xf;
    if (!triangle_mesh(am))
        return LM_OK;
    lm_status s = check_mesh(am, b->src->name);
    if (s)
        return s;
    for (unsigned f = 0; f < am->mNumFaces; f++)
        b->tris += am->mFaces[f].mNumIndices == 3;
    b->instances++;
    if (b->tris > b->src->max_tris)
        return lm_fail(LM_E_RANGE, "%s: more than %u triangles (the limit)", b->src->name,
                       b->src->max_tris);
    b->all_normals &= am->mNormals != NULL;
    b->any_uv |= am->mTextureCoords[0] != NULL;
    b->any_color |= am->mColors[0] != NULL;
    return LM_OK;
}

/* ---- parts ------------------------------------------------------------------------------------
 */

/* Names assimp makes up where the file has none: "", its "<OFFRoot>"-style roots, glTF's
 * "nodes[3]" and "meshes[3]", OBJ's "defaultobject", FBX pivot helpers. */
static int made_up_name(const char *s)
{
    size_t n = strlen(s), k = 0;
    if (n == 0 || (s[0] == '<' && s[n - 1] == '>') || !strcmp(s, "defaultobject") ||
        strstr(s, "$AssimpFbx$"))
        return 1;
    if (!strncmp(s, "nodes[", 6))
        k = 6;
    else if (!strncmp(s, "meshes[", 7))
        k = 7;
    if (!k || s[n - 1] != ']' || n == k + 1)
        return 0;
    for (size_t i = k; i + 1 < n; i++)
        if (s[i] < '0' || s[i] > '9')
            return 0;
    return 1;
}

/* Length of `s` without a "-<digits>" tail (assimp's glTF primitive number), or 0 if none. */
static size_t primitive_stem(const char *s)
{
    size_t n = strlen(s), i = n;
    while (i > 0 && s[i - 1] >= '0' && s[i - 1] <= '9')
        i--;
    return i < n && i > 1 && s[i - 1] == '-' ? i - 1 : 0;
}

/* The name of the node's part: its own, else its mesh's ("X" for the meshes "X-0", "X-1" that
 * assimp makes of one glTF mesh's primitives), else "". */
static void node_part_name(const struct aiScene *sc, const struct aiNode *node, char *out,
                           size_t cap)
{
    snprintf(out, cap, "%s", node->mName.data);
    if (!made_up_name(out))
        return;
    const char *m0 = node->mNumMeshes ? sc->mMeshes[node->mMeshes[0]]->mName.data : "";
    size_t stem = node->mNumMeshes > 1 ? primitive_stem(m0) : 0;
    for (unsigned i = 1; stem && i < node->mNumMeshes; i++) {
        const char *mi = sc->mMeshes[node->mMeshes[i]]->mName.data;
        if (primitive_stem(mi) != stem || strncmp(mi, m0, stem) != 0)
            stem = 0;
    }
    snprintf(out, cap, "%.*s", (int)(stem ? stem : strlen(m0)), m0);
    if (made_up_name(out))
        out[0] = '\0';
}

/* The id of the part named `name`, added if new. */
static lm_status part_id(scene_build *b, const char *name, uint32_t *out)
{
    char cut[LM_PART_NAME_MAX];
    snprintf(cut, sizeof cut, "%s", name);
    uint64_t h = hash_bytes(cut, strlen(cut));
    for (size_t i = (size_t)h & b->parts.mask;; i = (i + 1) & b->parts.mask) {
        uint32_t id = b->parts.slots[i];
        if (id == LM_NONE) {
            lm_status s = lm_mesh_add_part(b->m, cut, out);
            if (!s)
                b->parts.slots[i] = *out;
            return s;
        }
        if (!strcmp(b->m->parts[id].name, cut)) {
            *out = id;
            return LM_OK;
        }
    }
}

/* ---- pass 2: build ----------------------------------------------------------------------------
 */

static lm_status weld_vertex(scene_build *b, const float p[3], uint32_t *out)
{
    uint64_t h = hash_bytes(p, 3 * sizeof *p);
    for (size_t i = (size_t)h & b->verts.mask;; i = (i + 1) & b->verts.mask) {
        uint32_t id = b->verts.slots[i];
        if (id == LM_NONE) {
            lm_status s = lm_mesh_add_vertex(b->m, p, out);
            if (!s)
                b->verts.slots[i] = *out;
            return s;
        }
        if (!memcmp(b->m->pos[id], p, 3 * sizeof *p)) {
            *out = id;
            return LM_OK;
        }
    }
}

static uint64_t wedge_hash(const lm_wedge *w)
{
    float key[10] = {0,        w->normal[0], w->normal[1], w->normal[2], w->uv[0],
                     w->uv[1], w->color[0],  w->color[1],  w->color[2],  w->color[3]};
    memcpy(&key[0], &w->vertex, sizeof w->vertex);
    return hash_bytes(key, sizeof key);
}

static int wedge_equal(const lm_wedge *a, const lm_wedge *b)
{
    return a->vertex == b->vertex && !memcmp(a->normal, b->normal, sizeof a->normal) &&
           !memcmp(a->uv, b->uv, sizeof a->uv) && !memcmp(a->color, b->color, sizeof a->color);
}

/* The wedge of this instance equal to w, added if new. */
static lm_status find_wedge(scene_build *b, const lm_wedge *w, uint32_t *out)
{
    for (size_t i = (size_t)wedge_hash(w) & b->wedges.mask;; i = (i + 1) & b->wedges.mask) {
        uint32_t id = b->wedges.slots[i];
        if (id == LM_NONE) {
            lm_status s = lm_mesh_add_wedge(b->m, w, out);
            if (!s)
                b->wedges.slots[i] = *out;
            return s;
        }
        if (id >= b->first_wedge && wedge_equal(&b->m->wedges[id], w)) {
            *out = id;
            return LM_OK;
        }
    }
}

#define USED (LM_NONE - 1) /* in instance.wedge: used by a kept face, wedge not yet made */

/* Per-instance state: transformed positions and the wedge of each assimp vertex. */
typedef struct instance {
    const struct aiMesh *am;
    double nm[9]; /* normal matrix: inverse transpose of the upper 3x3, up to a positive scale */
    int flip;     /* determinant < 0: mirror, so reverse the winding */
    float (*pos)[3];
    uint32_t *wedge;
    uint32_t material;
    uint32_t part;       /* every face's part, unless face_part is set */
    uint32_t *face_part; /* [mNumFaces] part of each face (a lumesh PLY), or NULL */
} instance;

static void instance_transform(instance *in, const double xf[16])
{
    const double *m = xf;
    /* cofactor matrix of the upper 3x3 (= det * inverse transpose) */
    double c[9] = {
        m[5] * m[10] - m[6] * m[9], m[6] * m[8] - m[4] * m[10], m[4] * m[9] - m[5] * m[8],
        m[2] * m[9] - m[1] * m[10], m[0] * m[10] - m[2] * m[8], m[1] * m[8] - m[0] * m[9],
        m[1] * m[6] - m[2] * m[5],  m[2] * m[4] - m[0] * m[6],  m[0] * m[5] - m[1] * m[4]};
    double det = m[0] * c[0] + m[1] * c[1] + m[2] * c[2];
    in->flip = det < 0;
    for (int i = 0; i < 9; i++)
        in->nm[i] = det < 0 ? -c[i] : c[i];
    for (unsigned i = 0; i < in->am->mNumVertices; i++) {
        const struct aiVector3D *p = &in->am->mVertices[i];
        for (int r = 0; r < 3; r++)
            in->pos[i][r] = (float)(m[4 * r] * p->x + m[4 * r + 1] * p->y + m[4 * r + 2] * p->z +
                                    m[4 * r + 3]) +
                            0.0f; /* + 0.0f turns -0 into +0 for welding */
    }
}

/* Attributes of assimp vertex i, the normal transformed and kept at its original length. */
static void instance_attrs(const instance *in, unsigned i, lm_wedge *w)
{
    const struct aiMesh *am = in->am;
    memset(w, 0, sizeof *w);
    if (am->mNormals) {
        const struct aiVector3D *n = &am->mNormals[i];
        double t[3], len = 0,
                     len0 = sqrt((double)n->x * n->x + (double)n->y * n->y + (double)n->z * n->z);
        for (int r = 0; r < 3; r++) {
            t[r] = in->nm[3 * r] * n->x + in->nm[3 * r + 1] * n->y + in->nm[3 * r + 2] * n->z;
            len += t[r] * t[r];
        }
        len = sqrt(len);
        for (int r = 0; r < 3; r++)
            w->normal[r] = len > 0 ? (float)(t[r] * len0 / len) : 0.0f;
    }
    if (am->mTextureCoords[0]) {
        w->uv[0] = am->mTextureCoords[0][i].x;
        w->uv[1] = am->mTextureCoords[0][i].y;
    }
    if (am->mColors[0]) {
        const struct aiColor4D *c = &am->mColors[0][i];
        w->color[0] = c->r, w->color[1] = c->g, w->color[2] = c->b, w->color[3] = c->a;
    } else {
        w->color[0] = w->color[1] = w->color[2] = w->color[3] = 1.0f;
    }
}

/* The wedge of assimp vertex i into in->wedge[i] (welded vertex, deduplicated attributes). */
static lm_status corner_wedge(scene_build *b, instance *in, unsigned i)
{
    lm_wedge w;
    instance_attrs(in, i, &w);
    lm_status s = weld_vertex(b, in->pos[i], &w.vertex);
    return s ? s : find_wedge(b, &w, &in->wedge[i]);
}

/* 1 when the triangle must be dropped: corners at one position, or (unless kept) zero area. */
static int degenerate(const scene_build *b, const float *p0, const float *p1, const float *p2)
{
    if (!memcmp(p0, p1, 12) || !memcmp(p1, p2, 12) || !memcmp(p0, p2, 12))
        return 1;
    if (b->src->keep_degenerate)
        return 0;
    double u[3], v[3];
    for (int k = 0; k < 3; k++) {
        u[k] = (double)p1[k] - p0[k];
        v[k] = (double)p2[k] - p0[k];
    }
    return u[1] * v[2] - u[2] * v[1] == 0 && u[2] * v[0] - u[0] * v[2] == 0 &&
           u[0] * v[1] - u[1] * v[0] == 0;
}

/* Check face f; returns 1 in *keep when it becomes a triangle (and marks its corners used). */
static lm_status classify_face(scene_build *b, instance *in, const struct aiFace *f, uint8_t *keep)
{
    const struct aiMesh *am = in->am;
    *keep = 0;
    if (f->mNumIndices != 3 || !f->mIndices)
        return LM_OK;
    const unsigned *ix = f->mIndices;
    for (int k = 0; k < 3; k++)
        if (ix[k] >= am->mNumVertices)
            return lm_fail(LM_E_RANGE, "%s: face refers to vertex %u of %u in mesh '%s'",
                           b->src->name, ix[k], am->mNumVertices, am->mName.data);
    const float *p0 = in->pos[ix[0]], *p1 = in->pos[ix[1]], *p2 = in->pos[ix[2]];
    for (int k = 0; k < 3; k++)
        if (!isfinite(p0[k]) || !isfinite(p1[k]) || !isfinite(p2[k]))
            return lm_fail(LM_E_RANGE, "%s: a transformed vertex of mesh '%s' is not finite",
                           b->src->name, am->mName.data);
    if (degenerate(b, p0, p1, p2)) {
        b->dropped++;
        return LM_OK;
    }
    *keep = 1;
    for (int k = 0; k < 3; k++)
        in->wedge[ix[k]] = USED;
    return LM_OK;
}

static lm_status add_face(scene_build *b, instance *in, unsigned fi)
{
    const struct aiFace *f = &in->am->mFaces[fi];
    uint32_t w[3], id = LM_NONE;
    for (int k = 0; k < 3; k++)
        w[k] = in->wedge[f->mIndices[k]];
    if (in->flip) {
        uint32_t t = w[1];
        w[1] = w[2];
        w[2] = t;
    }
    lm_status s = lm_mesh_add_tri(b->m, w, in->material, &id);
    if (id != LM_NONE && id < b->m->n_tris)
        b->m->tris[id].part = in->face_part ? in->face_part[fi] : in->part;
    return s;
}

/* Faces are classified first, then the used vertices are welded in the model's vertex order (so
 * an OFF or PLY file's vertex i keeps its rank), then the triangles are added. */
static lm_status build_faces(scene_build *b, instance *in)
{
    const struct aiMesh *am = in->am;
    uint8_t *keep = malloc((size_t)am->mNumFaces + 1);
    if (!keep)
        return lm_fail(LM_E_NOMEM, "%s: out of memory for mesh '%s'", b->src->name, am->mName.data);
    lm_status s = LM_OK;
    for (unsigned f = 0; !s && f < am->mNumFaces; f++)
        s = classify_face(b, in, &am->mFaces[f], &keep[f]);
    for (unsigned i = 0; !s && i < am->mNumVertices; i++)
        if (in->wedge[i] == USED)
            s = corner_wedge(b, in, i);
    for (unsigned f = 0; !s && f < am->mNumFaces; f++)
        if (keep[f])
            s = add_face(b, in, f);
    free(keep);
    return s;
}

static lm_status instance_material(scene_build *b, unsigned index, uint32_t *out)
{
    if (index >= b->sc->mNumMaterials)
        return lm_fail(LM_E_FORMAT, "%s: mesh refers to missing material %u", b->src->name, index);
    if (b->mat_map[index] == LM_NONE) {
        lm_status s = lm_io_add_material(b->m, b->sc, index, b->src, &b->mat_map[index]);
        if (s)
            return s;
    }
    *out = b->mat_map[index];
    return LM_OK;
}

/* Parts of the faces of a lumesh PLY (one mesh, runs of faces named in its header); runs that do
 * not fit the mesh are not used. */
static lm_status face_parts(scene_build *b, instance *in)
{
    const lm_scene_source *src = b->src;
    uint64_t end = 0, faces = in->am->mNumFaces;
    for (uint32_t i = 0; i < src->n_face_parts; i++) {
        const lm_face_part *r = &src->face_parts[i];
        if (r->first != end || r->count > faces - end) /* runs in order, inside the mesh */
            return LM_OK;
        end += r->count;
    }
    if (b->instances != 1 || !src->n_face_parts || end != faces)
        return LM_OK;
    in->face_part = malloc((size_t)in->am->mNumFaces * sizeof *in->face_part);
    if (!in->face_part)
        return lm_fail(LM_E_NOMEM, "%s: out of memory for parts", src->name);
    lm_status s = LM_OK;
    for (uint32_t i = 0; !s && i < src->n_face_parts; i++) {
        const lm_face_part *r = &src->face_parts[i];
        uint32_t id;
        s = part_id(b, r->name, &id);
        for (uint64_t f = r->first; !s && f < r->first + r->count; f++)
            in->face_part[f] = id;
    }
    return s;
}

static lm_status build_instance(scene_build *b, const struct aiMesh *am, const double xf[16])
{
    if (!triangle_mesh(am))
        return LM_OK;
    instance in = {.am = am};
    char name[sizeof am->mName.data];
    node_part_name(b->sc, b->node, name, sizeof name);
    lm_status s = instance_material(b, am->mMaterialIndex, &in.material);
    if (!s && b->src->face_parts)
        s = face_parts(b, &in);
    if (!s && !in.face_part)
        s = part_id(b, name, &in.part);
    if (s) {
        free(in.face_part);
        return s;
    }
    in.pos = malloc((size_t)am->mNumVertices * sizeof *in.pos);
    in.wedge = malloc((size_t)am->mNumVertices * sizeof *in.wedge);
    if (!in.pos || !in.wedge)
        s = lm_fail(LM_E_NOMEM, "%s: out of memory for mesh '%s'", b->src->name, am->mName.data);
    if (!s) {
        memset(in.wedge, 0xff, (size_t)am->mNumVertices * sizeof *in.wedge);
        instance_transform(&in, xf);
        b->first_wedge = b->m->n_wedges;
    }
    if (!s)
        s = build_faces(b, &in);
    free(in.pos);
    free(in.wedge);
    free(in.face_part);
    return s;
}

/* ---- entry --------------------------------------------------------------------------------------
 */

static lm_status build(scene_build *b)
{
    b->all_normals = 1;
    b->visit = count_instance;
    lm_status s = walk_scene(b);
    if (s)
        return s;
    if (b->tris == 0)
        return lm_fail(LM_E_FORMAT, "%s: the model has no triangles", b->src->name);
    b->mat_map = malloc(((size_t)b->sc->mNumMaterials + 1) * sizeof *b->mat_map);
    if (!b->mat_map)
        return lm_fail(LM_E_NOMEM, "%s: out of memory", b->src->name);
    memset(b->mat_map, 0xff, ((size_t)b->sc->mNumMaterials + 1) * sizeof *b->mat_map);
    if ((s = table_init(&b->verts, 3 * b->tris, b->src->name)) ||
        (s = table_init(&b->wedges, 3 * b->tris, b->src->name)) ||
        (s = table_init(&b->parts, b->instances + b->src->n_face_parts, b->src->name)) ||
        (s = lm_mesh_create(&b->m)))
        return s;
    b->visit = build_instance;
    s = walk_scene(b);
    if (s)
        return s;
    if (b->m->live_tris == 0) /* one error line, not a warning before it */
        return lm_fail(LM_E_FORMAT,
                       "%s: the model has no triangles: all %llu of its faces are degenerate",
                       b->src->name, (unsigned long long)b->dropped);
    b->m->attrs = (b->all_normals ? LM_ATTR_NORMAL : 0) | (b->any_uv ? LM_ATTR_UV : 0) |
                  (b->any_color ? LM_ATTR_COLOR : 0);
    if (!b->all_normals)
        lm_mesh_compute_normals(b->m);
    if (b->dropped)
        lm_warn("%s: dropped %llu degenerate triangle%s", b->src->name,
                (unsigned long long)b->dropped, b->dropped == 1 ? "" : "s");
    return LM_OK;
}

lm_status lm_mesh_from_scene(const struct aiScene *sc, const lm_scene_source *src, lm_mesh **out)
{
    scene_build b = {.sc = sc, .src = src};
    lm_status s = build(&b);
    free(b.verts.slots);
    free(b.wedges.slots);
    free(b.parts.slots);
    free(b.mat_map);
    if (s) {
        lm_mesh_destroy(b.m);
        return s;
    }
    *out = b.m;
    return LM_OK;
}
