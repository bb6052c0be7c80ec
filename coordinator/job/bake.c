/* coordinator/job/bake.c — the result's normal-map bake from files to files (see bake.h). */
#include "coordinator/job/bake.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
#include "common/uv_atlas.h"
#include "coordinator/quality/json_text.h"

lm_status co_bake_parse_kind(const char *val)
{
    if (strcmp(val, "normal") == 0)
        return LM_OK;
    return lm_fail(LM_E_INVALID, "--bake expects normal (the one map baked so far), got '%s'", val);
}

/* OUT without its extension + "_normal.png". */
static lm_status map_path(const char *output, char *out, size_t cap)
{
    const char *dot = strrchr(output, '.'), *slash = strrchr(output, '/');
    size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - output) : strlen(output);
    int n = snprintf(out, cap, "%.*s_normal.png", (int)stem, output);
    if (n < 0 || (size_t)n >= cap)
        return lm_fail(LM_E_INVALID, "--bake: output name '%s' is too long", output);
    return LM_OK;
}

/* The mesh to bake onto: *res itself when its coordinates pass, else its atlas (*res becomes
 * the atlas and *from the mesh it was made of). */
static lm_status bake_target(lm_mesh **res, lm_mesh **from, int size, co_bake_result *r)
{
    *from = NULL;
    lm_status st = lm_bake_uv_check(*res, size, &r->stats);
    if (st == LM_OK)
        return LM_OK;
    lm_mesh *a;
    st = lm_atlas_per_triangle(*res, size, &a);
    if (st != LM_OK)
        return st;
    *from = *res;
    *res = a;
    r->atlas = 1;
    return LM_OK;
}

static lm_status attach(lm_mesh *res, const char *path, const lm_image *img)
{
    for (uint32_t i = 0; i < res->n_materials; i++) {
        lm_image *copy;
        lm_status st = lm_image_clone(img, &copy);
        if (st == LM_OK)
            st = lm_mesh_set_normal_map(res, i, path, copy);
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}

/* The atlas's materials take the resampled textures (ownership moves; NULL entries skipped). */
static void attach_colour(lm_mesh *res, lm_image **colour, co_bake_result *r)
{
    for (uint32_t i = 0; i < res->n_materials; i++) {
        if (!colour[i])
            continue;
        lm_image_destroy(res->materials[i].texture);
        res->materials[i].texture = colour[i];
        colour[i] = NULL;
        r->resampled++;
    }
}

static lm_status bake_meshes(const lm_mesh *orig, lm_mesh **res, const char *output, int size,
                             co_bake_result *r)
{
    /* A result without normals holds the derived ones (lm_mesh_compute_normals, as the renderers
     * derive them): the bake's frame, written with the map since TANGENT needs them. */
    (*res)->attrs |= LM_ATTR_NORMAL;
    lm_mesh *from = NULL;
    lm_status st = bake_target(res, &from, size, r);
    lm_image *img = NULL, **colour = NULL;
    lm_bake_colour transfer = {from, NULL};
    if (st == LM_OK && from) {
        colour = calloc((size_t)(*res)->n_materials + 1, sizeof *colour);
        transfer.out = colour;
        st = colour ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for a colour transfer");
    }
    if (st == LM_OK)
        st = lm_bake_normal(orig, *res, size, from ? &transfer : NULL, &img, &r->stats);
    if (st == LM_OK)
        st = lm_image_write(r->map_path, img);
    if (st == LM_OK)
        st = attach(*res, r->map_path, img);
    if (st == LM_OK && colour)
        attach_colour(*res, colour, r);
    for (uint32_t i = 0; colour && i < (*res)->n_materials; i++)
        lm_image_destroy(colour[i]);
    free(colour);
    lm_image_destroy(img);
    lm_mesh_destroy(from);
    if (st == LM_OK)
        st = lm_mesh_save(output, *res);
    return st;
}

lm_status co_bake_normal_file(const char *original, const char *output, int size, co_bake_result *r)
{
    memset(r, 0, sizeof *r);
    lm_status st = map_path(output, r->map_path, sizeof r->map_path);
    lm_mesh *orig = NULL, *res = NULL;
    if (st == LM_OK)
        st = lm_mesh_load(original, NULL, &orig);
    if (st == LM_OK)
        st = lm_mesh_load(output, NULL, &res);
    if (st == LM_OK)
        st = bake_meshes(orig, &res, output, size, r);
    lm_mesh_destroy(orig);
    lm_mesh_destroy(res);
    return st;
}

void co_bake_print(const co_bake_result *r, int json)
{
    const lm_bake_stats *s = &r->stats;
    if (!json) {
        printf("baked normal map: %s (%s; %llu texels, %llu met the original along the "
               "normal)\n",
               r->map_path,
               !r->atlas      ? "the result's own texture coordinates"
               : r->resampled ? "a per-triangle atlas, the colour textures resampled into it"
                              : "a per-triangle atlas",
               (unsigned long long)s->texels, (unsigned long long)s->hits);
        return;
    }
    fputs("{\"type\":\"bake\",\"map\":", stdout);
    co_json_string(stdout, r->map_path);
    printf(",\"atlas\":%s,\"resampled_textures\":%u,\"texels\":%llu,\"hits\":%llu}\n",
           r->atlas ? "true" : "false", r->resampled, (unsigned long long)s->texels,
           (unsigned long long)s->hits);
}
