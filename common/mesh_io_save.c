/* common/mesh_io_save.c — lm_mesh_save: picks the writer from the extension (OBJ+MTL, PLY, GLB),
 * and the output numbering every writer shares (dead elements, and vertices or wedges no alive
 * triangle uses, are skipped; the order of ids is kept). */
#include <stdlib.h>
#include <string.h>

#include "common/mesh_io_internal.h"

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
