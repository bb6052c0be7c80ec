/* common/io/mesh_io_ply.c — binary little-endian PLY writer: one PLY vertex per wedge (position,
 * then nx ny nz, texture_u texture_v, red green blue alpha as uchar — each group only when the
 * mesh has that attribute), faces as uchar-counted uint lists. The bytes are little-endian on
 * any host. Written atomically. Materials and textures are not representable and are dropped.
 * Faces come part by part; named parts are listed in header comments (mesh_io_ply_parts.c). */
#include <math.h>
#include <string.h>

#include "common/io/mesh_io_internal.h"

static void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8), p[2] = (uint8_t)(v >> 16),
    p[3] = (uint8_t)(v >> 24);
}

static void put_f32(uint8_t *p, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    put_u32(p, v);
}

static uint8_t to_u8(float c)
{
    float x = roundf(c * 255.0f);
    return (uint8_t)(x <= 0 ? 0 : x >= 255 ? 255 : x);
}

/* "comment lumesh part" lines: one per run of a part's faces, when some part has a name. */
static void write_parts(FILE *fp, const lm_mesh *m, const lm_out_groups *g)
{
    for (uint32_t i = 0; g->named && i < g->n_groups;) {
        uint32_t j = i, part = g->groups[i].part;
        uint64_t count = 0;
        for (; j < g->n_groups && g->groups[j].part == part; j++)
            count += g->groups[j].count;
        lm_io_ply_write_part(fp, g->groups[i].first, count,
                             part < m->n_parts ? m->parts[part].name : "");
        i = j;
    }
}

static void write_header(FILE *fp, const lm_mesh *m, const lm_out_map *map, const lm_out_groups *g)
{
    fprintf(fp, "ply\nformat binary_little_endian 1.0\ncomment lumesh\n");
    write_parts(fp, m, g);
    fprintf(fp, "element vertex %u\nproperty float x\nproperty float y\nproperty float z\n",
            map->n_wedges);
    if (m->attrs & LM_ATTR_NORMAL)
        fprintf(fp, "property float nx\nproperty float ny\nproperty float nz\n");
    if (m->attrs & LM_ATTR_UV)
        fprintf(fp, "property float texture_u\nproperty float texture_v\n");
    if (m->attrs & LM_ATTR_COLOR)
        fprintf(fp, "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                    "property uchar alpha\n");
    fprintf(fp, "element face %u\nproperty list uchar uint vertex_indices\nend_header\n",
            map->n_tris);
}

/* One vertex record into rec; returns its size. */
static size_t vertex_record(const lm_mesh *m, uint32_t w, uint8_t rec[64])
{
    const lm_wedge *wd = &m->wedges[w];
    size_t n = 0;
    for (int k = 0; k < 3; k++, n += 4)
        put_f32(rec + n, m->pos[wd->vertex][k]);
    for (int k = 0; (m->attrs & LM_ATTR_NORMAL) && k < 3; k++, n += 4)
        put_f32(rec + n, wd->normal[k]);
    for (int k = 0; (m->attrs & LM_ATTR_UV) && k < 2; k++, n += 4)
        put_f32(rec + n, wd->uv[k]);
    for (int k = 0; (m->attrs & LM_ATTR_COLOR) && k < 4; k++)
        rec[n++] = to_u8(wd->color[k]);
    return n;
}

lm_status lm_io_save_ply(const char *path, const lm_mesh *m)
{
    lm_out_map map;
    lm_out_groups groups;
    lm_status s = lm_out_map_build(m, &map);
    if (s)
        return s;
    lm_atomic_file f;
    if ((s = lm_out_groups_build(m, &groups)) != LM_OK || (s = lm_atomic_open(&f, path)) != LM_OK) {
        lm_out_map_free(&map);
        lm_out_groups_free(&groups);
        return s;
    }
    FILE *fp = f.fp;
    write_header(fp, m, &map, &groups);
    uint8_t rec[64];
    for (uint32_t w = 0; w < m->n_wedges; w++)
        if (map.wedge[w] != LM_NONE)
            fwrite(rec, 1, vertex_record(m, w, rec), fp);
    for (uint32_t i = 0; i < map.n_tris; i++) {
        uint32_t t = groups.tris[i];
        rec[0] = 3;
        for (int k = 0; k < 3; k++)
            put_u32(rec + 1 + 4 * k, map.wedge[m->tris[t].w[k]]);
        fwrite(rec, 1, 13, fp);
    }
    lm_out_map_free(&map);
    lm_out_groups_free(&groups);
    return lm_atomic_commit(&f);
}
