/* common/io/mesh_io_save.c — lm_mesh_save: picks the writer from the extension (OBJ+MTL, PLY, GLB),
 * and what every writer shares: the output numbering (dead elements, and vertices or wedges no
 * alive triangle uses, are skipped; the order of ids is kept) and the triangles grouped by part and
 * material. */
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io_internal.h"

lm_status lm_out_map_build(const lm_mesh *m, lm_out_map *map)
{
    memset(map, 0, sizeof *map);
    map->vert = malloc(((size_t)m->n_verts + 1) * sizeof *map->vert);
    map->wedge = malloc(((size_t)m->n_wedges + 1) * sizeof *map->wedge);
    if (!map->vert || !map->wedge) {
        lm_out_map_free(map);
        return lm_fail(LM_E_NOMEM, "out of memory writing a mesh");
    }
    memset(map->vert, 0xff, ((size_t)m->n_verts + 1) * sizeof *map->vert);
    memset(map->wedge, 0xff, ((size_t)m->n_wedges + 1) * sizeof *map->wedge);
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        for (int k = 0; k < 3; k++) {
            uint32_t w = m->tris[t].w[k];
            if (w >= m->n_wedges || !m->wedge_alive[w] || m->wedges[w].vertex >= m->n_verts ||
                !m->vert_alive[m->wedges[w].vertex]) {
                lm_out_map_free(map);
                return lm_fail(LM_E_INVALID,
                               "cannot write a mesh whose triangle %u refers to a "
                               "dead corner",
                               t);
            }
            map->wedge[w] = 0;
            map->vert[m->wedges[w].vertex] = 0;
        }
        map->n_tris++;
    }
    for (uint32_t v = 0; v < m->n_verts; v++)
        if (map->vert[v] != LM_NONE)
            map->vert[v] = map->n_verts++;
    for (uint32_t w = 0; w < m->n_wedges; w++)
        if (map->wedge[w] != LM_NONE)
            map->wedge[w] = map->n_wedges++;
    return LM_OK;
}

void lm_out_map_free(lm_out_map *map)
{
    free(map->vert);
    free(map->wedge);
    map->vert = map->wedge = NULL;
}

/* Group key of triangle t: part-major, then material. */
static uint64_t group_key(const lm_mesh *m, uint32_t t)
{
    uint64_t n_mat = m->n_materials ? m->n_materials : 1;
    return (uint64_t)m->tris[t].part * n_mat + m->tris[t].material;
}

typedef struct keyed_tri {
    uint64_t key;
    uint32_t t;
} keyed_tri;

static int keyed_cmp(const void *a, const void *b)
{
    const keyed_tri *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return x->t < y->t ? -1 : x->t > y->t;
}

/* The alive triangles sorted by group key, then id (n of them). */
static lm_status sort_by_group(const lm_mesh *m, uint32_t n, lm_out_groups *g)
{
    keyed_tri *k = malloc(((size_t)n + 1) * sizeof *k);
    if (!k)
        return lm_fail(LM_E_NOMEM, "out of memory grouping triangles");
    uint32_t i = 0;
    for (uint32_t t = 0; t < m->n_tris; t++)
        if (m->tri_alive[t])
            k[i++] = (keyed_tri){group_key(m, t), t};
    qsort(k, n, sizeof *k, keyed_cmp);
    for (i = 0; i < n; i++)
        g->tris[i] = k[i].t;
    free(k);
    return LM_OK;
}

/* The groups: runs of one key in the sorted order. */
static void make_groups(const lm_mesh *m, uint32_t n, lm_out_groups *g)
{
    for (uint32_t i = 0; i < n; i++) {
        const lm_tri *t = &m->tris[g->tris[i]];
        lm_out_group *last = g->n_groups ? &g->groups[g->n_groups - 1] : NULL;
        if (last && last->part == t->part && last->material == t->material) {
            last->count++;
            continue;
        }
        g->groups[g->n_groups++] = (lm_out_group){t->part, t->material, i, 1};
        if (t->part < m->n_parts && m->parts[t->part].name[0])
            g->named = 1;
    }
}

lm_status lm_out_groups_build(const lm_mesh *m, lm_out_groups *g)
{
    memset(g, 0, sizeof *g);
    uint32_t n = 0;
    for (uint32_t t = 0; t < m->n_tris; t++)
        n += m->tri_alive[t];
    g->tris = malloc(((size_t)n + 1) * sizeof *g->tris);
    g->groups = malloc(((size_t)n + 1) * sizeof *g->groups);
    lm_status s = g->tris && g->groups ? sort_by_group(m, n, g)
                                       : lm_fail(LM_E_NOMEM, "out of memory grouping triangles");
    if (s) {
        lm_out_groups_free(g);
        return s;
    }
    make_groups(m, n, g);
    return LM_OK;
}

void lm_out_groups_free(lm_out_groups *g)
{
    free(g->tris);
    free(g->groups);
    memset(g, 0, sizeof *g);
}

lm_status lm_mesh_save(const char *path, const lm_mesh *m)
{
    LM_ASSERT(path != NULL && m != NULL);
    if (m->live_tris == 0)
        return lm_fail(LM_E_INVALID, "cannot write %s: the mesh has no triangles", path);
    char ext[16];
    lm_io_path_ext(path, ext, sizeof ext);
    if (!strcmp(ext, "obj"))
        return lm_io_save_obj(path, m);
    if (!strcmp(ext, "ply"))
        return lm_io_save_ply(path, m);
    if (!strcmp(ext, "glb"))
        return lm_io_save_glb(path, m);
    return lm_fail(LM_E_INVALID, "cannot write %s: unknown extension '%s' (obj, ply, glb)", path,
                   ext);
}
