/* common/mesh_io_ply.c — binary little-endian PLY writer: one PLY vertex per wedge (position,
 * then nx ny nz, texture_u texture_v, red green blue alpha as uchar — each group only when the
 * mesh has that attribute), faces as uchar-counted uint lists. The bytes are little-endian on
 * any host. Written atomically. Materials and textures are not representable and are dropped. */
#include <math.h>
#include <string.h>

#include "common/mesh_io_internal.h"

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

static void write_header(FILE *fp, const lm_mesh *m, const lm_out_map *map)
{
    fprintf(fp, "ply\nformat binary_little_endian 1.0\ncomment lumesh\n");
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
    lm_status s = lm_out_map_build(m, &map);
    if (s)
        return s;
    lm_atomic_file f;
    if ((s = lm_atomic_open(&f, path)) != LM_OK) {
        lm_out_map_free(&map);
        return s;
    }
    FILE *fp = f.fp;
    write_header(fp, m, &map);
    uint8_t rec[64];
    for (uint32_t w = 0; w < m->n_wedges; w++)
        if (map.wedge[w] != LM_NONE)
            fwrite(rec, 1, vertex_record(m, w, rec), fp);
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        rec[0] = 3;
        for (int k = 0; k < 3; k++)
            put_u32(rec + 1 + 4 * k, map.wedge[m->tris[t].w[k]]);
        fwrite(rec, 1, 13, fp);
    }
    lm_out_map_free(&map);
    return lm_atomic_commit(&f);
}
