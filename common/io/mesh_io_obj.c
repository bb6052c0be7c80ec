/* common/io/mesh_io_obj.c — Wavefront OBJ + MTL writer. Positions are written once per vertex, or
 * once per wedge as extended "v x y z r g b" lines when the mesh has colours (OBJ binds colour
 * to the position); "vt" and "vn" once per wedge; faces as v/vt/vn triples grouped by part (an
 * "o NAME" line each, the unnamed part first and without one) and within a part by material.
 * Each material's decoded texture is written beside the OBJ as "<stem>_<material>.png", its normal
 * map as "<stem>_<material>_normal.png" (MTL "norm", which assimp reads as a normal map). Every
 * file is written atomically; when any fails, the ones already written are removed. Numbers
 * use %.9g, which round-trips 32-bit floats exactly. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/io/mesh_io_internal.h"

typedef struct obj_names {
    char *mtl_path; /* "<stem>.mtl" */
    char *stem;     /* path without ".obj" */
    char **tex;     /* [2 n_materials] texture, then normal map paths written, or NULL */
    uint32_t n;
    int mtl_written;
} obj_names;

static void names_free(obj_names *nm, int remove_files)
{
    if (remove_files && nm->mtl_written)
        unlink(nm->mtl_path);
    for (uint32_t i = 0; nm->tex && i < nm->n; i++) {
        if (remove_files && nm->tex[i])
            unlink(nm->tex[i]);
        free(nm->tex[i]);
    }
    free(nm->tex);
    free(nm->mtl_path);
    free(nm->stem);
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

static void sanitize(const char *name, char out[64])
{
    snprintf(out, 64, "%s", name);
    for (char *c = out; *c; c++)
        if ((unsigned char)*c <= ' ' || *c == '#' || *c == 127)
            *c = '_';
}

/* OBJ/MTL-safe unique material name: the material's own when usable and unique, else
 * "material_<i>" (names of that form are never taken from materials). */
static void material_name(const lm_mesh *m, uint32_t i, char out[64])
{
    char other[64];
    sanitize(m->materials[i].name, out);
    int ok = out[0] != '\0' && strncmp(out, "material_", 9) != 0;
    for (uint32_t j = 0; ok && j < m->n_materials; j++) {
        sanitize(m->materials[j].name, other);
        ok = j == i || strcmp(other, out) != 0;
    }
    if (!ok)
        snprintf(out, 64, "material_%u", i);
}

/* Write the textures and normal maps (PNG beside the OBJ), remembering their paths in nm->tex. */
static lm_status write_textures(const lm_mesh *m, obj_names *nm)
{
    for (uint32_t j = 0; j < 2 * m->n_materials; j++) {
        uint32_t i = j % m->n_materials;
        const lm_image *img =
            j < m->n_materials ? m->materials[i].texture : m->materials[i].normal_map;
        if (!img)
            continue;
        size_t n = strlen(nm->stem) + 32;
        if (!(nm->tex[j] = malloc(n)))
            return lm_fail(LM_E_NOMEM, "out of memory writing textures");
        snprintf(nm->tex[j], n, j < m->n_materials ? "%s_%u.png" : "%s_%u_normal.png", nm->stem, i);
        lm_status s = lm_image_write(nm->tex[j], img);
        if (s) {
            free(nm->tex[j]);
            nm->tex[j] = NULL;
            return s;
        }
    }
    return LM_OK;
}

static lm_status write_mtl(const lm_mesh *m, obj_names *nm)
{
    lm_atomic_file f;
    lm_status s = lm_atomic_open(&f, nm->mtl_path);
    if (s)
        return s;
    FILE *fp = f.fp;
    fprintf(fp, "# lumesh\n");
    for (uint32_t i = 0; i < m->n_materials; i++) {
        const lm_material *mat = &m->materials[i];
        char name[64];
        material_name(m, i, name);
        fprintf(fp, "\nnewmtl %s\nKa 0 0 0\nKd %.9g %.9g %.9g\nKs 0 0 0\nd %.9g\nillum 1\n", name,
                mat->diffuse[0], mat->diffuse[1], mat->diffuse[2], mat->diffuse[3]);
        if (nm->tex[i])
            fprintf(fp, "map_Kd %s\n", base_name(nm->tex[i]));
        if (nm->tex[m->n_materials + i])
            fprintf(fp, "norm %s\n", base_name(nm->tex[m->n_materials + i]));
    }
    s = lm_atomic_commit(&f);
    nm->mtl_written = s == LM_OK;
    return s;
}

static void write_vertices(FILE *fp, const lm_mesh *m, const lm_out_map *map)
{
    if (m->attrs & LM_ATTR_COLOR) {
        for (uint32_t w = 0; w < m->n_wedges; w++) {
            if (map->wedge[w] == LM_NONE)
                continue;
            const float *p = m->pos[m->wedges[w].vertex], *c = m->wedges[w].color;
            fprintf(fp, "v %.9g %.9g %.9g %.9g %.9g %.9g\n", p[0], p[1], p[2], c[0], c[1], c[2]);
        }
    } else {
        for (uint32_t v = 0; v < m->n_verts; v++)
            if (map->vert[v] != LM_NONE)
                fprintf(fp, "v %.9g %.9g %.9g\n", m->pos[v][0], m->pos[v][1], m->pos[v][2]);
    }
    for (uint32_t w = 0; (m->attrs & LM_ATTR_UV) && w < m->n_wedges; w++)
        if (map->wedge[w] != LM_NONE)
            fprintf(fp, "vt %.9g %.9g\n", m->wedges[w].uv[0], m->wedges[w].uv[1]);
    for (uint32_t w = 0; (m->attrs & LM_ATTR_NORMAL) && w < m->n_wedges; w++)
        if (map->wedge[w] != LM_NONE)
            fprintf(fp, "vn %.9g %.9g %.9g\n", m->wedges[w].normal[0], m->wedges[w].normal[1],
                    m->wedges[w].normal[2]);
}

static void write_corner(FILE *fp, const lm_mesh *m, const lm_out_map *map, uint32_t w)
{
    uint32_t v = 1 + (m->attrs & LM_ATTR_COLOR ? map->wedge[w] : map->vert[m->wedges[w].vertex]);
    uint32_t a = 1 + map->wedge[w];
    if ((m->attrs & LM_ATTR_UV) && (m->attrs & LM_ATTR_NORMAL))
        fprintf(fp, " %u/%u/%u", v, a, a);
    else if (m->attrs & LM_ATTR_UV)
        fprintf(fp, " %u/%u", v, a);
    else if (m->attrs & LM_ATTR_NORMAL)
        fprintf(fp, " %u//%u", v, a);
    else
        fprintf(fp, " %u", v);
}

/* "o NAME" with the characters an OBJ line cannot hold replaced by '_'. */
static void write_object(FILE *fp, const char *name)
{
    fputs("o ", fp);
    for (const unsigned char *c = (const unsigned char *)name; *c; c++)
        fputc(*c < ' ' || *c == 127 ? '_' : *c, fp);
    fputc('\n', fp);
}

/* One group of triangles (one part, one material), with the "o" and "usemtl" lines it starts. */
static void write_group(FILE *fp, const lm_mesh *m, const lm_out_map *map, const lm_out_groups *g,
                        const lm_out_group *grp, int new_part)
{
    const char *part = grp->part < m->n_parts ? m->parts[grp->part].name : "";
    if (new_part && part[0])
        write_object(fp, part);
    if (m->n_materials) {
        char name[64];
        material_name(m, grp->material, name);
        fprintf(fp, "usemtl %s\n", name);
    }
    for (uint32_t i = grp->first; i < grp->first + grp->count; i++) {
        fputc('f', fp);
        for (int k = 0; k < 3; k++)
            write_corner(fp, m, map, m->tris[g->tris[i]].w[k]);
        fputc('\n', fp);
    }
}

/* Faces part by part: the unnamed part first (faces before any "o" line), then the named ones. */
static void write_faces(FILE *fp, const lm_mesh *m, const lm_out_map *map, const lm_out_groups *g)
{
    for (int named = 0; named < 2; named++)
        for (uint32_t i = 0; i < g->n_groups; i++) {
            const lm_out_group *grp = &g->groups[i];
            int has_name = grp->part < m->n_parts && m->parts[grp->part].name[0];
            if (has_name == named)
                write_group(fp, m, map, g, grp, i == 0 || g->groups[i - 1].part != grp->part);
        }
}

static lm_status names_init(const char *path, const lm_mesh *m, obj_names *nm)
{
    memset(nm, 0, sizeof *nm);
    size_t n = strlen(path);
    nm->stem = strndup(path, n >= 4 ? n - 4 : n); /* lm_mesh_save checked the ".obj" ending */
    nm->mtl_path = malloc(n + 8);
    nm->tex = calloc(2 * (size_t)m->n_materials + 1, sizeof *nm->tex);
    nm->n = 2 * m->n_materials;
    if (!nm->stem || !nm->mtl_path || !nm->tex)
        return lm_fail(LM_E_NOMEM, "out of memory writing %s", path);
    snprintf(nm->mtl_path, n + 8, "%s.mtl", nm->stem);
    return LM_OK;
}

lm_status lm_io_save_obj(const char *path, const lm_mesh *m)
{
    obj_names nm;
    lm_out_map map = {0};
    lm_out_groups groups = {0};
    lm_atomic_file f = {0};
    lm_status s = names_init(path, m, &nm);
    if (!s)
        s = lm_out_map_build(m, &map);
    if (!s)
        s = lm_out_groups_build(m, &groups);
    if (!s)
        s = lm_atomic_open(&f, path); /* first: an unwritable target fails before anything */
    if (!s && m->n_materials && !(s = write_textures(m, &nm)))
        s = write_mtl(m, &nm);
    if (!s) {
        fprintf(f.fp, "# lumesh: %u vertices, %u triangles\n", map.n_verts, map.n_tris);
        if (m->n_materials)
            fprintf(f.fp, "mtllib %s\n", base_name(nm.mtl_path));
        write_vertices(f.fp, m, &map);
        write_faces(f.fp, m, &map, &groups);
        s = lm_atomic_commit(&f);
    } else if (f.tmp_path) {
        lm_atomic_abort(&f);
    }
    names_free(&nm, s != LM_OK);
    lm_out_map_free(&map);
    lm_out_groups_free(&groups);
    return s;
}
