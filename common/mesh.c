/* common/mesh.c — lm_mesh storage: creation, growth, building, validation, compaction, bounds,
 * derived normals, component count and content hash. Adjacency maintenance helpers for
 * mesh_topology.c live here too (mesh_internal.h). */
#include "common/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/mesh_internal.h"
#include "common/mesh_topology.h"

/* ---- small vectors ---------------------------------------------------------------------- */

lm_status lm_u32vec_push(lm_u32vec *v, uint32_t x)
{
    if (v->n == v->cap && !LM_GROW32(&v->data, &v->cap, (size_t)v->n + 1, 8))
        return lm_fail(LM_E_NOMEM, "out of memory growing an adjacency list");
    v->data[v->n++] = x;
    return LM_OK;
}

int lm_u32vec_remove(lm_u32vec *v, uint32_t x)
{
    for (uint32_t i = 0; i < v->n; i++) {
        if (v->data[i] == x) {
            memmove(v->data + i, v->data + i + 1, (size_t)(v->n - i - 1) * sizeof *v->data);
            v->n--;
            return 1;
        }
    }
    return 0;
}

void lm_u32vec_free(lm_u32vec *v)
{
    free(v->data);
    v->data = NULL;
    v->n = v->cap = 0;
}

/* ---- life cycle ------------------------------------------------------------------------- */

lm_status lm_mesh_create(lm_mesh **out)
{
    lm_mesh *m = calloc(1, sizeof *m);
    if (!m)
        return lm_fail(LM_E_NOMEM, "out of memory creating a mesh");
    *out = m;
    return LM_OK;
}

static void internal_free(lm_mesh *m)
{
    struct lm_mesh_internal *in = m->internal;
    if (!in)
        return;
    for (uint32_t i = 0; i < in->cap_vtris; i++)
        lm_u32vec_free(&in->vtris[i]);
    free(in->vtris);
    free(in);
    m->internal = NULL;
}

void lm_mesh_destroy(lm_mesh *m)
{
    if (!m)
        return;
    internal_free(m);
    for (uint32_t i = 0; i < m->n_materials; i++) {
        free(m->materials[i].texture_path);
        lm_image_destroy(m->materials[i].texture);
        free(m->materials[i].normal_path);
        lm_image_destroy(m->materials[i].normal_map);
    }
    free(m->materials);
    free(m->parts);
    free(m->pos);
    free(m->vert_alive);
    free(m->wedges);
    free(m->wedge_alive);
    free(m->tris);
    free(m->tri_alive);
    free(m);
}

lm_status lm_mesh_internal_ensure(lm_mesh *m)
{
    if (m->internal)
        return LM_OK;
    m->internal = calloc(1, sizeof *m->internal);
    return m->internal ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory");
}

/* Grow an array pair (elements + alive flags) to hold at least `need` slots. */
static lm_status grow(void **arr, size_t elem, uint8_t **alive, uint32_t *cap, uint32_t need,
                      uint32_t limit)
{
    if (need <= *cap)
        return LM_OK;
    if (need > limit)
        return lm_fail(LM_E_RANGE, "mesh too large (%u elements, limit %u)", need, limit);
    size_t c = lm_grow_cap(*cap, need, 64, limit);
    if (!lm_resize(arr, c, elem))
        return lm_fail(LM_E_NOMEM, "out of memory growing a mesh to %llu elements",
                       (unsigned long long)c);
    if (!LM_RESIZE(alive, c))
        return lm_fail(LM_E_NOMEM, "out of memory growing a mesh");
    *cap = (uint32_t)c;
    return LM_OK;
}

/* ---- building ----------------------------------------------------------------------------- */

lm_status lm_mesh_add_vertex(lm_mesh *m, const float p[3], uint32_t *out_id)
{
    lm_status s = grow((void **)&m->pos, sizeof *m->pos, &m->vert_alive, &m->cap_verts,
                       m->n_verts + 1, LM_MESH_MAX_VERTS);
    if (s)
        return s;
    uint32_t id = m->n_verts++;
    memcpy(m->pos[id], p, sizeof m->pos[id]);
    m->vert_alive[id] = 1;
    m->live_verts++;
    if (out_id)
        *out_id = id;
    return LM_OK;
}

lm_status lm_mesh_add_wedge(lm_mesh *m, const lm_wedge *w, uint32_t *out_id)
{
    if (w->vertex >= m->n_verts || !m->vert_alive[w->vertex])
        return lm_fail(LM_E_RANGE, "wedge refers to vertex %u of %u", w->vertex, m->n_verts);
    lm_status s = grow((void **)&m->wedges, sizeof *m->wedges, &m->wedge_alive, &m->cap_wedges,
                       m->n_wedges + 1, LM_MESH_MAX_VERTS * 4u);
    if (s)
        return s;
    uint32_t id = m->n_wedges++;
    m->wedges[id] = *w;
    m->wedge_alive[id] = 1;
    if (out_id)
        *out_id = id;
    return LM_OK;
}

lm_status lm_mesh_add_tri(lm_mesh *m, const uint32_t w[3], uint32_t material, uint32_t *out_id)
{
    for (int k = 0; k < 3; k++)
        if (w[k] >= m->n_wedges || !m->wedge_alive[w[k]])
            return lm_fail(LM_E_RANGE, "triangle refers to wedge %u of %u", w[k], m->n_wedges);
    if (m->n_materials && material >= m->n_materials)
        return lm_fail(LM_E_RANGE, "triangle refers to material %u of %u", material,
                       m->n_materials);
    lm_status s = grow((void **)&m->tris, sizeof *m->tris, &m->tri_alive, &m->cap_tris,
                       m->n_tris + 1, LM_MESH_MAX_TRIS);
    if (s)
        return s;
    uint32_t id = m->n_tris++;
    memcpy(m->tris[id].w, w, sizeof m->tris[id].w);
    m->tris[id].material = material;
    m->tris[id].part = 0;
    m->tri_alive[id] = 1;
    m->live_tris++;
    s = lm_mesh_adj_link_tri(m, id);
    if (out_id)
        *out_id = id;
    return s;
}

lm_status lm_mesh_add_material(lm_mesh *m, const char *name, const float diffuse[4],
                               const char *texture_path, lm_image *tex, uint32_t *out_id)
{
    lm_material *a = realloc(m->materials, (size_t)(m->n_materials + 1) * sizeof *a);
    if (!a)
        return lm_fail(LM_E_NOMEM, "out of memory adding a material");
    m->materials = a;
    lm_material *mat = &a[m->n_materials];
    memset(mat, 0, sizeof *mat);
    if (name)
        snprintf(mat->name, sizeof mat->name, "%s", name);
    static const float white[4] = {1, 1, 1, 1};
    memcpy(mat->diffuse, diffuse ? diffuse : white, sizeof mat->diffuse);
    if (texture_path) {
        mat->texture_path = strdup(texture_path);
        if (!mat->texture_path)
            return lm_fail(LM_E_NOMEM, "out of memory adding a material");
    }
    mat->texture = tex;
    if (out_id)
        *out_id = m->n_materials;
    m->n_materials++;
    return LM_OK;
}

lm_status lm_mesh_set_normal_map(lm_mesh *m, uint32_t mat, const char *path, lm_image *img)
{
    if (mat >= m->n_materials) {
        lm_image_destroy(img);
        return lm_fail(LM_E_RANGE, "normal map for material %u of %u", mat, m->n_materials);
    }
    char *copy = path ? strdup(path) : NULL;
    if (path && !copy) {
        lm_image_destroy(img);
        return lm_fail(LM_E_NOMEM, "out of memory adding a normal map");
    }
    lm_material *a = &m->materials[mat];
    free(a->normal_path);
    lm_image_destroy(a->normal_map);
    a->normal_path = copy;
    a->normal_map = img;
    return LM_OK;
}

lm_status lm_mesh_add_part(lm_mesh *m, const char *name, uint32_t *out_id)
{
    char cut[LM_PART_NAME_MAX];
    snprintf(cut, sizeof cut, "%s", name ? name : "");
    if (m->n_parts >= LM_MESH_MAX_TRIS)
        return lm_fail(LM_E_RANGE, "more than %u parts", LM_MESH_MAX_TRIS);
    lm_part *a = realloc(m->parts, (size_t)(m->n_parts + 1) * sizeof *a);
    if (!a)
        return lm_fail(LM_E_NOMEM, "out of memory adding a part");
    m->parts = a;
    memcpy(a[m->n_parts].name, cut, sizeof cut);
    *out_id = m->n_parts++;
    return LM_OK;
}

uint32_t lm_mesh_find_part(const lm_mesh *m, const char *name)
{
    char cut[LM_PART_NAME_MAX];
    snprintf(cut, sizeof cut, "%s", name ? name : "");
    for (uint32_t i = 0; i < m->n_parts; i++)
        if (strcmp(m->parts[i].name, cut) == 0)
            return i;
    return LM_NONE;
}

lm_status lm_mesh_copy_parts(const lm_mesh *src, lm_mesh *dst)
{
    if (!src->n_parts)
        return LM_OK;
    lm_part *a = malloc((size_t)src->n_parts * sizeof *a);
    if (!a)
        return lm_fail(LM_E_NOMEM, "out of memory copying parts");
    memcpy(a, src->parts, (size_t)src->n_parts * sizeof *a);
    free(dst->parts);
    dst->parts = a;
    dst->n_parts = src->n_parts;
    return LM_OK;
}

uint32_t lm_mesh_count_parts(const lm_mesh *m)
{
    if (m->n_parts == 0)
        return m->live_tris ? 1 : 0;
    uint8_t *used = calloc(m->n_parts, 1);
    if (!used)
        return 0;
    uint32_t n = 0;
    for (uint32_t t = 0; t < m->n_tris; t++)
        if (m->tri_alive[t] && m->tris[t].part < m->n_parts && !used[m->tris[t].part]) {
            used[m->tris[t].part] = 1;
            n++;
        }
    free(used);
    return n;
}

const char *lm_mesh_part_name(const lm_mesh *m, uint32_t t)
{
    uint32_t p = m->tris[t].part;
    return p < m->n_parts ? m->parts[p].name : "";
}

/* ---- adjacency maintenance (used when adjacency has been built) --------------------------- */

static lm_status vtris_reserve(struct lm_mesh_internal *in, uint32_t n_verts)
{
    if (n_verts <= in->cap_vtris)
        return LM_OK;
    size_t cap = lm_grow_cap(in->cap_vtris, n_verts, 64, UINT32_MAX);
    if (!LM_RESIZE(&in->vtris, cap))
        return lm_fail(LM_E_NOMEM, "out of memory growing adjacency");
    memset(in->vtris + in->cap_vtris, 0, (cap - in->cap_vtris) * sizeof *in->vtris);
    in->cap_vtris = (uint32_t)cap;
    return LM_OK;
}

/* Insert keeping the list ascending (ids of new triangles are usually the largest). */
static lm_status sorted_insert(lm_u32vec *v, uint32_t t)
{
    lm_status s = lm_u32vec_push(v, t);
    if (s)
        return s;
    uint32_t i = v->n - 1;
    while (i > 0 && v->data[i - 1] > t) {
        v->data[i] = v->data[i - 1];
        i--;
    }
    v->data[i] = t;
    return LM_OK;
}

lm_status lm_mesh_adj_reserve(lm_mesh *m, uint32_t n_verts)
{
    lm_status s = lm_mesh_internal_ensure(m);
    return s ? s : vtris_reserve(m->internal, n_verts);
}

lm_status lm_mesh_adj_link_tri(lm_mesh *m, uint32_t t)
{
    struct lm_mesh_internal *in = m->internal;
    if (!in || !in->adjacency_built)
        return LM_OK;
    lm_status s = vtris_reserve(in, m->n_verts);
    for (int k = 0; k < 3 && !s; k++) {
        uint32_t v = lm_tri_vertex(m, t, k);
        int dup = 0;
        for (int j = 0; j < k; j++)
            dup |= lm_tri_vertex(m, t, j) == v;
        if (!dup)
            s = sorted_insert(&in->vtris[v], t);
    }
    return s;
}

void lm_mesh_adj_unlink_tri(lm_mesh *m, uint32_t t)
{
    struct lm_mesh_internal *in = m->internal;
    if (!in || !in->adjacency_built)
        return;
    for (int k = 0; k < 3; k++) {
        uint32_t v = lm_tri_vertex(m, t, k);
        if (v < in->cap_vtris)
            lm_u32vec_remove(&in->vtris[v], t);
    }
}

/* ---- copy ----------------------------------------------------------------------------------- */

lm_status lm_mesh_copy_materials(const lm_mesh *src, lm_mesh *dst)
{
    for (uint32_t i = 0; i < src->n_materials; i++) {
        const lm_material *mat = &src->materials[i];
        lm_image *tex = NULL;
        if (mat->texture) {
            lm_status s = lm_image_clone(mat->texture, &tex);
            if (s)
                return s;
        }
        lm_status s =
            lm_mesh_add_material(dst, mat->name, mat->diffuse, mat->texture_path, tex, NULL);
        if (s) {
            lm_image_destroy(tex);
            return s;
        }
        lm_image *nrm = NULL;
        if (mat->normal_map && (s = lm_image_clone(mat->normal_map, &nrm)))
            return s;
        if ((mat->normal_map || mat->normal_path) &&
            (s = lm_mesh_set_normal_map(dst, dst->n_materials - 1, mat->normal_path, nrm)))
            return s;
    }
    return LM_OK;
}

/* dst[0..n) := src[0..n), dst grown (realloc) to hold them. */
static lm_status copy_into(void **dst, uint32_t *cap, const void *src, uint32_t n, size_t elem)
{
    if (n > *cap) {
        void *p = realloc(*dst, (size_t)n * elem);
        if (!p)
            return lm_fail(LM_E_NOMEM, "out of memory copying a mesh");
        *dst = p;
        *cap = n;
    }
    if (n)
        memcpy(*dst, src, (size_t)n * elem);
    return LM_OK;
}

/* The flags arrays share the element arrays' capacities; grown alongside. */
static lm_status copy_flags(uint8_t **dst, uint32_t cap, const uint8_t *src, uint32_t n)
{
    uint8_t *p = realloc(*dst, cap ? cap : 1);
    if (!p)
        return lm_fail(LM_E_NOMEM, "out of memory copying a mesh");
    *dst = p;
    if (n)
        memcpy(p, src, n);
    return LM_OK;
}

static lm_status copy_adjacency(lm_mesh *dst, const lm_mesh *src)
{
    const struct lm_mesh_internal *si = src->internal;
    if (!si || !si->adjacency_built)
        return LM_OK;
    lm_status s = lm_mesh_adj_reserve(dst, src->n_verts);
    for (uint32_t v = 0; v < dst->internal->cap_vtris && !s; v++) {
        lm_u32vec *d = &dst->internal->vtris[v];
        d->n = 0;
        const lm_u32vec *from = v < si->cap_vtris && v < src->n_verts ? &si->vtris[v] : NULL;
        for (uint32_t i = 0; from && i < from->n && !s; i++)
            s = lm_u32vec_push(d, from->data[i]);
    }
    if (!s)
        dst->internal->adjacency_built = 1;
    return s;
}

/* Names and colours only: a copy for topology work has no use for textures. */
static lm_status copy_material_names(lm_mesh *dst, const lm_mesh *src)
{
    if (dst->n_materials == src->n_materials)
        return LM_OK;
    for (uint32_t i = 0; i < dst->n_materials; i++) {
        free(dst->materials[i].texture_path);
        lm_image_destroy(dst->materials[i].texture);
        free(dst->materials[i].normal_path);
        lm_image_destroy(dst->materials[i].normal_map);
    }
    dst->n_materials = 0;
    lm_status s = LM_OK;
    for (uint32_t i = 0; i < src->n_materials && !s; i++)
        s = lm_mesh_add_material(dst, src->materials[i].name, src->materials[i].diffuse, NULL, NULL,
                                 NULL);
    return s;
}

lm_status lm_mesh_copy_geometry(lm_mesh *dst, const lm_mesh *src)
{
    lm_status s =
        copy_into((void **)&dst->pos, &dst->cap_verts, src->pos, src->n_verts, sizeof *src->pos);
    if (!s)
        s = copy_flags(&dst->vert_alive, dst->cap_verts, src->vert_alive, src->n_verts);
    if (!s)
        s = copy_into((void **)&dst->wedges, &dst->cap_wedges, src->wedges, src->n_wedges,
                      sizeof *src->wedges);
    if (!s)
        s = copy_flags(&dst->wedge_alive, dst->cap_wedges, src->wedge_alive, src->n_wedges);
    if (!s)
        s = copy_into((void **)&dst->tris, &dst->cap_tris, src->tris, src->n_tris,
                      sizeof *src->tris);
    if (!s)
        s = copy_flags(&dst->tri_alive, dst->cap_tris, src->tri_alive, src->n_tris);
    if (s)
        return s;
    dst->n_verts = src->n_verts;
    dst->n_wedges = src->n_wedges;
    dst->n_tris = src->n_tris;
    dst->live_verts = src->live_verts;
    dst->live_tris = src->live_tris;
    dst->attrs = src->attrs;
    s = copy_material_names(dst, src);
    if (!s && dst->n_parts != src->n_parts) {
        free(dst->parts);
        dst->parts = NULL;
        dst->n_parts = 0;
        s = lm_mesh_copy_parts(src, dst);
    }
    return s ? s : copy_adjacency(dst, src);
}

static void *dup_array(const void *src, size_t bytes, lm_status *s)
{
    if (!bytes)
        return NULL;
    void *d = malloc(bytes);
    if (!d)
        *s = lm_fail(LM_E_NOMEM, "out of memory copying a mesh");
    else
        memcpy(d, src, bytes);
    return d;
}

lm_status lm_mesh_clone(const lm_mesh *src, lm_mesh **out)
{
    lm_mesh *m = NULL;
    lm_status s = lm_mesh_create(&m);
    if (s)
        return s;
    m->n_verts = m->cap_verts = src->n_verts;
    m->n_wedges = m->cap_wedges = src->n_wedges;
    m->n_tris = m->cap_tris = src->n_tris;
    m->live_verts = src->live_verts;
    m->live_tris = src->live_tris;
    m->attrs = src->attrs;
    m->pos = dup_array(src->pos, src->n_verts * sizeof *src->pos, &s);
    m->vert_alive = dup_array(src->vert_alive, src->n_verts, &s);
    m->wedges = dup_array(src->wedges, src->n_wedges * sizeof *src->wedges, &s);
    m->wedge_alive = dup_array(src->wedge_alive, src->n_wedges, &s);
    m->tris = dup_array(src->tris, src->n_tris * sizeof *src->tris, &s);
    m->tri_alive = dup_array(src->tri_alive, src->n_tris, &s);
    if (!s)
        s = lm_mesh_copy_materials(src, m);
    if (!s)
        s = lm_mesh_copy_parts(src, m);
    if (!s && src->internal && src->internal->adjacency_built)
        s = lm_mesh_build_adjacency(m);
    if (s) {
        lm_mesh_destroy(m);
        return s;
    }
    *out = m;
    return LM_OK;
}

/* ---- validation ------------------------------------------------------------------------------ */

static int finite3(const float *p)
{
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

static lm_status validate_wedges(const lm_mesh *m)
{
    for (uint32_t i = 0; i < m->n_wedges; i++) {
        if (!m->wedge_alive[i])
            continue;
        const lm_wedge *w = &m->wedges[i];
        if (w->vertex >= m->n_verts || !m->vert_alive[w->vertex])
            return lm_fail(LM_E_RANGE, "wedge %u refers to missing vertex %u", i, w->vertex);
        if (!finite3(w->normal) || !isfinite(w->uv[0]) || !isfinite(w->uv[1]) ||
            !finite3(w->color) || !isfinite(w->color[3]))
            return lm_fail(LM_E_RANGE, "attribute of vertex %u is not a finite number", w->vertex);
    }
    return LM_OK;
}

static lm_status validate_tris(const lm_mesh *m)
{
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        for (int k = 0; k < 3; k++) {
            uint32_t w = m->tris[t].w[k];
            if (w >= m->n_wedges || !m->wedge_alive[w])
                return lm_fail(LM_E_RANGE, "triangle %u refers to missing corner %u", t, w);
        }
        uint32_t a = lm_tri_vertex(m, t, 0), b = lm_tri_vertex(m, t, 1), c = lm_tri_vertex(m, t, 2);
        if (a == b || b == c || a == c)
            return lm_fail(LM_E_FORMAT, "triangle %u repeats a vertex", t);
        if (m->n_materials ? m->tris[t].material >= m->n_materials : m->tris[t].material != 0)
            return lm_fail(LM_E_RANGE, "triangle %u refers to missing material %u", t,
                           m->tris[t].material);
        if (m->n_parts ? m->tris[t].part >= m->n_parts : m->tris[t].part != 0)
            return lm_fail(LM_E_RANGE, "triangle %u refers to missing part %u", t, m->tris[t].part);
    }
    return LM_OK;
}

lm_status lm_mesh_validate(const lm_mesh *m)
{
    if (m->live_tris == 0)
        return lm_fail(LM_E_FORMAT, "the mesh has no triangles");
    for (uint32_t v = 0; v < m->n_verts; v++)
        if (m->vert_alive[v] && !finite3(m->pos[v]))
            return lm_fail(LM_E_RANGE, "vertex %u has a coordinate that is not a finite number", v);
    lm_status s = validate_wedges(m);
    return s ? s : validate_tris(m);
}

/* ---- compaction ------------------------------------------------------------------------------ */

/* Renumber alive entries of one array in place; fills map[old] = new (LM_NONE if dead). */
static uint32_t compact_array(void *arr, size_t elem, uint8_t *alive, uint32_t n, uint32_t *map)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (!alive[i]) {
            map[i] = LM_NONE;
            continue;
        }
        map[i] = k;
        if (k != i)
            memmove((char *)arr + (size_t)k * elem, (char *)arr + (size_t)i * elem, elem);
        alive[k++] = 1;
    }
    return k;
}

lm_status lm_mesh_compact(lm_mesh *m)
{
    uint32_t big = m->n_verts > m->n_wedges ? m->n_verts : m->n_wedges;
    uint32_t *map = malloc(((size_t)big + 1) * sizeof *map);
    uint32_t *tmap = malloc(((size_t)m->n_tris + 1) * sizeof *tmap);
    if (!map || !tmap) {
        free(map);
        free(tmap);
        return lm_fail(LM_E_NOMEM, "out of memory compacting a mesh");
    }
    m->n_verts = compact_array(m->pos, sizeof *m->pos, m->vert_alive, m->n_verts, map);
    for (uint32_t i = 0; i < m->n_wedges; i++)
        if (m->wedge_alive[i])
            m->wedges[i].vertex = map[m->wedges[i].vertex];
    m->n_wedges = compact_array(m->wedges, sizeof *m->wedges, m->wedge_alive, m->n_wedges, map);
    m->n_tris = compact_array(m->tris, sizeof *m->tris, m->tri_alive, m->n_tris, tmap);
    for (uint32_t t = 0; t < m->n_tris; t++)
        for (int k = 0; k < 3; k++)
            m->tris[t].w[k] = map[m->tris[t].w[k]];
    free(map);
    free(tmap);
    m->live_verts = m->n_verts;
    m->live_tris = m->n_tris;
    int had_adjacency = m->internal && m->internal->adjacency_built;
    internal_free(m);
    return had_adjacency ? lm_mesh_build_adjacency(m) : LM_OK;
}

/* ---- geometry ----------------------------------------------------------------------------------
 */

void lm_mesh_bounds(const lm_mesh *m, float lo[3], float hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (uint32_t v = 0; v < m->n_verts; v++) {
        if (!m->vert_alive[v])
            continue;
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], m->pos[v][k]);
            hi[k] = fmaxf(hi[k], m->pos[v][k]);
        }
    }
    if (lo[0] > hi[0])
        for (int k = 0; k < 3; k++)
            lo[k] = hi[k] = 0;
}

void lm_mesh_bounding_sphere(const lm_mesh *m, float centre[3], float *radius)
{
    float lo[3], hi[3];
    lm_mesh_bounds(m, lo, hi);
    for (int k = 0; k < 3; k++)
        centre[k] = 0.5f * (lo[k] + hi[k]);
    double r2 = 0;
    for (uint32_t v = 0; v < m->n_verts; v++) {
        if (!m->vert_alive[v])
            continue;
        double d = 0;
        for (int k = 0; k < 3; k++)
            d += ((double)m->pos[v][k] - centre[k]) * ((double)m->pos[v][k] - centre[k]);
        if (d > r2)
            r2 = d;
    }
    *radius = r2 > 0 ? (float)sqrt(r2) : 1.0f;
}

/* Face normal scaled by twice the triangle area. */
void lm_mesh_face_normal(const lm_mesh *m, uint32_t t, double n[3])
{
    const float *a = m->pos[lm_tri_vertex(m, t, 0)];
    const float *b = m->pos[lm_tri_vertex(m, t, 1)];
    const float *c = m->pos[lm_tri_vertex(m, t, 2)];
    double u[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = (double)b[k] - a[k];
        w[k] = (double)c[k] - a[k];
    }
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
}

void lm_mesh_compute_normals(lm_mesh *m)
{
    double *acc = calloc((size_t)m->n_verts * 3 + 3, sizeof *acc);
    LM_ASSERT(acc != NULL);
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        double n[3];
        lm_mesh_face_normal(m, t, n);
        for (int k = 0; k < 3; k++) {
            double *a = acc + (size_t)lm_tri_vertex(m, t, k) * 3;
            a[0] += n[0];
            a[1] += n[1];
            a[2] += n[2];
        }
    }
    for (uint32_t i = 0; i < m->n_wedges; i++) {
        if (!m->wedge_alive[i])
            continue;
        const double *a = acc + (size_t)m->wedges[i].vertex * 3;
        double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        for (int k = 0; k < 3; k++)
            m->wedges[i].normal[k] = len > 0 ? (float)(a[k] / len) : (k == 2 ? 1.0f : 0.0f);
    }
    free(acc);
}

/* ---- components and hash -----------------------------------------------------------------------
 */

static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

uint32_t lm_mesh_count_components(const lm_mesh *m)
{
    uint32_t *parent = malloc(((size_t)m->n_verts + 1) * sizeof *parent);
    LM_ASSERT(parent != NULL);
    for (uint32_t v = 0; v < m->n_verts; v++)
        parent[v] = v;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        uint32_t r0 = uf_find(parent, lm_tri_vertex(m, t, 0));
        for (int k = 1; k < 3; k++) {
            uint32_t r = uf_find(parent, lm_tri_vertex(m, t, k));
            if (r != r0)
                parent[r] = r0;
        }
    }
    uint8_t *used = calloc((size_t)m->n_verts + 1, 1);
    LM_ASSERT(used != NULL);
    uint32_t count = 0;
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        uint32_t r = uf_find(parent, lm_tri_vertex(m, t, 0));
        if (!used[r]) {
            used[r] = 1;
            count++;
        }
    }
    free(used);
    free(parent);
    return count;
}

/* n bytes at p (a record's raw bytes) as one 64-bit word: 8 bytes at a time (a 4-byte tail, then
 * single bytes), each word mixed in (the records are short; the chain over them is the caller's).
 */
static inline uint64_t record_word(const void *p, size_t n)
{
    const uint8_t *b = p;
    uint64_t acc = 0x9e3779b97f4a7c15ull ^ n, w;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        memcpy(&w, b + i, 8);
        acc = (acc ^ w) * 0xff51afd7ed558ccdull;
        acc ^= acc >> 29;
    }
    for (; i < n; i += 4) {
        uint32_t u = 0;
        memcpy(&u, b + i, n - i < 4 ? n - i : 4);
        acc = (acc ^ u) * 0xff51afd7ed558ccdull;
        acc ^= acc >> 29;
    }
    return acc;
}

/* One record (alive flag, and its bytes when alive) into the hash. */
static inline uint64_t mix_record(uint64_t h, uint8_t alive, const void *p, size_t n)
{
    uint64_t w = alive ? record_word(p, n) ^ ((uint64_t)alive << 56) : (uint64_t)alive;
    h = (h ^ w) * 0xc4ceb9fe1a85ec53ull;
    return h ^ (h >> 31);
}

uint64_t lm_mesh_hash(const lm_mesh *m)
{
    const uint32_t head[5] = {m->n_verts, m->n_wedges, m->n_tris, m->live_verts, m->live_tris};
    uint64_t h = record_word(head, sizeof head);
    for (uint32_t v = 0; v < m->n_verts; v++)
        h = mix_record(h, m->vert_alive[v], m->pos[v], sizeof m->pos[v]);
    for (uint32_t i = 0; i < m->n_wedges; i++)
        h = mix_record(h, m->wedge_alive[i], &m->wedges[i], sizeof m->wedges[i]);
    for (uint32_t t = 0; t < m->n_tris; t++)
        h = mix_record(h, m->tri_alive[t], &m->tris[t], sizeof m->tris[t]);
    return h;
}
